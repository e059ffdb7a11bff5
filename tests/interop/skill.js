#!/usr/bin/env node
// node-opcua client using a skillcell skill as any OPC UA client would, knowing only the
// skill model (not skillcell's NodeIds):
//   1. finds the skills by browsing from Objects for objects whose type definition is a
//      subtype of SkillType (ns = index of http://skillcell.dev/UA/Skills/, i=1002), walking
//      the type hierarchy on the server (inverse HasSubtype), and picks the one named
//      by argv[3] (its browse name);
//   2. writes its MaxVelocity parameter (and checks that an out-of-range value is refused
//      with BadOutOfRange);
//   3. subscribes to the skill's events (FromState/Id, ToState/Id, Transition/Id, Message),
//      calls Start, and waits for ReadyToRunning and then RunningToReady;
//   4. reads CurrentState (Ready) and LastTransition (RunningToReady); checks that Resume in
//      Ready is refused with BadInvalidState.
// usage: node skill.js opc.tcp://HOST:PORT SKILL_NAME
// Prints "OK skill" and exits 0, or prints the failure on stderr and exits 1.
"use strict";

require("./log_to_stderr"); // before node-opcua: keep stdout clean
const { AttributeIds, DataType, constructEventFilter } = require("node-opcua-client");
const {
    StatusCodes, checkEndpointUrl, connect, disconnect, monitorItem, resolveNamespaceIndex, runMain,
    startSubscription, waitFor
} = require("./common");
const { childByName, findSkills } = require("./skill_model");

const SKILLS_URI = "http://skillcell.dev/UA/Skills/";
const url = process.argv[2];
const skillName = process.argv[3];
checkEndpointUrl(url, "usage: node skill.js opc.tcp://HOST:PORT SKILL_NAME");
if (!skillName) { process.stderr.write("usage: node skill.js URL SKILL_NAME\n"); process.exit(2); }

async function main() {
    let problem = null;
    const { client, session } = await connect(url, "skillcell-skill", (m) => { problem = m; });
    try {
        const { index: ns } = await resolveNamespaceIndex(session, SKILLS_URI);
        if (ns < 0) throw new Error(`namespace ${SKILLS_URI} missing`);
        const skills = await findSkills(session, `ns=${ns};i=1002`);
        const names = skills.map((s) => s.browseName.name);
        const skill = skills.find((s) => s.browseName.name === skillName);
        if (!skill) throw new Error(`skill ${skillName} not found among [${names}]`);
        const id = skill.nodeId;
        process.stderr.write(`found skills [${names}]; using ${id.toString()}\n`);

        const parameterSet = await childByName(session, id, "ParameterSet");
        const maxVelocity = await childByName(session, parameterSet, "MaxVelocity");
        const write = (v) => session.write({
            nodeId: maxVelocity, attributeId: AttributeIds.Value,
            value: { value: { dataType: DataType.Double, value: v } }
        });
        let status = await write(99);
        if (status !== StatusCodes.BadOutOfRange) {
            throw new Error(`MaxVelocity = 99: ${status.toString()}, expected BadOutOfRange`);
        }
        status = await write(0.5);
        if (status !== StatusCodes.Good) throw new Error(`MaxVelocity = 0.5: ${status.toString()}`);

        const subscription = await startSubscription(session, 20);
        const fields = ["FromState.Id", "ToState.Id", "Transition.Id", "Message", "EventType"];
        const events = await monitorItem(subscription, id, AttributeIds.EventNotifier,
            { queueSize: 100, filter: constructEventFilter(fields) });
        const received = [];
        events.on("changed", (values) => received.push(values.map((v) => v.value)));
        const transition = (name, number) => waitFor(events, "changed", () => {
            const hit = received.find((v) => v[2] && v[2].toString() === `ns=0;i=${number}`);
            return hit;
        }, 5000, `${name} event`);

        const ready = transition("RunningToReady", 2414);
        const start = await session.call({ objectId: id, methodId: await childByName(session, id, "Start") });
        if (start.statusCode !== StatusCodes.Good) throw new Error(`Start: ${start.statusCode.toString()}`);
        await ready;
        const started = received.find((v) => v[2] && v[2].toString() === "ns=0;i=2410");
        if (!started) throw new Error("no ReadyToRunning event before RunningToReady");
        if (started[0].toString() !== "ns=0;i=2400" || started[1].toString() !== "ns=0;i=2402") {
            throw new Error(`ReadyToRunning event From/To ${started[0]} ${started[1]}`);
        }
        if (received.indexOf(started) > received.findIndex((v) => v[2].toString() === "ns=0;i=2414")) {
            throw new Error("RunningToReady arrived before ReadyToRunning");
        }

        const current = await session.read({ nodeId: await childByName(session, id, "CurrentState"), attributeId: AttributeIds.Value });
        if (current.value.value.text !== "Ready") throw new Error(`CurrentState ${current.value.value.text}`);
        const last = await session.read({ nodeId: await childByName(session, id, "LastTransition"), attributeId: AttributeIds.Value });
        if (last.value.value.text !== "RunningToReady") throw new Error(`LastTransition ${last.value.value.text}`);
        const resume = await session.call({ objectId: id, methodId: await childByName(session, id, "Resume") });
        if (resume.statusCode !== StatusCodes.BadInvalidState) {
            throw new Error(`Resume in Ready: ${resume.statusCode.toString()}, expected BadInvalidState`);
        }
        await subscription.terminate();
        if (problem) throw new Error(problem);
        process.stdout.write("OK skill\n");
    } finally {
        await disconnect(client, session);
    }
}

runMain(main, 60);
