#!/usr/bin/env node
// node-opcua client handing the semantic MES a process, as any OPC UA client would, knowing
// only the skill models:
//   1. finds the skills whose type is ExecuteProcessSkillType (MesSkills namespace, i=1001)
//      through the server's type hierarchy;
//   2. subscribes to Objects/ProcessExecution/Progress (data changes) and to the skill's
//      transition events;
//   3. writes ProcessIri, calls Reset if the skill is Halted (the previous run's stop) and
//      Start, and waits for the run's end: RunningToReady, or
//      RunningToHalted with the MES's reason in the event's Message;
//   4. checks the end against the expectation and that the progress showed each expected
//      state.
// usage: node execute_process.js opc.tcp://HOST:PORT PROCESS_IRI ready|halted:TEXT STATE...
//   halted:TEXT: the run must end Halted with TEXT in its message; STATE...: words that must
//   each appear in some Progress value ("reading", "waiting", ...).
// Prints "OK execute_process" and exits 0, or prints the failure on stderr and exits 1.
"use strict";

require("./log_to_stderr"); // before node-opcua: keep stdout clean
const { AttributeIds, DataType, constructEventFilter } = require("node-opcua-client");
const {
    StatusCodes, checkEndpointUrl, connect, disconnect, monitorItem, resolveNamespaceIndex, runMain,
    startSubscription, waitFor
} = require("./common");
const { childByName, findSkills } = require("./skill_model");

const MES_URI = "http://skillcell.dev/UA/MesSkills/";
const USAGE = "usage: node execute_process.js URL PROCESS_IRI ready|halted:TEXT STATE...";
const [url, processIri, expected, ...states] = process.argv.slice(2);
checkEndpointUrl(url, USAGE);
if (!processIri || !expected || !(expected === "ready" || expected.startsWith("halted:"))) {
    process.stderr.write(`${USAGE}\n`);
    process.exit(2);
}
const RUNNING_TO_READY = "ns=0;i=2414";
const RUNNING_TO_HALTED = "ns=0;i=2412";

async function main() {
    let problem = null;
    const { client, session } = await connect(url, "skillcell-execute-process", (m) => { problem = m; });
    try {
        const { index: ns } = await resolveNamespaceIndex(session, MES_URI);
        if (ns < 0) throw new Error(`namespace ${MES_URI} missing`);
        const skills = await findSkills(session, `ns=${ns};i=1001`);
        if (skills.length !== 1) {
            throw new Error(`expected one ExecuteProcess skill, found [${skills.map((s) => s.browseName.name)}]`);
        }
        const id = skills[0].nodeId;
        const execution = await childByName(session, "ns=0;i=85", "ProcessExecution");
        const progressNode = await childByName(session, execution, "Progress");

        const subscription = await startSubscription(session, 20);
        const progress = [];
        const progressItem = await monitorItem(subscription, progressNode, AttributeIds.Value, { queueSize: 100 });
        progressItem.on("changed", (dv) => {
            if (dv.value && typeof dv.value.value === "string") progress.push(dv.value.value);
        });
        const fields = ["Transition.Id", "Message"];
        const events = await monitorItem(subscription, id, AttributeIds.EventNotifier,
            { queueSize: 100, filter: constructEventFilter(fields) });
        const received = [];
        events.on("changed", (values) => received.push(values.map((v) => v.value)));
        const end = waitFor(events, "changed", () => received.find((v) => v[0] &&
            [RUNNING_TO_READY, RUNNING_TO_HALTED].includes(v[0].toString())), 60000, "the run's end");

        const parameterSet = await childByName(session, id, "ParameterSet");
        const iriNode = await childByName(session, parameterSet, "ProcessIri");
        const written = await session.write({
            nodeId: iriNode, attributeId: AttributeIds.Value,
            value: { value: { dataType: DataType.String, value: processIri } }
        });
        if (written !== StatusCodes.Good) throw new Error(`ProcessIri: ${written.toString()}`);
        // A Halted skill is the previous run's stop: Reset it first, as an operator would.
        const current = await session.read({ nodeId: await childByName(session, id, "CurrentState"), attributeId: AttributeIds.Value });
        if (current.value.value.text === "Halted") {
            const reset = await session.call({ objectId: id, methodId: await childByName(session, id, "Reset") });
            if (reset.statusCode !== StatusCodes.Good) throw new Error(`Reset: ${reset.statusCode.toString()}`);
        }
        const start = await session.call({ objectId: id, methodId: await childByName(session, id, "Start") });
        if (start.statusCode !== StatusCodes.Good) throw new Error(`Start: ${start.statusCode.toString()}`);
        const [transition, message] = await end;
        const text = message && message.text !== undefined ? message.text : String(message);
        process.stderr.write(`end: ${transition.toString()} ${text}\n`);
        if (expected === "ready" && transition.toString() !== RUNNING_TO_READY) {
            throw new Error(`expected RunningToReady, got ${transition.toString()}: ${text}`);
        }
        if (expected.startsWith("halted:")) {
            const want = expected.slice("halted:".length);
            if (transition.toString() !== RUNNING_TO_HALTED) throw new Error(`expected RunningToHalted, got ${transition}`);
            if (!text.includes(want)) throw new Error(`the reason '${text}' lacks '${want}'`);
        }
        // The last progress may arrive after the event: wait for it briefly, bounded.
        const shows = (word) => progress.some((p) => p.includes(` ${word}`));
        for (const word of states) {
            if (!shows(word)) {
                await waitFor(progressItem, "changed", () => (shows(word) ? true : undefined), 5000,
                    `progress '${word}'`);
            }
        }
        process.stderr.write(`progress:\n  ${progress.join("\n  ")}\n`);
        await subscription.terminate();
        if (problem) throw new Error(problem);
        process.stdout.write("OK execute_process\n");
    } finally {
        await disconnect(client, session);
    }
}

runMain(main, 90);
