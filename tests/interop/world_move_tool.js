#!/usr/bin/env node
// node-opcua client calling the world model's methods (`skillcell device world`, Objects/World)
// with security on: MoveTool, AddRobot and the per-robot ones (SetFlangePose, DockAtFlange,
// MountTool, UnmountTool, ObjectAtGripPoint, Grasp, Release: the robot's id first).
// node_world_move_tool.sh starts the world with the scene below and runs this script once per
// part, the user in SKILLCELL_NODE_USER (see common.js for SKILLCELL_NODE_*).
//
// usage: node world_move_tool.js URL --expect-untrusted | --as operator|engineer|restored
//   --expect-untrusted  the connection must be refused (the server does not trust us yet);
//   --as operator       MoveTool and AddRobot (Engineer methods) are refused with
//                       BadUserAccessDenied and nothing changed; SetFlangePose (an Operator
//                       method) passes the role check and names an unknown robot: BadNotFound;
//   --as engineer       MoveTool of a stored tool to a free dock is Good and the docks' Tool
//                       variables show it; AddRobot adds robot2, whose World/Robots/robot2
//                       nodes node-opcua browses and reads; bad input (to both: another
//                       structure than a 3DFrame is BadInvalidArgument with BadTypeMismatch
//                       on that argument), an empty robot id (BadInvalidArgument) and calls
//                       naming an unknown robot get their exact Bad status and change nothing;
//                       SetFlangePose, DockAtFlange, MountTool, ObjectAtGripPoint, Grasp and
//                       Release for robot2 act on robot2 alone (robot, the default robot, stays
//                       as it was); a new session afterwards still reads the changed state;
//   --as restored       (an operator, on the world killed after the engineer's part and
//                       started again from its state file) robot2 reads as the engineer left
//                       it, but ObjectAtGripPoint, DockAtFlange and a Grasp at its flange are
//                       BadWaitingForInitialData until SetFlangePose reports where the flange
//                       is; then they answer and the Grasp is Good.
// Prints "OK ..." lines and exits 0, or one "FAIL ..." line per problem on stderr and exits 1.
"use strict";

require("./log_to_stderr"); // before node-opcua: keep stdout clean
const { AttributeIds, BrowseDirection, DataType, StatusCodes, makeBrowsePath } = require("node-opcua-client");
// The structures node-opcua-client encodes with (its own dependency, the version the lock file
// pins); it does not re-export them.
const { Range, ThreeDFrame, ThreeDVector } = require("node-opcua-types");
const { checkEndpointUrl, connect, disconnect, resolveNamespaceIndex, stringNodeId } = require("./common");

const USAGE = "usage: node world_move_tool.js URL --expect-untrusted | --as operator|engineer|restored";
const WORLD_NAMESPACE_URI = "http://skillcell.dev/UA/World/"; // kWorldNamespaceUri
// The scene the driver starts: tool -> dock it is stored in; DOCKS lists every dock.
const DOCKS = ["d1", "d2", "d3"];
const STORED = { d1: "parallel", d2: "suction", d3: "" };
const MOVED = { d1: "", d2: "suction", d3: "parallel" }; // after MoveTool(parallel, d3)
// Its robots: `robot` (the default one, base and flange at the origin) and, once AddRobot made
// it, robot2. Poses are [x, y, z, a, b, c] (m, rad), as 3DFrame's six Doubles.
const ORIGIN = [0, 0, 0, 0, 0, 0];
const BASE2 = [1, 0.5, 0, 0, 0, Math.PI / 2]; // robot2's base; its flange starts there
const AT_D2 = [0.5, -0.3, 0.1, 0, 0, 0]; // dock d2's pose (--dock d2@...)
// The box (--object box:0.04,0.04,0.04@0.2,0.2,0.42) is at the grip point of a flange here
// that carries suction.
const ABOVE_BOX = [0.2, 0.2, 0.3, 0, 0, 0];
const BOX_EDGES = [0.04, 0.04, 0.04];
const UNKNOWN = "nosuchrobot";

const url = process.argv[2];
checkEndpointUrl(url, USAGE);
const args = process.argv.slice(3);
const asIndex = args.indexOf("--as");
const role = asIndex >= 0 ? args[asIndex + 1] : undefined;
const expectUntrusted = args.includes("--expect-untrusted");
if (expectUntrusted === (role !== undefined) || (role && !["operator", "engineer", "restored"].includes(role))) {
    process.stderr.write(`${USAGE}\n`);
    process.exit(2);
}

const failures = [];
function fail(message) {
    failures.push(message);
    process.stderr.write(`FAIL ${message}\n`);
}
function ok(message) {
    process.stdout.write(`OK ${message}\n`);
}
const NAME = "skillcell world interop"; // also the CN of node's self-signed certificate
const str = (value) => ({ dataType: DataType.String, value });
// A 3DFrame argument: node-opcua encodes it as an ExtensionObject (Default Binary, six Doubles).
const frame = ([x, y, z, a, b, c]) => ({
    dataType: DataType.ExtensionObject,
    value: new ThreeDFrame({ cartesianCoordinates: { x, y, z }, orientation: { a, b, c } })
});
// Structures that are no 3DFrame, for a 3DFrame argument.
const VECTOR = { dataType: DataType.ExtensionObject, value: new ThreeDVector({ x: 1, y: 2, z: 3 }) };
const RANGE = { dataType: DataType.ExtensionObject, value: new Range({ low: 0, high: 1 }) };
// Numbers rounded to 1 nm / 1 nrad (the server turns a 3DFrame into a rotation matrix and
// back), -0 as 0, so that values compare as JSON.
const round = (v) => Number(v.toFixed(9)) + 0;
const poseOf = (f) => [f.cartesianCoordinates.x, f.cartesianCoordinates.y, f.cartesianCoordinates.z,
    f.orientation.a, f.orientation.b, f.orientation.c].map(round);

// A dropped connection would make node-opcua replay requests silently: count it as a failure.
async function open() {
    const { client, session } = await connect(url, NAME, (msg) => fail(msg));
    const { index, namespaces } = await resolveNamespaceIndex(session, WORLD_NAMESPACE_URI);
    if (index < 0) throw new Error(`${WORLD_NAMESPACE_URI} not in the namespace array: ${namespaces.join(", ")}`);
    const node = (path) => stringNodeId(index, path);
    const call = (method, inputArguments) =>
        session.call({ objectId: node("World"), methodId: node(`World.${method}`), inputArguments });
    return { client, session, index, node, call };
}

// Each dock's Tool variable (World/Docks/<id>/Tool) as node-opcua reads it. Our server sends an
// empty dock's "" as a null String (length -1), which node-opcua decodes as null: both are
// "no tool" here.
async function docks(w) {
    const values = await w.session.read(
        DOCKS.map((d) => ({ nodeId: w.node(`World/Docks/${d}/Tool`), attributeId: AttributeIds.Value }))
    );
    const out = {};
    values.forEach((dv, i) => {
        if (dv.statusCode !== StatusCodes.Good) throw new Error(`reading ${DOCKS[i]}/Tool: ${dv.statusCode.toString()}`);
        out[DOCKS[i]] = dv.value.value ?? "";
    });
    return out;
}

async function expectDocks(w, want, when) {
    const got = await docks(w);
    if (JSON.stringify(got) !== JSON.stringify(want)) {
        fail(`${when}: docks hold ${JSON.stringify(got)}, want ${JSON.stringify(want)}`);
    } else {
        ok(`${when}: docks hold ${JSON.stringify(got)}`);
    }
}

// One call of World.<method> whose statusCode (and, when given, inputArgumentResults) must be
// exactly these. Returns the output arguments' values when the call was Good.
async function expectCall(w, what, method, inputArguments, status, argumentResults) {
    const r = await w.call(method, inputArguments);
    const results = (r.inputArgumentResults || []).map((s) => s.name);
    if (r.statusCode !== status) {
        fail(`${what}: ${method} returned ${r.statusCode.toString()}, want ${status.name}`);
    } else if (argumentResults && JSON.stringify(results) !== JSON.stringify(argumentResults.map((s) => s.name))) {
        fail(`${what}: inputArgumentResults [${results}], want [${argumentResults.map((s) => s.name)}]`);
    } else {
        ok(`${what}: ${method} ${r.statusCode.name}${argumentResults ? ` [${results}]` : ""}`);
    }
    return r.statusCode === StatusCodes.Good ? (r.outputArguments || []).map((v) => v.value) : undefined;
}

// A call that must be Good and answer exactly `want` (its output arguments' values: Doubles
// and Double arrays rounded as above, a null String as "").
async function expectAnswer(w, what, method, inputArguments, want) {
    const out = await expectCall(w, what, method, inputArguments, StatusCodes.Good);
    if (out === undefined) return;
    const got = out.map((v) => (v === null ? "" : typeof v === "number" ? round(v)
        : v instanceof Float64Array ? Array.from(v, round) : v));
    if (JSON.stringify(got) !== JSON.stringify(want)) {
        fail(`${what}: ${method} answered ${JSON.stringify(got)}, want ${JSON.stringify(want)}`);
    } else {
        ok(`${what}: ${method} answered ${JSON.stringify(got)}`);
    }
}

// The robots node-opcua finds by browsing World/Robots (their browse names, sorted).
async function robots(w) {
    const r = await w.session.browse({
        nodeId: w.node("World/Robots"), browseDirection: BrowseDirection.Forward,
        referenceTypeId: "HierarchicalReferences", includeSubtypes: true, nodeClassMask: 0, resultMask: 63
    });
    if (r.statusCode !== StatusCodes.Good) throw new Error(`browsing World/Robots: ${r.statusCode.toString()}`);
    if (r.continuationPoint && r.continuationPoint.length) throw new Error("browsing World/Robots: a continuation point");
    return r.references.map((ref) => ref.browseName.name).sort();
}

// What World/Robots/<id> holds, as node-opcua reads it: every variable, poses as rounded
// [x, y, z, a, b, c], an empty String (sent as null) as "".
const ROBOT_VARIABLES = ["Base", "FlangePose", "GripPoint", "MountedTool", "GraspedObject", "ContactForce"];
async function robot(w, id) {
    const values = await w.session.read(ROBOT_VARIABLES.map((v) =>
        ({ nodeId: w.node(`World/Robots/${id}/${v}`), attributeId: AttributeIds.Value })));
    const out = {};
    values.forEach((dv, i) => {
        if (dv.statusCode !== StatusCodes.Good) {
            throw new Error(`reading World/Robots/${id}/${ROBOT_VARIABLES[i]}: ${dv.statusCode.toString()}`);
        }
        const v = dv.value.value;
        out[ROBOT_VARIABLES[i]] = v instanceof ThreeDFrame ? poseOf(v) : typeof v === "number" ? round(v) : v ?? "";
    });
    return out;
}

// How often a gripper took hold of the object (World/Objects/<id>/Grasps, a UInt32).
async function grasps(w, id) {
    const dv = await w.session.read({ nodeId: w.node(`World/Objects/${id}/Grasps`), attributeId: AttributeIds.Value });
    if (dv.statusCode !== StatusCodes.Good) {
        throw new Error(`reading World/Objects/${id}/Grasps: ${dv.statusCode.toString()}`);
    }
    if (dv.value.dataType !== DataType.UInt32) {
        throw new Error(`World/Objects/${id}/Grasps is a ${DataType[dv.value.dataType]}, not a UInt32`);
    }
    return dv.value.value;
}

// Everything a refused call must leave as it was: the docks, the robot list, each robot.
async function scene(w) {
    const out = { docks: await docks(w), robots: {} };
    for (const id of await robots(w)) out.robots[id] = await robot(w, id);
    return out;
}

function expectSame(got, want, when) {
    if (JSON.stringify(got) !== JSON.stringify(want)) {
        fail(`${when}: ${JSON.stringify(got)}, want ${JSON.stringify(want)}`);
    } else {
        ok(`${when}: ${JSON.stringify(got)}`);
    }
}

// A robot's variables as they must read: `want` holds those the check is about.
async function expectRobot(w, id, want, when) {
    const got = await robot(w, id);
    const picked = Object.fromEntries(Object.keys(want).map((k) => [k, got[k]]));
    expectSame(picked, want, `${when}: ${id}`);
}

async function untrusted() {
    let w;
    try {
        w = await open();
        fail("connected although the server does not trust our certificate");
    } catch (err) {
        ok(`untrusted client refused: ${err.message.split("\n")[0]}`);
    } finally {
        if (w) await disconnect(w.client, w.session);
    }
}

async function operator() {
    const w = await open();
    try {
        await expectDocks(w, STORED, "operator, before");
        await expectCall(w, "operator moves parallel to d3", "MoveTool", [str("parallel"), str("d3")],
            StatusCodes.BadUserAccessDenied);
        await expectDocks(w, STORED, "operator, after the refusal");

        const before = await scene(w);
        expectSame(Object.keys(before.robots), ["robot"], "operator, the robots before");
        await expectCall(w, "operator adds robot2", "AddRobot", [str("robot2"), frame(BASE2)],
            StatusCodes.BadUserAccessDenied);
        // SetFlangePose is an Operator's (a device reports its flange): the role check passes,
        // the world does not know the robot.
        await expectCall(w, `operator moves ${UNKNOWN}'s flange`, "SetFlangePose", [str(UNKNOWN), frame(AT_D2)],
            StatusCodes.BadNotFound);
        expectSame(await scene(w), before, "operator, the scene after the refusals");
    } finally {
        await disconnect(w.client, w.session);
    }
}

// MoveTool: the move, then its refusals; the docks show the move and nothing else.
async function engineerMovesTool(w) {
    await expectDocks(w, STORED, "engineer, before");
    await expectCall(w, "engineer moves parallel to d3", "MoveTool", [str("parallel"), str("d3")], StatusCodes.Good);
    await expectDocks(w, MOVED, "engineer, after the move");

    // World::moveTool's refusals.
    await expectCall(w, "unknown tool", "MoveTool", [str("no-such-tool"), str("d1")], StatusCodes.BadNotFound);
    await expectCall(w, "unknown dock", "MoveTool", [str("suction"), str("no-such-dock")], StatusCodes.BadNotFound);
    await expectCall(w, "occupied dock", "MoveTool", [str("parallel"), str("d2")], StatusCodes.BadInvalidState);
    // The Call service's argument checks (OPC 10000-4, 5.11.2.4, Tables 67 and 68): too few
    // or too many arguments fail the call as such; a wrongly typed one makes it
    // BadInvalidArgument with BadTypeMismatch in that argument's inputArgumentResults entry.
    await expectCall(w, "one argument", "MoveTool", [str("suction")], StatusCodes.BadArgumentsMissing);
    await expectCall(w, "no arguments", "MoveTool", [], StatusCodes.BadArgumentsMissing);
    await expectCall(w, "three arguments", "MoveTool", [str("suction"), str("d1"), str("d3")],
        StatusCodes.BadTooManyArguments);
    await expectCall(w, "Int32 tool id", "MoveTool", [{ dataType: DataType.Int32, value: 7 }, str("d1")],
        StatusCodes.BadInvalidArgument, [StatusCodes.BadTypeMismatch, StatusCodes.Good]);
    await expectCall(w, "String[] dock id", "MoveTool", [str("suction"), { dataType: DataType.String, value: ["d1"] }],
        StatusCodes.BadInvalidArgument, [StatusCodes.Good, StatusCodes.BadTypeMismatch]);
    await expectDocks(w, MOVED, "engineer, after the refusals");
}

// AddRobot: robot2 appears under World/Robots with the base it was given; a taken id and bad
// input are refused with their exact status and add nothing.
async function engineerAddsRobot(w) {
    expectSame(await robots(w), ["robot"], "engineer, the robots before AddRobot");
    await expectCall(w, "engineer adds robot2", "AddRobot", [str("robot2"), frame(BASE2)], StatusCodes.Good);
    expectSame(await robots(w), ["robot", "robot2"], "the robots node-opcua browses after AddRobot");
    // By browse names, as a client that knows only the model would find it.
    const ns = w.index;
    const path = `/${ns}:World/${ns}:Robots/${ns}:robot2/${ns}:Base`;
    const found = await w.session.translateBrowsePath(makeBrowsePath("ObjectsFolder", path));
    if (found.statusCode !== StatusCodes.Good || !found.targets || found.targets.length !== 1) {
        fail(`${path}: ${found.statusCode.toString()}, ${found.targets ? found.targets.length : 0} targets`);
    } else {
        const dv = await w.session.read({ nodeId: found.targets[0].targetId, attributeId: AttributeIds.Value });
        const got = dv.value.value instanceof ThreeDFrame ? poseOf(dv.value.value) : dv.value.value;
        expectSame({ status: dv.statusCode.name, base: got }, { status: "Good", base: BASE2.map(round) },
            `${path} (${found.targets[0].targetId.toString()})`);
    }
    // A new robot: its flange at its base, no tool, nothing held, no force.
    expectSame(await robot(w, "robot2"), {
        Base: BASE2.map(round), FlangePose: BASE2.map(round), GripPoint: BASE2.map(round),
        MountedTool: "", GraspedObject: "", ContactForce: 0
    }, "robot2 as AddRobot made it");

    const before = await scene(w);
    // World::addRobot's refusals: an id taken (by a robot or anything else in the world, a dock
    // here) is BadNodeIdExists, an empty one BadInvalidArgument.
    await expectCall(w, "robot2 again", "AddRobot", [str("robot2"), frame(AT_D2)], StatusCodes.BadNodeIdExists);
    await expectCall(w, "the default robot again", "AddRobot", [str("robot"), frame(ORIGIN)], StatusCodes.BadNodeIdExists);
    await expectCall(w, "a dock's id", "AddRobot", [str("d1"), frame(ORIGIN)], StatusCodes.BadNodeIdExists);
    await expectCall(w, "empty robot id", "AddRobot", [str(""), frame(ORIGIN)], StatusCodes.BadInvalidArgument);
    // The Call service's argument checks, as for MoveTool.
    await expectCall(w, "AddRobot with one argument", "AddRobot", [str("robot3")], StatusCodes.BadArgumentsMissing);
    await expectCall(w, "AddRobot with no arguments", "AddRobot", [], StatusCodes.BadArgumentsMissing);
    await expectCall(w, "AddRobot with three arguments", "AddRobot", [str("robot3"), frame(ORIGIN), str("x")],
        StatusCodes.BadTooManyArguments);
    await expectCall(w, "Int32 robot id", "AddRobot", [{ dataType: DataType.Int32, value: 3 }, frame(ORIGIN)],
        StatusCodes.BadInvalidArgument, [StatusCodes.BadTypeMismatch, StatusCodes.Good]);
    await expectCall(w, "String base", "AddRobot", [str("robot3"), str("0,0,0")],
        StatusCodes.BadInvalidArgument, [StatusCodes.Good, StatusCodes.BadTypeMismatch]);
    await expectCall(w, "Double[6] base", "AddRobot", [str("robot3"), { dataType: DataType.Double, value: ORIGIN }],
        StatusCodes.BadInvalidArgument, [StatusCodes.Good, StatusCodes.BadTypeMismatch]);
    // Another structure where a 3DFrame is due is wrongly typed, too: the Call service checks
    // that its encoding is 3DFrame's (or a subtype's) and answers as for any wrong type. A NaN
    // in a 3DFrame is the method's to refuse: BadOutOfRange as the call's status.
    await expectCall(w, "a 3DVector as base", "AddRobot", [str("robot3"), VECTOR],
        StatusCodes.BadInvalidArgument, [StatusCodes.Good, StatusCodes.BadTypeMismatch]);
    await expectCall(w, "a Range as base", "AddRobot", [str("robot3"), RANGE],
        StatusCodes.BadInvalidArgument, [StatusCodes.Good, StatusCodes.BadTypeMismatch]);
    await expectCall(w, "a NaN in the base", "AddRobot", [str("robot3"), frame([NaN, 0, 0, 0, 0, 0])],
        StatusCodes.BadOutOfRange);
    expectSame(await scene(w), before, "the scene after AddRobot's refusals");
}

// Every per-robot method naming a robot the world lacks: BadNotFound, whatever else the call
// names (the dock, the box exist; the calls would be refused otherwise for other reasons); an
// empty robot id BadInvalidArgument.
async function engineerNamesUnknownRobot(w) {
    const before = await scene(w);
    const u = str(UNKNOWN);
    await expectCall(w, `${UNKNOWN}'s flange moved`, "SetFlangePose", [u, frame(AT_D2)], StatusCodes.BadNotFound);
    await expectCall(w, `${UNKNOWN} mounts d2's tool`, "MountTool", [u, str("d2")], StatusCodes.BadNotFound);
    await expectCall(w, `${UNKNOWN} unmounts into d1`, "UnmountTool", [u, str("d1")], StatusCodes.BadNotFound);
    await expectCall(w, `${UNKNOWN} grasps box`, "Grasp", [u, str("box")], StatusCodes.BadNotFound);
    await expectCall(w, `${UNKNOWN} releases`, "Release", [u], StatusCodes.BadNotFound);
    await expectCall(w, `the dock at ${UNKNOWN}'s flange`, "DockAtFlange", [u], StatusCodes.BadNotFound);
    await expectCall(w, `the object at ${UNKNOWN}'s grip point`, "ObjectAtGripPoint", [u], StatusCodes.BadNotFound);
    // An empty robot id is a bad argument, as AddRobot answers it, not a robot not found.
    await expectCall(w, "an empty robot id", "SetFlangePose", [str(""), frame(AT_D2)], StatusCodes.BadInvalidArgument);
    await expectCall(w, "an empty robot id", "Release", [str("")], StatusCodes.BadInvalidArgument);
    await expectCall(w, "an empty robot id", "DockAtFlange", [str("")], StatusCodes.BadInvalidArgument);
    // A known robot, another structure than a 3DFrame for its pose: the Call service's.
    await expectCall(w, "a 3DVector as robot2's flange pose", "SetFlangePose", [str("robot2"), VECTOR],
        StatusCodes.BadInvalidArgument, [StatusCodes.Good, StatusCodes.BadTypeMismatch]);
    // The robot is the first argument of each: a wrongly typed one is the Call service's.
    await expectCall(w, "Int32 robot id", "Grasp", [{ dataType: DataType.Int32, value: 2 }, str("box")],
        StatusCodes.BadInvalidArgument, [StatusCodes.BadTypeMismatch, StatusCodes.Good]);
    await expectCall(w, "Release without its robot", "Release", [], StatusCodes.BadArgumentsMissing);
    expectSame(await scene(w), before, "the scene after the calls for an unknown robot");
}

// robot2 moves to dock d2, takes its tool, moves above the box, grasps and releases it: each
// step shows on robot2's variables and the docks, and robot (the default) stays at the origin
// with nothing mounted or held.
async function engineerWorksRobot2(w) {
    const origin = { FlangePose: ORIGIN, MountedTool: "", GraspedObject: "" };
    await expectAnswer(w, "robot2's flange to dock d2", "SetFlangePose", [str("robot2"), frame(AT_D2)], [0]);
    await expectRobot(w, "robot2", { Base: BASE2.map(round), FlangePose: AT_D2 }, "after SetFlangePose");
    await expectRobot(w, "robot", origin, "after robot2's SetFlangePose");
    await expectAnswer(w, "the dock at robot2's flange", "DockAtFlange", [str("robot2")], ["d2"]);
    await expectAnswer(w, "the dock at robot's flange", "DockAtFlange", [str("robot")], [""]);
    // robot's flange is not at d3: its own pose is what MountTool checks.
    await expectCall(w, "robot mounts d3's tool", "MountTool", [str("robot"), str("d3")], StatusCodes.BadInvalidState);
    await expectCall(w, "robot2 mounts d2's tool", "MountTool", [str("robot2"), str("d2")], StatusCodes.Good);
    await expectDocks(w, { d1: "", d2: "", d3: "parallel" }, "after robot2's MountTool");
    await expectRobot(w, "robot2", { MountedTool: "suction", GripPoint: [0.5, -0.3, 0.22, 0, 0, 0] },
        "after MountTool");
    await expectRobot(w, "robot", origin, "after robot2's MountTool");

    await expectAnswer(w, "robot2's flange above the box", "SetFlangePose", [str("robot2"), frame(ABOVE_BOX)], [0]);
    await expectAnswer(w, "the object at robot2's grip point", "ObjectAtGripPoint", [str("robot2")], ["box", BOX_EDGES]);
    await expectAnswer(w, "the object at robot's grip point", "ObjectAtGripPoint", [str("robot")], ["", [0, 0, 0]]);
    const graspsBefore = await grasps(w, "box");
    await expectCall(w, "robot grasps box", "Grasp", [str("robot"), str("box")], StatusCodes.BadInvalidState);
    expectSame(await grasps(w, "box"), graspsBefore, "box's Grasps after a refused Grasp");
    await expectCall(w, "robot2 grasps box", "Grasp", [str("robot2"), str("box")], StatusCodes.Good);
    expectSame(await grasps(w, "box"), graspsBefore + 1, "box's Grasps after robot2's Grasp");
    await expectRobot(w, "robot2", { FlangePose: ABOVE_BOX, GraspedObject: "box" }, "after Grasp");
    await expectRobot(w, "robot", origin, "after robot2's Grasp");
    await expectCall(w, "robot releases", "Release", [str("robot")], StatusCodes.BadInvalidState);
    await expectCall(w, "robot2 releases", "Release", [str("robot2")], StatusCodes.Good);
    await expectRobot(w, "robot2", { GraspedObject: "" }, "after Release");
}

// What the engineer's part leaves, for the new session to read.
const FINAL_DOCKS = { d1: "", d2: "", d3: "parallel" };
const FINAL_ROBOT2 = {
    Base: BASE2.map(round), FlangePose: ABOVE_BOX, GripPoint: [0.2, 0.2, 0.42, 0, 0, 0],
    MountedTool: "suction", GraspedObject: "", ContactForce: 0
};

async function engineer() {
    let w = await open();
    try {
        await engineerMovesTool(w);
        await engineerAddsRobot(w);
        await engineerNamesUnknownRobot(w);
        await engineerWorksRobot2(w);
    } finally {
        await disconnect(w.client, w.session);
    }
    // A new session: the server still serves, and the changes outlived the session that made them.
    w = await open();
    try {
        const state = await w.session.read({ nodeId: "ns=0;i=2259", attributeId: AttributeIds.Value });
        if (state.statusCode !== StatusCodes.Good || state.value.value !== 0) {
            fail(`ServerStatus.State: ${state.statusCode.toString()} ${state.value.value} (want Good, 0 = Running)`);
        } else {
            ok("server running in a new session");
        }
        await expectDocks(w, FINAL_DOCKS, "new session");
        expectSame(await robots(w), ["robot", "robot2"], "new session: the robots");
        expectSame(await robot(w, "robot2"), FINAL_ROBOT2, "new session: robot2");
        await expectRobot(w, "robot", { FlangePose: ORIGIN, MountedTool: "", GraspedObject: "" }, "new session");
    } finally {
        await disconnect(w.client, w.session);
    }
}

// A world restarted from its state file knows where robot2's flange was, not where it is: it
// acts there only once the robot has said so again.
async function restored() {
    const w = await open();
    try {
        expectSame(await robot(w, "robot2"), FINAL_ROBOT2, "restored: robot2");
        const graspsBefore = await grasps(w, "box");
        // What is at its flange is not known either.
        await expectCall(w, "the object at robot2's grip point before its flange is heard",
            "ObjectAtGripPoint", [str("robot2")], StatusCodes.BadWaitingForInitialData);
        await expectCall(w, "the dock at robot2's flange before it is heard", "DockAtFlange",
            [str("robot2")], StatusCodes.BadWaitingForInitialData);
        await expectCall(w, "robot2 grasps box before its flange is heard", "Grasp",
            [str("robot2"), str("box")], StatusCodes.BadWaitingForInitialData);
        expectSame(await grasps(w, "box"), graspsBefore, "box's Grasps after the refused Grasp");
        await expectAnswer(w, "robot2's flange reported again", "SetFlangePose",
            [str("robot2"), frame(ABOVE_BOX)], [0]);
        await expectAnswer(w, "the object at robot2's grip point", "ObjectAtGripPoint", [str("robot2")],
            ["box", BOX_EDGES]);
        await expectCall(w, "robot2 grasps box", "Grasp", [str("robot2"), str("box")], StatusCodes.Good);
        expectSame(await grasps(w, "box"), graspsBefore + 1, "box's Grasps after the Grasp");
        await expectRobot(w, "robot2", { GraspedObject: "box" }, "restored: after Grasp");
    } finally {
        await disconnect(w.client, w.session);
    }
}

const timer = setTimeout(() => {
    fail("timed out after 25 s");
    process.exit(1);
}, 25000);
(expectUntrusted ? untrusted() : role === "operator" ? operator() : role === "restored" ? restored() : engineer())
    .catch((err) => fail(`unexpected: ${err.stack || err}`))
    .finally(() => {
        clearTimeout(timer);
        process.exit(failures.length ? 1 : 0);
    });
