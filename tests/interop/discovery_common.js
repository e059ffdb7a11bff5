// Helpers shared by the discovery scripts (lds.js, register_server.js,
// find_servers_on_network.js, find_servers.js): argument parsing, the PKI folder,
// a guard against mDNS on a real network, and a bounded polling loop over a
// discovery service. node-opcua public API only.
"use strict";

require("./log_to_stderr"); // before node-opcua: keep stdout clean
const net = require("net");
const os = require("os");
const path = require("path");
// node-opcua is required where it is used: mdns_sniff.js must start fast without it

const HOST = "127.0.0.1";

function pkiRoot() {
    return process.env.SKILLCELL_INTEROP_PKI || path.join(os.tmpdir(), "skillcell-interop-pki");
}

// Tiny option parser. spec: { "--port": "int", "--absent": "flag", ... }.
// Returns { positional: [...], opts: { port: ..., absent: true, ... } } or exits 2.
function parseArgs(argv, spec, usage, nPositional) {
    const positional = [];
    const opts = {};
    const fail = (msg) => {
        process.stderr.write(`${msg}\n${usage}\n`);
        process.exit(2);
    };
    for (let i = 0; i < argv.length; i++) {
        let a = argv[i];
        let value;
        const eq = a.indexOf("=");
        if (a.startsWith("--") && eq > 0) {
            value = a.slice(eq + 1);
            a = a.slice(0, eq);
        }
        if (a === "-h" || a === "--help") {
            process.stdout.write(`${usage}\n`);
            process.exit(0);
        }
        if (!a.startsWith("--")) {
            positional.push(a);
            continue;
        }
        const kind = spec[a];
        if (!kind) fail(`unknown argument '${a}'`);
        const key = a.slice(2).replace(/-([a-z])/g, (_, c) => c.toUpperCase());
        if (kind === "flag") {
            if (value !== undefined) fail(`${a} takes no value`);
            opts[key] = true;
            continue;
        }
        if (value === undefined) {
            if (i + 1 >= argv.length) fail(`${a} needs a value`);
            value = argv[++i];
        }
        if (kind === "int" || kind === "number") {
            const n = Number(value);
            if (!Number.isFinite(n) || n < 0 || (kind === "int" && !Number.isInteger(n))) {
                fail(`${a} needs a non-negative ${kind === "int" ? "integer" : "number"}`);
            }
            opts[key] = n;
        } else {
            opts[key] = value;
        }
    }
    if (positional.length !== nPositional) fail(`expected ${nPositional} positional argument(s)`);
    return { positional, opts };
}

function checkEndpointUrl(url, usage) {
    if (typeof url !== "string" || !/^opc\.tcp:\/\/[^/:]+:\d+(\/.*)?$/.test(url)) {
        process.stderr.write(`not an opc.tcp URL: '${url}'\n${usage}\n`);
        process.exit(2);
    }
}

// mDNS must never reach a real network: refuse to run when an interface other
// than loopback exists (run inside tests/netns/run_in_private_netns.sh), unless
// SKILLCELL_INTEROP_ALLOW_NETWORK_MDNS=1.
function requirePrivateNetwork(scriptName) {
    if (process.env.SKILLCELL_INTEROP_ALLOW_NETWORK_MDNS === "1") return;
    const external = [];
    for (const [name, addrs] of Object.entries(os.networkInterfaces())) {
        if ((addrs || []).some((a) => !a.internal)) external.push(name);
    }
    if (external.length > 0) {
        process.stderr.write(
            `${scriptName}: refusing to send mDNS: non-loopback interface(s) ${external.join(", ")} present. ` +
                "Run inside tests/netns/run_in_private_netns.sh (or set SKILLCELL_INTEROP_ALLOW_NETWORK_MDNS=1).\n"
        );
        process.exit(2);
    }
}

// Bind a throw-away TCP server to port 0 on loopback, read the port the
// kernel chose, then release it.
function pickFreePort() {
    return new Promise((resolve, reject) => {
        const srv = net.createServer();
        srv.unref();
        srv.on("error", reject);
        srv.listen({ port: 0, host: HOST, exclusive: true }, () => {
            const { port } = srv.address();
            srv.close(() => resolve(port));
        });
    });
}

function isAddressInUse(err) {
    return !!err && (err.code === "EADDRINUSE" || /EADDRINUSE/.test(String(err.message)));
}

// A client without session (discovery services need none), SecurityPolicy None.
function createDiscoveryClient() {
    const { OPCUAClient, MessageSecurityMode, SecurityPolicy } = require("node-opcua-client");
    const { OPCUACertificateManager } = require("node-opcua-certificate-manager");
    return OPCUAClient.create({
        applicationName: "skillcell-interop-discovery-client",
        // the applicationUri of client.js & co: they share one client certificate
        applicationUri: "urn:skillcell:interop:node-opcua-client",
        securityMode: MessageSecurityMode.None,
        securityPolicy: SecurityPolicy.None,
        endpointMustExist: false,
        keepSessionAlive: false,
        clientCertificateManager: new OPCUACertificateManager({
            automaticallyAcceptUnknownCertificate: true,
            rootFolder: path.join(pkiRoot(), "client")
        }),
        connectionStrategy: { maxRetry: 1, initialDelay: 250, maxDelay: 500 },
        transportTimeout: 5000,
        requestedSessionTimeout: 60000
    });
}

const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));

function withTimeout(promise, ms, what) {
    let timer;
    return Promise.race([
        promise,
        new Promise((_, reject) => {
            timer = setTimeout(() => reject(new Error(`${what} timed out after ${ms} ms`)), ms);
        })
    ]).finally(() => clearTimeout(timer));
}

// Polls query(client) -> items every periodMs until (present ? some : none) item matches,
// or timeoutS passes. describe(item) turns an item into one line for the logs.
// Prints "OK ..." (exit 0) or "FAILED ..." (exit 1) on stdout.
async function pollUntil({ url, what, expected, absent, timeoutS, periodMs, query, matches, describe }) {
    const deadline = Date.now() + timeoutS * 1000;
    let client = null;
    let lastListing = null;
    let lastError = null;
    let polls = 0;
    const drop = async () => {
        if (!client) return;
        const c = client;
        client = null;
        try {
            await withTimeout(c.disconnect(), 3000, "disconnect");
        } catch (_) {
            // the connection is being abandoned anyway
        }
    };
    const finish = async (ok, line) => {
        await drop();
        process.stdout.write(`${ok ? "OK" : "FAILED"} ${line}\n`);
        process.exit(ok ? 0 : 1);
    };
    for (;;) {
        polls++;
        try {
            if (!client) {
                client = createDiscoveryClient();
                await withTimeout(client.connect(url), 8000, `connect to ${url}`);
            }
            const items = await withTimeout(query(client), 8000, what);
            lastError = null;
            const listing = items.map(describe).join("\n");
            if (listing !== lastListing) {
                process.stderr.write(`${what} on ${url}: ${items.length} entr${items.length === 1 ? "y" : "ies"}\n`);
                for (const item of items) process.stderr.write(`  ${describe(item)}\n`);
                lastListing = listing;
            }
            const hits = items.filter(matches);
            if (!absent && hits.length > 0) {
                return finish(true, `found '${expected}' after ${polls} poll(s): ${describe(hits[0])}`);
            }
            if (absent && hits.length === 0) {
                return finish(true, `'${expected}' absent after ${polls} poll(s)`);
            }
        } catch (err) {
            const msg = err && err.message ? err.message : String(err);
            if (msg !== lastError) process.stderr.write(`${what} on ${url} failed: ${msg}\n`);
            lastError = msg;
            await drop();
        }
        if (Date.now() + periodMs > deadline) {
            const why = lastError ? ` (last error: ${lastError})` : "";
            return finish(
                false,
                `'${expected}' still ${absent ? "present" : "absent"} after ${timeoutS} s and ${polls} poll(s)${why}`
            );
        }
        await sleep(periodMs);
    }
}

// The command line of find_servers.js / find_servers_on_network.js: LDS_URL
// EXPECTED_SUBSTRING [--absent] [--timeout S] [--period MS], then pollUntil() with the
// script's own query. `spec`: { usage, what, query(client, url), matches(item, expected),
// describe(item) }.
function runPollScript(spec) {
    const { positional, opts } = parseArgs(
        process.argv.slice(2),
        { "--absent": "flag", "--timeout": "number", "--period": "int" },
        spec.usage,
        2
    );
    const [url, expected] = positional;
    checkEndpointUrl(url, spec.usage);
    pollUntil({
        url,
        what: spec.what,
        expected,
        absent: !!opts.absent,
        timeoutS: opts.timeout !== undefined ? opts.timeout : 30,
        periodMs: opts.period || 500,
        query: (client) => spec.query(client, url),
        matches: (item) => spec.matches(item, expected),
        describe: spec.describe
    }).catch((err) => {
        process.stdout.write(`FAILED ${err && err.stack ? err.stack : err}\n`);
        process.exit(1);
    });
}

module.exports = {
    HOST,
    runPollScript,
    pkiRoot,
    parseArgs,
    checkEndpointUrl,
    requirePrivateNetwork,
    pickFreePort,
    isAddressInUse,
    createDiscoveryClient,
    sleep,
    withTimeout,
    pollUntil
};
