#!/usr/bin/env node
// node-opcua server that registers itself with a Local Discovery Server, for the skillcell
// discovery interop tests (registerServerMethod LDS, so it sends no mDNS itself).
//
// usage: node register_server.js LDS_URL [--port N] [--application-uri URI] [--caps A,B]
//
//   --port N               0 or omitted: pick a free port
//   --application-uri URI  default urn:skillcell:interop:node-registered-server; node-opcua also
//                          uses it as the mdnsServerName of its RegisterServer2 request
//   --caps A,B             serverCapabilities announced for mDNS (node-opcua's default: NA)
//
// node-opcua's RegisterServerManager connects to LDS_URL, calls GetEndpoints, picks the most
// secure endpoint (it needs the endpoint's serverCertificate to be set, even for
// SecurityPolicy None), then sends RegisterServer2 (falling back to RegisterServer when that
// fails). Its "serverRegistered" event fires even when both were refused, so this script
// watches the responses itself: it prints "READY opc.tcp://127.0.0.1:PORT" on stdout only
// once a RegisterServer(2) with isOnline=true was answered without a fault, and
// "FAILED ..." (exit 1) when it was refused, or at once when none of the LDS's endpoints
// carries a serverCertificate (node-opcua would then never send RegisterServer(2)). Every
// registration request and its outcome is logged to stderr
// ("register: RegisterServer2Request isOnline=true -> Good").
// SIGTERM/SIGINT: shutdown, which unregisters (isOnline=false), then exit 0.
"use strict";

require("./log_to_stderr"); // before node-opcua: keep stdout clean
const path = require("path");
const {
    OPCUAServer,
    OPCUACertificateManager,
    SecurityPolicy,
    MessageSecurityMode,
    RegisterServerMethod,
    nodesets
} = require("node-opcua");
const { OPCUAClientBase } = require("node-opcua-client");
const {
    HOST,
    pkiRoot,
    parseArgs,
    checkEndpointUrl,
    pickFreePort,
    isAddressInUse
} = require("./discovery_common");

const USAGE =
    "usage: node register_server.js LDS_URL [--port N] [--application-uri URI] [--caps A,B]";
const log = (msg) => process.stderr.write(`register_server.js: ${msg}\n`);

// Outcomes of the registration requests sent by node-opcua's RegisterServerManager, observed
// by wrapping the clients it creates (OPCUAClientBase.create is looked up at each call).
const outcomes = []; // { online, request, ok, status }
let lastEndpointListing = null;
// set by main(): called when none of the LDS's endpoints carries a serverCertificate
const hooks = { noCertificate: () => {} };
function instrumentRegistrationClients() {
    const create = OPCUAClientBase.create;
    OPCUAClientBase.create = (options) => {
        const client = create(options);
        const channel = `${MessageSecurityMode[options.securityMode || MessageSecurityMode.None]} ${options.securityPolicy || SecurityPolicy.None}`;
        const perform = client.performMessageTransaction.bind(client);
        client.performMessageTransaction = (request, callback) => {
            const name = request && request.schema ? request.schema.name : "?";
            perform(request, (err, response) => {
                if (/^RegisterServer2?Request$/.test(name)) {
                    const online = !!(request.server && request.server.isOnline);
                    const status = err ? err.message.trim() : response.responseHeader.serviceResult.toString();
                    let extra = "";
                    if (!err && response.configurationResults) {
                        extra = ` configurationResults=[${response.configurationResults.map((s) => s.toString()).join(", ")}]`;
                    }
                    if (name === "RegisterServer2Request") {
                        const conf = (request.discoveryConfiguration || [])
                            .map((c) => `mdnsServerName=${c.mdnsServerName} caps=${(c.serverCapabilities || []).join(",")}`)
                            .join("; ");
                        extra += ` (${conf})`;
                    }
                    log(`register: ${name} over ${channel} isOnline=${online} urls=${(request.server.discoveryUrls || []).join(",")} -> ${status}${extra}`);
                    outcomes.push({ online, request: name, ok: !err, status });
                } else if (name === "GetEndpointsRequest" && !err) {
                    const endpoints = response.endpoints || [];
                    const listing = endpoints
                        .map(
                            (e) =>
                                `LDS endpoint ${e.endpointUrl} ${MessageSecurityMode[e.securityMode]} ${e.securityPolicyUri} ` +
                                `serverCertificate=${e.serverCertificate && e.serverCertificate.length ? `${e.serverCertificate.length} bytes` : "EMPTY"}`
                        )
                        .join("\n");
                    if (listing !== lastEndpointListing) {
                        lastEndpointListing = listing;
                        for (const line of listing.split("\n")) log(line);
                    }
                    const withoutCertificate = endpoints.filter((e) => !(e.serverCertificate && e.serverCertificate.length));
                    if (endpoints.length > 0 && withoutCertificate.length === endpoints.length) {
                        hooks.noCertificate();
                    }
                }
                callback(err, response);
            });
        };
        return client;
    };
}

function createServer(port, ldsUrl, opts) {
    const applicationUri = opts.applicationUri || "urn:skillcell:interop:node-registered-server";
    // one PKI folder per applicationUri: node-opcua puts the applicationUri in the
    // certificate it creates, and an LDS may compare the two
    const folder = `registered-server-${applicationUri.replace(/[^A-Za-z0-9._-]/g, "_")}`;
    const serverCertificateManager = new OPCUACertificateManager({
        automaticallyAcceptUnknownCertificate: true,
        rootFolder: path.join(pkiRoot(), folder)
    });
    const userCertificateManager = new OPCUACertificateManager({
        automaticallyAcceptUnknownCertificate: true,
        rootFolder: path.join(pkiRoot(), `${folder}-users`)
    });
    const options = {
        port,
        host: HOST,
        hostname: HOST,
        nodeset_filename: [nodesets.standard],
        securityPolicies: [SecurityPolicy.None],
        securityModes: [MessageSecurityMode.None],
        allowAnonymous: true,
        serverCertificateManager,
        userCertificateManager,
        registerServerMethod: RegisterServerMethod.LDS,
        discoveryServerEndpointUrl: ldsUrl,
        buildInfo: { productName: "skillcell-interop-node-registered-server", softwareVersion: "1.0" },
        serverInfo: {
            applicationUri,
            productUri: "urn:skillcell:interop",
            applicationName: { text: "skillcell-interop-node-registered-server", locale: "en" }
        }
    };
    if (opts.caps !== undefined) {
        options.capabilitiesForMDNS = opts.caps.split(",").filter((c) => c.length > 0);
    }
    return new OPCUAServer(options);
}

async function main() {
    const { positional, opts } = parseArgs(
        process.argv.slice(2),
        { "--port": "int", "--application-uri": "string", "--caps": "string" },
        USAGE,
        1
    );
    const ldsUrl = positional[0];
    checkEndpointUrl(ldsUrl, USAGE);
    if ((opts.port || 0) > 65535) {
        process.stderr.write(`register_server.js: --port needs 0..65535\n${USAGE}\n`);
        process.exit(2);
    }
    instrumentRegistrationClients();

    let server = null;
    let stopping = false;
    const shutdown = async (why, code) => {
        if (stopping) return;
        stopping = true;
        const guard = setTimeout(() => process.exit(code), 15000);
        guard.unref();
        try {
            // unregisters from the LDS (RegisterServer2 isOnline=false) before closing
            if (server) await server.shutdown(0);
        } catch (err) {
            log(`shutdown error on ${why}: ${err && err.message}`);
        }
        const offline = outcomes.filter((o) => !o.online);
        log(offline.length ? `unregistration: ${offline.map((o) => `${o.request} -> ${o.status}`).join(", ")}` : "no unregistration was sent");
        process.exit(code);
    };
    process.on("SIGTERM", () => shutdown("SIGTERM", 0));
    hooks.noCertificate = () => {
        if (stopping) return;
        process.stdout.write(
            `FAILED the endpoints of ${ldsUrl} carry no serverCertificate: node-opcua's RegisterServerManager ` +
                "then has no selected endpoint and never sends RegisterServer(2), even for SecurityPolicy None " +
                "(the LDS needs an application instance certificate)\n"
        );
        shutdown("LDS without certificate", 1);
    };
    process.on("SIGINT", () => shutdown("SIGINT", 0));

    const wanted = opts.port || 0;
    const attempts = wanted === 0 ? 5 : 1;
    let port = 0;
    for (let attempt = 1; ; attempt++) {
        port = wanted === 0 ? await pickFreePort() : wanted;
        const candidate = createServer(port, ldsUrl, opts);
        let announced = false;
        candidate.on("serverRegistrationPending", () => log("registration pending"));
        candidate.on("serverRegistrationRenewed", () => log("registration renewed"));
        candidate.on("serverUnregistered", () => log("unregistered"));
        candidate.on("serverRegistered", () => {
            if (announced || stopping) return;
            announced = true;
            const online = outcomes.filter((o) => o.online);
            if (online.some((o) => o.ok)) {
                process.stdout.write(`READY opc.tcp://${HOST}:${port}\n`);
            } else {
                const why = online.length ? online.map((o) => `${o.request} -> ${o.status}`).join(", ") : "no RegisterServer(2) was sent";
                process.stdout.write(`FAILED registration with ${ldsUrl}: ${why}\n`);
                shutdown("failed registration", 1);
            }
        });
        try {
            await candidate.start();
            server = candidate;
            break;
        } catch (err) {
            try {
                await candidate.shutdown(0);
            } catch (_) {
                // it never fully started
            }
            if (!isAddressInUse(err) || attempt >= attempts) throw err;
            log(`port ${port} taken, picking another one`);
        }
    }
    // not forwarded by OPCUAServer: listen on its RegisterServerManager (created by start())
    if (server.registerServerManager) {
        server.registerServerManager.on("serverRegistrationFailure", () =>
            log("registration attempt failed, node-opcua retries in 5 s")
        );
    }
    log(`listening on opc.tcp://${HOST}:${port}, registering with ${ldsUrl}`);
}

main().catch((err) => {
    process.stderr.write(`register_server.js: failed to start: ${err && err.stack ? err.stack : err}\n`);
    process.exit(1);
});
