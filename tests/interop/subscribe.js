#!/usr/bin/env node
// node-opcua client checking skillcell's subscriptions.
//
// usage: node subscribe.js opc.tcp://HOST:PORT
//
//   (a) data change: monitors ns=<demo>;s=Demo.Double, waits for the initial value, writes
//       a new one and expects its notification within 2 s;
//   (b) events: monitors the Server object (i=2253, EventNotifier) selecting EventId,
//       EventType, SourceName, Time, Message, Severity, calls Demo.FireEvent(message) and
//       expects that event (Severity 500, the message) within 2 s.
// Prints "OK subscriptions" and exits 0, or prints the failure on stderr and exits 1.
"use strict";

require("./log_to_stderr"); // before node-opcua: keep stdout clean
const {
    AttributeIds,
    ClientMonitoredItem,
    DataType,
    TimestampsToReturn,
    constructEventFilter
} = require("node-opcua-client");
const {
    DEMO_NAMESPACE_URI,
    StatusCodes,
    checkEndpointUrl,
    connect,
    disconnect,
    resolveNamespaceIndex,
    runMain,
    startSubscription,
    stringNodeId,
    waitFor
} = require("./common");

const url = process.argv[2];
checkEndpointUrl(url, "usage: node subscribe.js opc.tcp://HOST:PORT");

async function main() {
    let problem = null;
    const { client, session } = await connect(url, "skillcell-subscribe", (m) => { problem = m; });
    try {
        const { index: ns } = await resolveNamespaceIndex(session, DEMO_NAMESPACE_URI);
        if (ns < 0) throw new Error(`namespace ${DEMO_NAMESPACE_URI} missing`);
        const subscription = await startSubscription(session, 50);

        // (a) data change after a write
        const doubleId = stringNodeId(ns, "Demo.Double");
        const item = ClientMonitoredItem.create(
            subscription, { nodeId: doubleId, attributeId: AttributeIds.Value },
            { samplingInterval: 0, queueSize: 10, discardOldest: true }, TimestampsToReturn.Both);
        await waitFor(item, "changed", (dv) => dv, 2000, "initial value of Demo.Double");
        const target = 1000 + Math.round(Math.random() * 1000) / 8;
        const written = waitFor(item, "changed",
            (dv) => (dv.value && dv.value.value === target ? dv : undefined), 2000,
            `notification of Demo.Double = ${target}`);
        const status = await session.write({
            nodeId: doubleId, attributeId: AttributeIds.Value,
            value: { value: { dataType: DataType.Double, value: target } }
        });
        if (status !== StatusCodes.Good) throw new Error(`write: ${status.toString()}`);
        await written;

        // (b) an event fired by a method call reaches the Server object
        const fields = ["EventId", "EventType", "SourceName", "Time", "Message", "Severity"];
        const events = ClientMonitoredItem.create(
            subscription, { nodeId: "ns=0;i=2253", attributeId: AttributeIds.EventNotifier },
            { samplingInterval: 0, queueSize: 100, discardOldest: true,
              filter: constructEventFilter(fields) }, TimestampsToReturn.Both);
        await new Promise((resolve, reject) => {
            events.once("initialized", resolve);
            events.once("err", (e) => reject(new Error(`event item: ${e}`)));
        });
        const text = `interop ${Date.now()}`;
        const fired = waitFor(events, "changed", (values) => {
            const message = values[4] && values[4].value;
            return message && message.text === text ? values : undefined;
        }, 2000, `event '${text}'`);
        const call = await session.call({
            objectId: stringNodeId(ns, "Demo"),
            methodId: stringNodeId(ns, "Demo.FireEvent"),
            inputArguments: [{ dataType: DataType.String, value: text }]
        });
        if (call.statusCode !== StatusCodes.Good) {
            throw new Error(`Demo.FireEvent: ${call.statusCode.toString()}`);
        }
        const values = await fired;
        if (values[5].value !== 500) throw new Error(`Severity ${values[5].value}, expected 500`);
        if (!values[0].value || values[0].value.length === 0) throw new Error("empty EventId");
        if (values[2].value !== "Demo") throw new Error(`SourceName '${values[2].value}'`);

        await subscription.terminate();
        if (problem) throw new Error(problem);
        process.stdout.write("OK subscriptions\n");
    } finally {
        await disconnect(client, session);
    }
}

runMain(main, 60);
