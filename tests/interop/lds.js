#!/usr/bin/env node
// node-opcua Local Discovery Server with the multicast extension (LDS-ME) for the skillcell
// discovery interop tests. Sends and receives mDNS: run it only inside a private network
// namespace (tests/netns/run_in_private_netns.sh); it refuses to start when a non-loopback
// interface exists.
//
// usage: node lds.js [--port N] [--application-uri URI] [--refuse-unsecured-registration]
//                    [--none-only]
//
//   --port N    0 or omitted: pick a free port
//   --application-uri URI   the LDS's applicationUri, also its mDNS service name
//                           (default urn:skillcell:interop:node-lds)
//   --refuse-unsecured-registration   do not set allowUnsecuredRegistration: RegisterServer(2)
//               over SecurityPolicy None is then refused with BadSecurityModeInsufficient, so
//               FindServersOnNetwork can only list what the LDS learnt by mDNS.
//   --none-only offer only the SecurityPolicy None endpoint (default: node-opcua's default
//               endpoints, None + Sign + SignAndEncrypt)
//
// Prints exactly one stdout line "READY opc.tcp://127.0.0.1:PORT" once it listens and has
// published its own mDNS announcement; logs every RegisterServer(2) it receives to stderr
// ("registered <serverUri> ..." / "unregistered <serverUri>"). Exits 0 on SIGTERM/SIGINT
// (after its mDNS goodbye).
"use strict";

require("./log_to_stderr"); // before node-opcua: keep stdout clean
const path = require("path");
const { OPCUACertificateManager } = require("node-opcua-certificate-manager");
const { SecurityPolicy, MessageSecurityMode } = require("node-opcua-secure-channel");
const { OPCUADiscoveryServer } = require("node-opcua-server-discovery");
const { HOST, pkiRoot, parseArgs, requirePrivateNetwork, pickFreePort, isAddressInUse } = require("./discovery_common");

const USAGE =
    "usage: node lds.js [--port N] [--application-uri URI] [--refuse-unsecured-registration] [--none-only]";

function createLds(port, opts) {
    const serverCertificateManager = new OPCUACertificateManager({
        automaticallyAcceptUnknownCertificate: true,
        rootFolder: path.join(pkiRoot(), "lds")
    });
    const options = {
        port,
        hostname: HOST, // advertise opc.tcp://127.0.0.1:PORT (endpoints and mDNS SRV target)
        serverCertificateManager,
        automaticallyAcceptUnknownCertificate: true,
        allowUnsecuredRegistration: !opts.refuseUnsecuredRegistration,
        serverInfo: {
            applicationUri: opts.applicationUri || "urn:skillcell:interop:node-lds",
            productUri: "urn:skillcell:interop",
            applicationName: { text: "skillcell-interop-node-lds", locale: "en" }
        }
    };
    if (opts.noneOnly) {
        options.securityPolicies = [SecurityPolicy.None];
        options.securityModes = [MessageSecurityMode.None];
    }
    const lds = new OPCUADiscoveryServer(options);
    lds.on("onRegisterServer", (server, first) => {
        // node-opcua attaches the mDNS configuration right after emitting the event
        setImmediate(() => {
            const conf = (server.discoveryConfiguration || [])
                .map((c) => `mdnsServerName=${c.mdnsServerName} caps=${(c.serverCapabilities || []).join(",")}`)
                .join("; ");
            process.stderr.write(
                `lds.js: registered ${server.serverUri} (${first ? "first time" : "renewal"}) ` +
                    `urls=${(server.discoveryUrls || []).join(",")} ${conf || "(no mDNS configuration)"}\n`
            );
        });
    });
    lds.on("onUnregisterServer", (server, forced) => {
        process.stderr.write(`lds.js: unregistered ${server.serverUri}${forced ? " (forced)" : ""}\n`);
    });
    lds.on("onRegistrationRefused", (server, info) => {
        process.stderr.write(`lds.js: refused registration of ${server.serverUri}: ${info.statusCode.toString()}\n`);
    });
    return lds;
}

async function main() {
    const { opts } = parseArgs(
        process.argv.slice(2),
        {
            "--port": "int",
            "--application-uri": "string",
            "--refuse-unsecured-registration": "flag",
            "--none-only": "flag"
        },
        USAGE,
        0
    );
    if ((opts.port || 0) > 65535) {
        process.stderr.write(`lds.js: --port needs 0..65535\n${USAGE}\n`);
        process.exit(2);
    }
    requirePrivateNetwork("lds.js");

    let lds = null;
    let stopping = false;
    const shutdown = async (sig) => {
        if (stopping) return;
        stopping = true;
        const guard = setTimeout(() => process.exit(0), 8000);
        guard.unref();
        try {
            if (lds) await lds.shutdown();
        } catch (err) {
            process.stderr.write(`lds.js: shutdown error on ${sig}: ${err && err.message}\n`);
        }
        process.exit(0);
    };
    process.on("SIGTERM", () => shutdown("SIGTERM"));
    process.on("SIGINT", () => shutdown("SIGINT"));

    const wanted = opts.port || 0;
    const attempts = wanted === 0 ? 5 : 1;
    let port = 0;
    for (let attempt = 1; ; attempt++) {
        port = wanted === 0 ? await pickFreePort() : wanted;
        const candidate = createLds(port, opts);
        try {
            await candidate.start();
            lds = candidate;
            break;
        } catch (err) {
            try {
                await candidate.shutdown();
            } catch (_) {
                // it never fully started
            }
            if (!isAddressInUse(err) || attempt >= attempts) throw err;
            process.stderr.write(`lds.js: port ${port} taken, picking another one\n`);
        }
    }
    if (stopping) return;
    process.stderr.write(`lds.js: endpoint ${lds.getEndpointUrl()} applicationUri ${lds.serverInfo.applicationUri}\n`);
    process.stdout.write(`READY opc.tcp://${HOST}:${port}\n`);
}

main().catch((err) => {
    process.stderr.write(`lds.js: failed to start: ${err && err.stack ? err.stack : err}\n`);
    process.exit(1);
});
