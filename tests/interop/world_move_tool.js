#!/usr/bin/env node
// node-opcua client calling the world model's MoveTool (`skillcell device world`, Objects/World)
// with security on; node_world_move_tool.sh starts the world with the scene below and runs this
// script once per part, the user in SKILLCELL_NODE_USER (see common.js for SKILLCELL_NODE_*).
//
// usage: node world_move_tool.js URL --expect-untrusted | --as operator | --as engineer
//   --expect-untrusted  the connection must be refused (the server does not trust us yet);
//   --as operator       MoveTool is refused with BadUserAccessDenied and nothing moved;
//   --as engineer       MoveTool of a stored tool to a free dock is Good and the docks' Tool
//                       variables show it; bad input gets its exact Bad status and changes
//                       nothing; a new session afterwards still reads the moved state.
// Prints "OK ..." lines and exits 0, or one "FAIL ..." line per problem on stderr and exits 1.
"use strict";

require("./log_to_stderr"); // before node-opcua: keep stdout clean
const { AttributeIds, DataType, StatusCodes } = require("node-opcua-client");
const { checkEndpointUrl, connect, disconnect, resolveNamespaceIndex, stringNodeId } = require("./common");

const USAGE = "usage: node world_move_tool.js URL --expect-untrusted | --as operator|engineer";
const WORLD_NAMESPACE_URI = "http://skillcell.dev/UA/World/"; // kWorldNamespaceUri
// The scene the driver starts: tool -> dock it is stored in; DOCKS lists every dock.
const DOCKS = ["d1", "d2", "d3"];
const STORED = { d1: "parallel", d2: "suction", d3: "" };
const MOVED = { d1: "", d2: "suction", d3: "parallel" }; // after MoveTool(parallel, d3)

const url = process.argv[2];
checkEndpointUrl(url, USAGE);
const args = process.argv.slice(3);
const asIndex = args.indexOf("--as");
const role = asIndex >= 0 ? args[asIndex + 1] : undefined;
const expectUntrusted = args.includes("--expect-untrusted");
if (expectUntrusted === (role !== undefined) || (role && !["operator", "engineer"].includes(role))) {
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

// A dropped connection would make node-opcua replay requests silently: count it as a failure.
async function open() {
    const { client, session } = await connect(url, NAME, (msg) => fail(msg));
    const { index, namespaces } = await resolveNamespaceIndex(session, WORLD_NAMESPACE_URI);
    if (index < 0) throw new Error(`${WORLD_NAMESPACE_URI} not in the namespace array: ${namespaces.join(", ")}`);
    const node = (path) => stringNodeId(index, path);
    const moveTool = (inputArguments) =>
        session.call({ objectId: node("World"), methodId: node("World.MoveTool"), inputArguments });
    return { client, session, node, moveTool };
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

// One call whose statusCode (and, when given, inputArgumentResults) must be exactly these.
async function expectCall(w, what, inputArguments, status, argumentResults) {
    const r = await w.moveTool(inputArguments);
    const results = (r.inputArgumentResults || []).map((s) => s.name);
    if (r.statusCode !== status) {
        fail(`${what}: MoveTool returned ${r.statusCode.toString()}, want ${status.name}`);
    } else if (argumentResults && JSON.stringify(results) !== JSON.stringify(argumentResults.map((s) => s.name))) {
        fail(`${what}: inputArgumentResults [${results}], want [${argumentResults.map((s) => s.name)}]`);
    } else {
        ok(`${what}: ${r.statusCode.name}${argumentResults ? ` [${results}]` : ""}`);
    }
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
        await expectCall(w, "operator moves parallel to d3", [str("parallel"), str("d3")], StatusCodes.BadUserAccessDenied);
        await expectDocks(w, STORED, "operator, after the refusal");
    } finally {
        await disconnect(w.client, w.session);
    }
}

async function engineer() {
    let w = await open();
    try {
        await expectDocks(w, STORED, "engineer, before");
        await expectCall(w, "engineer moves parallel to d3", [str("parallel"), str("d3")], StatusCodes.Good);
        await expectDocks(w, MOVED, "engineer, after the move");

        // World::moveTool's refusals.
        await expectCall(w, "unknown tool", [str("no-such-tool"), str("d1")], StatusCodes.BadNotFound);
        await expectCall(w, "unknown dock", [str("suction"), str("no-such-dock")], StatusCodes.BadNotFound);
        await expectCall(w, "occupied dock", [str("parallel"), str("d2")], StatusCodes.BadInvalidState);
        // The Call service's argument checks (OPC 10000-4, 5.11.2.4, Tables 67 and 68): too few
        // or too many arguments fail the call as such; a wrongly typed one makes it
        // BadInvalidArgument with BadTypeMismatch in that argument's inputArgumentResults entry.
        await expectCall(w, "one argument", [str("suction")], StatusCodes.BadArgumentsMissing);
        await expectCall(w, "no arguments", [], StatusCodes.BadArgumentsMissing);
        await expectCall(w, "three arguments", [str("suction"), str("d1"), str("d3")], StatusCodes.BadTooManyArguments);
        await expectCall(w, "Int32 tool id", [{ dataType: DataType.Int32, value: 7 }, str("d1")],
            StatusCodes.BadInvalidArgument, [StatusCodes.BadTypeMismatch, StatusCodes.Good]);
        await expectCall(w, "String[] dock id", [str("suction"), { dataType: DataType.String, value: ["d1"] }],
            StatusCodes.BadInvalidArgument, [StatusCodes.Good, StatusCodes.BadTypeMismatch]);
        await expectDocks(w, MOVED, "engineer, after the refusals");
    } finally {
        await disconnect(w.client, w.session);
    }
    // A new session: the server still serves, and the move outlived the session that made it.
    w = await open();
    try {
        const state = await w.session.read({ nodeId: "ns=0;i=2259", attributeId: AttributeIds.Value });
        if (state.statusCode !== StatusCodes.Good || state.value.value !== 0) {
            fail(`ServerStatus.State: ${state.statusCode.toString()} ${state.value.value} (want Good, 0 = Running)`);
        } else {
            ok("server running in a new session");
        }
        await expectDocks(w, MOVED, "new session");
    } finally {
        await disconnect(w.client, w.session);
    }
}

const timer = setTimeout(() => {
    fail("timed out after 25 s");
    process.exit(1);
}, 25000);
(expectUntrusted ? untrusted() : role === "operator" ? operator() : engineer())
    .catch((err) => fail(`unexpected: ${err.stack || err}`))
    .finally(() => {
        clearTimeout(timer);
        process.exit(failures.length ? 1 : 0);
    });
