#!/usr/bin/env node
// A node-opcua server that offers skills of our companion models, for `skillcell check`
// (node_skill_server_vs_check.sh): an independent implementation of the skill model that
// the conformance checker must accept, and a broken one that it must reject.
//
// usage: node skill_server.js MODELS_DIR [--port N]     (N = 0 or omitted: a free port)
//
// Loads namespace 0 and models/Skillcell.*.NodeSet2.xml, then creates, in namespace
// "urn:skillcell:interop:skills":
//   Objects/Good/Move    a CartesianLinearMoveSkillType as the skill model wants it: the
//                        methods Start..Reset (node-opcua does not instantiate
//                        OptionalPlaceholders: added here), the EURanges, an event notifier,
//                        and a state machine behind the methods (interlocking with
//                        BadInvalidState, CurrentState/LastTransition, a
//                        SkillTransitionEventType event per transition with Transition,
//                        FromState, ToState and their Ids); a run ends in Ready after
//                        300 ms of Running (Suspend pauses it).
//   Objects/Bad/Broken   the same type without the Suspend method and with CurrentState
//                        "Idle".
// Prints "READY opc.tcp://127.0.0.1:PORT GOOD_FOLDER_ID BAD_FOLDER_ID" on stdout once it
// listens, and shuts down on SIGTERM / SIGINT.
"use strict";

require("./log_to_stderr"); // before node-opcua: keep stdout clean
const os = require("os");
const path = require("path");
const {
    OPCUAServer,
    OPCUACertificateManager,
    SecurityPolicy,
    MessageSecurityMode,
    DataType,
    VariantArrayType,
    Range,
    StatusCodes,
    QualifiedName,
    resolveNodeId,
    nodesets
} = require("node-opcua");
const { HOST, pickFreePort } = require("./discovery_common");

const NAMESPACE_URI = "urn:skillcell:interop:skills";
// The OPC Foundation's models as we ship them, then ours layered on DI.
const FOUNDATION = ["Opc.Ua.Di", "Opc.Ua.IA", "Opc.Ua.Robotics"];
const MODELS = ["Skills", "RoboticSkills", "GripperSkills", "ToolChangerSkills",
                "CompositeSkills", "MesSkills"];
const uri = (key) => `http://skillcell.dev/UA/${key}/`;

// The program state machine of OPC 10000-10 with namespace 0's NodeIds, as
// src/skills/skill_state_machine.hpp has it (an independent spelling, on purpose).
const STATES = { Halted: [11, 2406], Ready: [12, 2400], Running: [13, 2402], Suspended: [14, 2404] };
const TRANSITIONS = {
    HaltedToReady: [1, 2408, "Halted", "Ready"],
    ReadyToRunning: [2, 2410, "Ready", "Running"],
    RunningToHalted: [3, 2412, "Running", "Halted"],
    RunningToReady: [4, 2414, "Running", "Ready"],
    RunningToSuspended: [5, 2416, "Running", "Suspended"],
    SuspendedToRunning: [6, 2418, "Suspended", "Running"],
    SuspendedToHalted: [7, 2420, "Suspended", "Halted"],
    SuspendedToReady: [8, 2422, "Suspended", "Ready"],
    ReadyToHalted: [9, 2424, "Ready", "Halted"]
};
const METHODS = {
    Start: { Ready: "ReadyToRunning" },
    Suspend: { Running: "RunningToSuspended" },
    Resume: { Suspended: "SuspendedToRunning" },
    Halt: { Ready: "ReadyToHalted", Running: "RunningToHalted", Suspended: "SuspendedToHalted" },
    Reset: { Halted: "HaltedToReady" }
};

function parseArgs(argv) {
    const opts = { port: 0, models: null };
    for (let i = 0; i < argv.length; i++) {
        const a = argv[i];
        if (a === "--port" && i + 1 < argv.length) {
            opts.port = Number(argv[++i]);
        } else if (a === "-h" || a === "--help") {
            process.stdout.write("usage: node skill_server.js MODELS_DIR [--port N]\n");
            process.exit(0);
        } else if (!a.startsWith("--") && opts.models === null) {
            opts.models = a;
        } else {
            process.stderr.write(`skill_server.js: unknown argument '${a}'\n`);
            process.exit(2);
        }
    }
    if (opts.models === null || !Number.isInteger(opts.port) || opts.port < 0 || opts.port > 65535) {
        process.stderr.write("usage: node skill_server.js MODELS_DIR [--port N]\n");
        process.exit(2);
    }
    return opts;
}

const text = (t) => ({ dataType: DataType.LocalizedText, value: { text: t } });
const nodeId = (id) => ({ dataType: DataType.NodeId, value: resolveNodeId(`i=${id}`) });

function setState(skill, state) {
    skill.getComponentByName("CurrentState").setValueFromSource(text(state));
    const current = skill.getComponentByName("CurrentState");
    current.getPropertyByName("Id").setValueFromSource(nodeId(STATES[state][1]));
    current.getPropertyByName("Number").setValueFromSource({ dataType: DataType.UInt32, value: STATES[state][0] });
}

function addSkill(addressSpace, ns, folder, name, { methods, eventNotifier }) {
    const type = addressSpace.findObjectType("CartesianLinearMoveSkillType",
                                             addressSpace.getNamespaceIndex(uri("RoboticSkills")));
    const skill = type.instantiate({
        browseName: name,
        organizedBy: folder,
        optionals: ["ParameterSet.MaxVelocity.EURange", "ParameterSet.MaxAcceleration.EURange"]
    });
    for (const m of methods) {
        ns.addMethod(skill, {
            browseName: new QualifiedName({ namespaceIndex: 0, name: m }),
            inputArguments: [],
            outputArguments: []
        });
    }
    // node-opcua gives a Range[] parameter without a value a *scalar* Range by default,
    // which the checker rightly reports (ValueRank 1): a device sets its joint bounds.
    const bounds = [];
    for (let joint = 0; joint < 6; joint++) bounds.push(new Range({ low: -Math.PI, high: Math.PI }));
    skill.getComponentByName("ParameterSet").getComponentByName("AxisBounds").setValueFromSource({
        dataType: DataType.ExtensionObject,
        arrayType: VariantArrayType.Array,
        value: bounds
    });
    if (eventNotifier) skill.setEventNotifier(1);
    setState(skill, "Ready");
    return skill;
}

// The state machine behind the methods of a conforming skill. A run takes RUN_MS, long
// enough for the checker to Suspend and Resume it; Suspend keeps the time that remains.
const RUN_MS = 300;
function runStateMachine(addressSpace, skill) {
    const eventType = addressSpace.findEventType("SkillTransitionEventType",
                                                 addressSpace.getNamespaceIndex(uri("Skills")));
    let state = "Ready";
    let timer = null;
    let remaining = 0;
    let armedAt = 0;
    const enter = (transition) => {
        const [number, id, from, to] = TRANSITIONS[transition];
        state = to;
        setState(skill, to);
        const last = skill.getComponentByName("LastTransition");
        last.setValueFromSource(text(transition));
        last.getPropertyByName("Id").setValueFromSource(nodeId(id));
        last.getPropertyByName("Number").setValueFromSource({ dataType: DataType.UInt32, value: number });
        last.getPropertyByName("TransitionTime").setValueFromSource({ dataType: DataType.DateTime, value: new Date() });
        skill.raiseEvent(eventType, {
            message: text(transition),
            transition: text(transition),
            "transition.id": nodeId(id),
            fromState: text(from),
            "fromState.id": nodeId(STATES[from][1]),
            toState: text(to),
            "toState.id": nodeId(STATES[to][1])
        });
    };
    const arm = (ms) => {
        armedAt = Date.now();
        remaining = ms;
        timer = setTimeout(() => {
            timer = null;
            if (state === "Running") enter("RunningToReady");
        }, ms);
    };
    const disarm = () => {
        if (timer) clearTimeout(timer);
        timer = null;
        remaining = Math.max(0, remaining - (Date.now() - armedAt));
    };
    for (const name of Object.keys(METHODS)) {
        const method = skill.getMethodByName(name);
        // bindMethod dispatches on Function.length: two parameters for an async handler.
        // eslint-disable-next-line no-unused-vars
        method.bindMethod(async (inputArguments, context) => {
            const transition = METHODS[name][state];
            if (!transition) return { statusCode: StatusCodes.BadInvalidState };
            enter(transition);
            if (transition === "ReadyToRunning") arm(RUN_MS);
            if (transition === "RunningToSuspended" || TRANSITIONS[transition][3] === "Halted") disarm();
            if (transition === "SuspendedToRunning") arm(remaining);
            return { statusCode: StatusCodes.Good, outputArguments: [] };
        });
    }
}

function populate(addressSpace) {
    const ns = addressSpace.registerNamespace(NAMESPACE_URI);
    const objects = addressSpace.rootFolder.objects;
    const good = ns.addFolder(objects, { nodeId: "s=Good", browseName: "Good" });
    const bad = ns.addFolder(objects, { nodeId: "s=Bad", browseName: "Bad" });
    const move = addSkill(addressSpace, ns, good, "Move",
                          { methods: Object.keys(METHODS), eventNotifier: true });
    runStateMachine(addressSpace, move);
    const broken = addSkill(addressSpace, ns, bad, "Broken",
                            { methods: ["Start", "Resume", "Halt", "Reset"], eventNotifier: true });
    broken.getComponentByName("CurrentState").setValueFromSource(text("Idle"));
    return [good.nodeId.toString(), bad.nodeId.toString()];
}

function createServer(port, pkiRoot, models) {
    return new OPCUAServer({
        port,
        host: HOST,
        hostname: HOST,
        nodeset_filename: [nodesets.standard,
                           ...FOUNDATION.map((f) => path.join(models, "opcfoundation",
                                                              `${f}.NodeSet2.xml`)),
                           ...MODELS.map((k) => path.join(models, `Skillcell.${k}.NodeSet2.xml`))],
        securityPolicies: [SecurityPolicy.None],
        securityModes: [MessageSecurityMode.None],
        allowAnonymous: true,
        serverCertificateManager: new OPCUACertificateManager({
            automaticallyAcceptUnknownCertificate: true,
            rootFolder: path.join(pkiRoot, "skill-server")
        }),
        userCertificateManager: new OPCUACertificateManager({
            automaticallyAcceptUnknownCertificate: true,
            rootFolder: path.join(pkiRoot, "skill-server-users")
        }),
        buildInfo: { productName: "skillcell-interop-node-opcua-skills", softwareVersion: "1.0" },
        serverInfo: { applicationUri: "urn:skillcell:interop:node-opcua-skill-server",
                      productUri: "urn:skillcell:interop" }
    });
}

async function main() {
    const opts = parseArgs(process.argv.slice(2));
    let server = null;
    let stopping = false;
    const shutdown = async () => {
        if (stopping) return;
        stopping = true;
        setTimeout(() => process.exit(0), 5000).unref();
        try {
            if (server) await server.shutdown(0);
        } catch (err) {
            process.stderr.write(`skill_server.js: shutdown: ${err && err.message}\n`);
        }
        process.exit(0);
    };
    process.on("SIGTERM", shutdown);
    process.on("SIGINT", shutdown);

    const pkiRoot = process.env.SKILLCELL_INTEROP_PKI || path.join(os.tmpdir(), "skillcell-interop-pki");
    // A port picked here may be taken before node-opcua binds it: try again.
    const attempts = opts.port === 0 ? 5 : 1;
    for (let attempt = 1; ; attempt++) {
        const port = opts.port === 0 ? await pickFreePort() : opts.port;
        const candidate = createServer(port, pkiRoot, opts.models);
        try {
            await candidate.initialize();
            const [good, bad] = populate(candidate.engine.addressSpace);
            await candidate.start();
            server = candidate;
            process.stdout.write(`READY opc.tcp://${HOST}:${port} ${good} ${bad}\n`);
            return;
        } catch (err) {
            try { await candidate.shutdown(0); } catch (_) { /* ignore */ }
            if (attempt >= attempts) throw err;
        }
    }
}

main().catch((err) => {
    process.stderr.write(`skill_server.js: ${err && err.stack ? err.stack : err}\n`);
    process.exit(1);
});
