#!/usr/bin/env node
// node-opcua reference server for the skillcell interop tests.
//
// usage: node server.js [--port N] [--secure]   (N = 0 or omitted: pick a free port)
//
// --secure: Basic256Sha256, Aes128_Sha256_RsaOaep and Aes256_Sha256_RsaPss with Sign and
// SignAndEncrypt instead of None, no anonymous users; the user "operator" with the
// password "op-pw" (the interop tests of our client's security).
//
// Exposes, in namespace "urn:skillcell:demo", the object ns=<idx>;s=Demo
// (organized by Objects) with the Demo.* variables and the methods Demo.Add and
// Demo.FireEvent (raises a BaseEventType event from the Server object).
// Prints exactly one line "READY opc.tcp://127.0.0.1:PORT" on stdout once it
// is listening, and shuts down cleanly on SIGTERM / SIGINT.
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
    Variant,
    VariantArrayType,
    StatusCodes,
    nodesets
} = require("node-opcua");

const NAMESPACE_URI = "urn:skillcell:demo";
const { HOST, pickFreePort } = require("./discovery_common");

function parseArgs(argv) {
    const opts = { port: 0, secure: false };
    for (let i = 0; i < argv.length; i++) {
        const a = argv[i];
        if (a === "--secure") {
            opts.secure = true;
        } else if (a === "--port" && i + 1 < argv.length) {
            opts.port = Number(argv[++i]);
        } else if (a.startsWith("--port=")) {
            opts.port = Number(a.slice("--port=".length));
        } else if (a === "-h" || a === "--help") {
            process.stdout.write("usage: node server.js [--port N] [--secure]\n");
            process.exit(0);
        } else {
            process.stderr.write(`server.js: unknown argument '${a}'\n`);
            process.exit(2);
        }
    }
    if (!Number.isInteger(opts.port) || opts.port < 0 || opts.port > 65535) {
        process.stderr.write("server.js: --port needs an integer in 0..65535\n");
        process.exit(2);
    }
    return opts;
}

function populate(addressSpace) {
    const ns = addressSpace.registerNamespace(NAMESPACE_URI);

    const demo = ns.addObject({
        nodeId: "s=Demo",
        browseName: "Demo",
        organizedBy: addressSpace.rootFolder.objects
    });

    const rw = { accessLevel: "CurrentRead | CurrentWrite", userAccessLevel: "CurrentRead | CurrentWrite" };
    const ro = { accessLevel: "CurrentRead", userAccessLevel: "CurrentRead" };

    const scalar = (name, dataType, value, access) =>
        ns.addVariable({
            componentOf: demo,
            nodeId: `s=Demo.${name}`,
            browseName: name,
            dataType,
            valueRank: -1,
            minimumSamplingInterval: 0,
            ...access,
            value: new Variant({ dataType: DataType[dataType], value })
        });

    scalar("Double", "Double", 1.5, rw);
    scalar("Int32", "Int32", 42, rw);
    scalar("String", "String", "hello", rw);
    scalar("Boolean", "Boolean", true, rw);
    scalar("ReadOnly", "UInt32", 7, ro);

    ns.addVariable({
        componentOf: demo,
        nodeId: "s=Demo.DoubleArray",
        browseName: "DoubleArray",
        dataType: "Double",
        valueRank: 1,
        arrayDimensions: [0],
        minimumSamplingInterval: 0,
        ...rw,
        value: new Variant({
            dataType: DataType.Double,
            arrayType: VariantArrayType.Array,
            value: [1, 2, 3]
        })
    });

    const add = ns.addMethod(demo, {
        nodeId: "s=Demo.Add",
        browseName: "Add",
        inputArguments: [
            { name: "a", description: { text: "first addend" }, dataType: DataType.Double, valueRank: -1 },
            { name: "b", description: { text: "second addend" }, dataType: DataType.Double, valueRank: -1 }
        ],
        outputArguments: [{ name: "sum", description: { text: "a + b" }, dataType: DataType.Double, valueRank: -1 }]
    });
    // node-opcua validates argument count and types against the
    // InputArguments property before this callback is invoked
    // (BadArgumentsMissing / BadTooManyArguments / BadTypeMismatch).
    // Note: bindMethod dispatches on Function.length, so an async handler
    // must declare exactly two parameters (inputArguments, context).
    // eslint-disable-next-line no-unused-vars
    add.bindMethod(async (inputArguments, context) => {
        const a = inputArguments[0].value;
        const b = inputArguments[1].value;
        return {
            statusCode: StatusCodes.Good,
            outputArguments: [new Variant({ dataType: DataType.Double, value: a + b })]
        };
    });

    // Demo.FireEvent(message): raises a BaseEventType event from the Server object, so that
    // event subscriptions (skillcell_subscriptions_vs_node_server.cpp) have something to see.
    const fireEvent = ns.addMethod(demo, {
        nodeId: "s=Demo.FireEvent",
        browseName: "FireEvent",
        inputArguments: [
            { name: "message", description: { text: "the event's Message" }, dataType: DataType.String, valueRank: -1 }
        ],
        outputArguments: []
    });
    // eslint-disable-next-line no-unused-vars
    fireEvent.bindMethod(async (inputArguments, context) => {
        const text = inputArguments[0].value || "";
        addressSpace.rootFolder.objects.server.raiseEvent("BaseEventType", {
            message: { dataType: DataType.LocalizedText, value: { text } },
            severity: { dataType: DataType.UInt16, value: 500 },
            sourceName: { dataType: DataType.String, value: "Demo" }
        });
        return { statusCode: StatusCodes.Good, outputArguments: [] };
    });
}

function securityOptions(secure) {
    if (!secure) {
        return {
            securityPolicies: [SecurityPolicy.None],
            securityModes: [MessageSecurityMode.None],
            allowAnonymous: true
        };
    }
    return {
        securityPolicies: [
            SecurityPolicy.Basic256Sha256,
            SecurityPolicy.Aes128_Sha256_RsaOaep,
            SecurityPolicy.Aes256_Sha256_RsaPss
        ],
        securityModes: [MessageSecurityMode.Sign, MessageSecurityMode.SignAndEncrypt],
        allowAnonymous: false,
        userManager: {
            isValidUser: (userName, password) => userName === "operator" && password === "op-pw"
        }
    };
}

function createServer(port, pkiRoot, secure) {
    const serverCertificateManager = new OPCUACertificateManager({
        automaticallyAcceptUnknownCertificate: true,
        rootFolder: path.join(pkiRoot, "server")
    });
    const userCertificateManager = new OPCUACertificateManager({
        automaticallyAcceptUnknownCertificate: true,
        rootFolder: path.join(pkiRoot, "server-users")
    });
    return new OPCUAServer({
        port,
        host: HOST, // listen on loopback only
        hostname: HOST, // and advertise opc.tcp://127.0.0.1:PORT in the endpoints
        nodeset_filename: [nodesets.standard],
        ...securityOptions(secure),
        serverCertificateManager,
        userCertificateManager,
        buildInfo: { productName: "skillcell-interop-node-opcua", softwareVersion: "1.0" },
        serverInfo: { applicationUri: "urn:skillcell:interop:node-opcua-server", productUri: "urn:skillcell:interop" }
    });
}

async function main() {
    const opts = parseArgs(process.argv.slice(2));

    let server = null;
    let stopping = false;
    const shutdown = async (sig) => {
        if (stopping) return;
        stopping = true;
        const guard = setTimeout(() => process.exit(0), 5000);
        guard.unref();
        try {
            if (server) await server.shutdown(0);
        } catch (err) {
            process.stderr.write(`server.js: shutdown error on ${sig}: ${err && err.message}\n`);
        }
        process.exit(0);
    };
    process.on("SIGTERM", () => shutdown("SIGTERM"));
    process.on("SIGINT", () => shutdown("SIGINT"));

    // Keep the server's PKI (self-signed certificate, created on first run)
    // out of the repository; it is reused by later runs.
    const pkiRoot = process.env.SKILLCELL_INTEROP_PKI || path.join(os.tmpdir(), "skillcell-interop-pki");

    // With --port 0 the port picked here could be taken by someone else
    // before node-opcua binds it: pick another one and try again.
    const attempts = opts.port === 0 ? 5 : 1;
    let port = 0;
    for (let attempt = 1; ; attempt++) {
        port = opts.port === 0 ? await pickFreePort() : opts.port;
        const candidate = createServer(port, pkiRoot, opts.secure);
        try {
            await candidate.initialize();
            populate(candidate.engine.addressSpace);
            await candidate.start();
            server = candidate;
            break;
        } catch (err) {
            const inUse = err && (err.code === "EADDRINUSE" || /EADDRINUSE/.test(String(err.message)));
            try {
                await candidate.shutdown(0);
            } catch (_) {
                // it never fully started
            }
            if (!inUse || attempt >= attempts) throw err;
            process.stderr.write(`server.js: port ${port} taken, picking another one\n`);
        }
    }
    if (stopping) return;

    process.stdout.write(`READY opc.tcp://${HOST}:${port}\n`);
}

main().catch((err) => {
    process.stderr.write(`server.js: failed to start: ${err && err.stack ? err.stack : err}\n`);
    process.exit(1);
});
