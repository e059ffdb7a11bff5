#!/usr/bin/env node
// Round-trip latency benchmark for the skillcell interop tests.
//
// usage: node bench_client.js opc.tcp://HOST:PORT N
//
// Connects (SecurityPolicy None, anonymous), warms up with 200 Reads and 200
// Calls, then times N sequential Reads of ns=<urn:skillcell:demo>;s=Demo.Double
// (Value) and N sequential Calls of Demo.Add(2, 3.5), each one with
// process.hrtime.bigint(). Prints ONE line of JSON on stdout:
//   {"read":{"median_us":..,"p99_us":..,"n":N,...},"call":{...}}
// Exits 1 (message on stderr) when a request fails or after 120 s.
"use strict";

require("./log_to_stderr"); // before node-opcua: keep stdout clean
const { AttributeIds, DataType } = require("node-opcua-client");
const {
    DEMO_NAMESPACE_URI,
    checkEndpointUrl,
    connect,
    disconnect,
    resolveNamespaceIndex,
    stringNodeId,
    percentile
} = require("./common");

const USAGE = "usage: node bench_client.js opc.tcp://HOST:PORT N";
const WARMUP = 200;
const OVERALL_TIMEOUT_MS = 120000;

function summarize(samplesNs) {
    const us = samplesNs.map((ns) => Number(ns) / 1000).sort((a, b) => a - b);
    const round = (x) => Math.round(x * 10) / 10;
    const mean = us.reduce((s, x) => s + x, 0) / us.length;
    return {
        median_us: round(percentile(us, 50)),
        p99_us: round(percentile(us, 99)),
        n: us.length,
        mean_us: round(mean),
        min_us: round(us[0]),
        max_us: round(us[us.length - 1])
    };
}

async function main() {
    const [url, nArg, ...rest] = process.argv.slice(2);
    checkEndpointUrl(url, USAGE);
    const n = Number(nArg);
    if (!Number.isInteger(n) || n <= 0 || rest.length > 0) {
        process.stderr.write(`${USAGE}\n`);
        return 2;
    }

    let problem = null;
    const { client, session } = await connect(url, "skillcell-interop-bench", (msg) => {
        problem = problem || msg;
    });
    const { index: ns, namespaces } = await resolveNamespaceIndex(session, DEMO_NAMESPACE_URI);
    if (ns < 0) {
        throw new Error(`namespace ${DEMO_NAMESPACE_URI} not in NamespaceArray [${namespaces.join(", ")}]`);
    }

    const readRequest = { nodeId: stringNodeId(ns, "Demo.Double"), attributeId: AttributeIds.Value };
    const callRequest = {
        objectId: stringNodeId(ns, "Demo"),
        methodId: stringNodeId(ns, "Demo.Add"),
        inputArguments: [
            { dataType: DataType.Double, value: 2 },
            { dataType: DataType.Double, value: 3.5 }
        ]
    };

    const doRead = async () => {
        const dv = await session.read(readRequest);
        if (dv.statusCode.isNotGood()) throw new Error(`Read Demo.Double: ${dv.statusCode.toString()}`);
    };
    const doCall = async () => {
        const r = await session.call(callRequest);
        if (r.statusCode.isNotGood()) throw new Error(`Call Demo.Add: ${r.statusCode.toString()}`);
        const out = r.outputArguments && r.outputArguments[0];
        if (!out || out.value !== 5.5) throw new Error(`Call Demo.Add(2, 3.5) returned ${out ? out.value : "nothing"}`);
    };

    for (let i = 0; i < WARMUP; i++) await doRead();
    for (let i = 0; i < WARMUP; i++) await doCall();

    const time = async (fn) => {
        const samples = new Array(n);
        for (let i = 0; i < n; i++) {
            const t = process.hrtime.bigint();
            await fn();
            samples[i] = process.hrtime.bigint() - t;
        }
        return samples;
    };
    const reads = await time(doRead);
    const calls = await time(doCall);

    await disconnect(client, session);
    if (problem) throw new Error(problem);
    process.stdout.write(JSON.stringify({ read: summarize(reads), call: summarize(calls) }) + "\n");
    return 0;
}

const watchdog = setTimeout(() => {
    process.stderr.write(`bench_client.js: overall timeout of ${OVERALL_TIMEOUT_MS / 1000} s exceeded\n`);
    process.exit(1);
}, OVERALL_TIMEOUT_MS);

main().then(
    (code) => {
        clearTimeout(watchdog);
        process.exit(code);
    },
    (err) => {
        process.stderr.write(`bench_client.js: ${err && err.stack ? err.stack : err}\n`);
        process.exit(1);
    }
);
