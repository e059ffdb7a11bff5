#!/usr/bin/env node
// node-opcua server that registers itself with a Local Discovery Server, for the skillcell
// discovery interop tests (registerServerMethod LDS, so it sends no mDNS itself).
//
// usage: node register_server.js LDS_URL [--port N] [--application-uri URI] [--caps A,B]
//                                [--certificate FILE --private-key FILE] [--keep-trying]
//
//   --port N               0 or omitted: pick a free port
//   --application-uri URI  default urn:skillcell:interop:node-registered-server; node-opcua also
//                          uses it as the mdnsServerName of its RegisterServer2 request
//   --caps A,B             serverCapabilities announced for mDNS (node-opcua's default: NA)
//   --certificate FILE     application instance certificate (DER or PEM) and its key (PEM),
//   --private-key FILE     e.g. issued by `skillcell pki issue`; node-opcua uses them for its
//                          endpoints and for the channel to the LDS. Default: a self-signed
//                          certificate node-opcua makes in its PKI folder
//   --keep-trying          a refused registration is not final: no FAILED, node-opcua tries
//                          again every second, READY is printed at the first success
//
// node-opcua's RegisterServerManager connects to LDS_URL, calls GetEndpoints, picks the most
// secure endpoint (SignAndEncrypt before Sign before None, then the strongest policy; it needs
// the endpoint's serverCertificate to be set, even for SecurityPolicy None), then sends
// RegisterServer2 (falling back to RegisterServer when that fails). It does not verify the
// LDS's certificate: it takes the one GetEndpoints returned. Its "serverRegistered" event
// fires even when both requests were refused or the secure channel could not be opened, and
// it then waits for the renewal period (8 min) before trying again, so this script watches
// the responses itself: it prints "READY opc.tcp://127.0.0.1:PORT" on stdout only once a
// RegisterServer(2) with isOnline=true was answered without a fault, and "FAILED ..." (exit 1)
// when it was refused (unless --keep-trying), or at once when none of the LDS's endpoints
// carries a serverCertificate (node-opcua would then never send RegisterServer(2)). Logged to
// stderr: the certificate ("certificate thumbprint=SHA1HEX subjectAltName=.. issuer=.."), the
// LDS's endpoints, every registration request with the channel it went over and its outcome
// ("register: RegisterServer2Request over SignAndEncrypt <policy URI> isOnline=true ... ->
// Good ..."), and every failed connection ("register: connect over <mode> <policy> to URL
// failed: ...").
// SIGTERM/SIGINT: shutdown, which unregisters (isOnline=false), then exit 0.
"use strict";

require("./log_to_stderr"); // before node-opcua: keep stdout clean
const crypto = require("crypto");
const fs = require("fs");
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
const { RegisterServerManagerStatus } = require("node-opcua-server/dist/i_register_server_manager.js");
const {
    HOST,
    pkiRoot,
    parseArgs,
    checkEndpointUrl,
    pickFreePort,
    isAddressInUse
} = require("./discovery_common");

const USAGE =
    "usage: node register_server.js LDS_URL [--port N] [--application-uri URI] [--caps A,B]\n" +
    "                               [--certificate FILE --private-key FILE] [--keep-trying]";
// --keep-trying: RegisterServerManager's renewal period, which is also its only retry after a
// refused registration or a refused secure channel (it retries every 5 s only when the LDS
// cannot be reached at all)
const KEEP_TRYING_PERIOD_MS = 1000;
const log = (msg) => process.stderr.write(`register_server.js: ${msg}\n`);

// Outcomes of the registration requests sent by node-opcua's RegisterServerManager, observed
// by wrapping the clients it creates (OPCUAClientBase.create is looked up at each call).
const outcomes = []; // { online, request, ok, status }
let lastEndpointListing = null;
// set by main(): noCertificate when none of the LDS's endpoints carries a serverCertificate,
// outcome after each registration request was answered
const hooks = { noCertificate: () => {}, outcome: () => {} };
function instrumentRegistrationClients() {
    const create = OPCUAClientBase.create;
    OPCUAClientBase.create = (options) => {
        const client = create(options);
        const channel = `${MessageSecurityMode[options.securityMode || MessageSecurityMode.None]} ${options.securityPolicy || SecurityPolicy.None}`;
        const connect = client.connect.bind(client);
        client.connect = (...args) => {
            // RegisterServerManager awaits connect(url); a refused channel shows only here
            if (typeof args[args.length - 1] === "function") return connect(...args);
            return connect(...args).catch((err) => {
                const why = (err && err.message ? err.message : String(err)).replace(/\s*\n\s*/g, " ").trim();
                log(`register: connect over ${channel} to ${args[0]} failed: ${why}`);
                throw err;
            });
        };
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
                    const outcome = { online, request: name, ok: !err, status };
                    outcomes.push(outcome);
                    hooks.outcome(outcome);
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

// node-opcua reads a certificate file whose name contains ".der" as DER, any other as PEM:
// hand it a PEM copy (in its PKI folder) when the name does not tell the content
function certificateFileForNode(file, folder) {
    const data = fs.readFileSync(file);
    const isPem = data.includes("-----BEGIN CERTIFICATE-----");
    if (isPem !== /.*\.der/.test(file)) return file;
    if (isPem) throw new Error(`${file}: PEM in a file named .der, which node-opcua would read as DER`);
    fs.mkdirSync(folder, { recursive: true });
    const pem = path.join(folder, "certificate_from_der.pem");
    const base64 = data.toString("base64").match(/.{1,64}/g).join("\n");
    fs.writeFileSync(pem, `-----BEGIN CERTIFICATE-----\n${base64}\n-----END CERTIFICATE-----\n`);
    return pem;
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
    if (opts.certificate) {
        options.certificateFile = certificateFileForNode(opts.certificate, path.join(pkiRoot(), folder));
        options.privateKeyFile = opts.privateKey;
    }
    if (opts.caps !== undefined) {
        options.capabilitiesForMDNS = opts.caps.split(",").filter((c) => c.length > 0);
    }
    return new OPCUAServer(options);
}

// node-opcua's RegisterServerManager, stopped while a registration request is in flight,
// cancels that request and then sends no unregistration at all (seen with --keep-trying, which
// renews every second: SIGTERM during a renewal left "no unregistration was sent"). So a
// shutdown first lets the request in flight settle, bounded by 10 s.
async function registrationSettled(server) {
    const manager = server && server.registerServerManager;
    if (!manager || manager.getState() !== RegisterServerManagerStatus.REGISTERING) return;
    log("a registration request is in flight: letting it settle before unregistering");
    await new Promise((resolve) => {
        const timer = setTimeout(resolve, 10000);
        const settled = () => {
            clearTimeout(timer);
            resolve();
        };
        server.once("serverRegistrationRenewed", settled);
        server.once("serverRegistered", settled);
        manager.once("serverRegistrationFailure", settled);
    });
}

async function main() {
    const { positional, opts } = parseArgs(
        process.argv.slice(2),
        {
            "--port": "int",
            "--application-uri": "string",
            "--caps": "string",
            "--certificate": "string",
            "--private-key": "string",
            "--keep-trying": "flag"
        },
        USAGE,
        1
    );
    const ldsUrl = positional[0];
    checkEndpointUrl(ldsUrl, USAGE);
    if (!opts.certificate !== !opts.privateKey) {
        process.stderr.write(`register_server.js: --certificate and --private-key go together\n${USAGE}\n`);
        process.exit(2);
    }
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
            await registrationSettled(server);
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
    let ready = false;
    const printReady = () => {
        if (ready || stopping) return;
        ready = true;
        process.stdout.write(`READY opc.tcp://${HOST}:${port}\n`);
    };
    // --keep-trying: a later attempt is a renewal, which fires no "serverRegistered"
    hooks.outcome = (o) => {
        if (opts.keepTrying && o.online && o.ok) printReady();
    };
    for (let attempt = 1; ; attempt++) {
        port = wanted === 0 ? await pickFreePort() : wanted;
        const candidate = createServer(port, ldsUrl, opts);
        if (opts.keepTrying && candidate.registerServerManager) {
            candidate.registerServerManager.timeout = KEEP_TRYING_PERIOD_MS;
        }
        let announced = false;
        candidate.on("serverRegistrationPending", () => log("registration pending"));
        candidate.on("serverRegistrationRenewed", () => log("registration renewed"));
        candidate.on("serverUnregistered", () => log("unregistered"));
        candidate.on("serverRegistered", () => {
            if (announced || stopping) return;
            announced = true;
            const online = outcomes.filter((o) => o.online);
            if (online.some((o) => o.ok)) {
                printReady();
                return;
            }
            const why = online.length ? online.map((o) => `${o.request} -> ${o.status}`).join(", ") : "no RegisterServer(2) was sent";
            if (opts.keepTrying) {
                log(`first registration failed (${why}); trying again every ${KEEP_TRYING_PERIOD_MS} ms`);
                return;
            }
            process.stdout.write(`FAILED registration with ${ldsUrl}: ${why}\n`);
            shutdown("failed registration", 1);
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
    // not forwarded by OPCUAServer: listen on its RegisterServerManager
    if (server.registerServerManager) {
        const manager = server.registerServerManager;
        manager.on("serverRegistrationFailure", () =>
            log(`registration attempt failed, node-opcua retries in ${Math.min(5000, manager.timeout) / 1000} s`)
        );
    }
    // the test drivers find this certificate in the LDS's rejected/ by its thumbprint
    const der = server.getCertificate();
    const x509 = new crypto.X509Certificate(der);
    log(
        `certificate thumbprint=${crypto.createHash("sha1").update(der).digest("hex")} ` +
            `subjectAltName="${x509.subjectAltName || ""}" issuer="${x509.issuer.replace(/\n/g, ", ")}" ` +
            (opts.certificate ? `from ${opts.certificate}` : "made by node-opcua")
    );
    log(`listening on opc.tcp://${HOST}:${port}, registering with ${ldsUrl}`);
}

main().catch((err) => {
    process.stderr.write(`register_server.js: failed to start: ${err && err.stack ? err.stack : err}\n`);
    process.exit(1);
});
