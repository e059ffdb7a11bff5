// Helpers shared by client.js and bench_client.js (node-opcua public API only).
"use strict";

require("./log_to_stderr"); // before node-opcua: keep stdout clean
const os = require("os");
const path = require("path");
const {
    OPCUAClient,
    MessageSecurityMode,
    SecurityPolicy,
    AttributeIds,
    StatusCodes,
    NodeId,
    UserTokenType,
    ClientMonitoredItem,
    ClientSubscription,
    TimestampsToReturn
} = require("node-opcua-client");
const { OPCUACertificateManager } = require("node-opcua-certificate-manager");
const { NodeIdType } = require("node-opcua-nodeid");

const DEMO_NAMESPACE_URI = "urn:skillcell:demo";
const NAMESPACE_ARRAY = "ns=0;i=2255"; // Server_NamespaceArray

function pkiRoot() {
    return process.env.SKILLCELL_INTEROP_PKI || path.join(os.tmpdir(), "skillcell-interop-pki");
}

function checkEndpointUrl(url, usage) {
    if (typeof url !== "string" || !/^opc\.tcp:\/\/[^/:]+:\d+\/?.*$/.test(url)) {
        process.stderr.write(`${usage}\n`);
        process.exit(2);
    }
}

// How connect() secures its connection. By default SecurityPolicy None and an anonymous
// session; for servers with security on, from the environment:
//   SKILLCELL_NODE_SECURITY     "SignAndEncrypt" or "Sign" (with Aes256_Sha256_RsaPss)
//   SKILLCELL_NODE_CERTIFICATE  our certificate (DER file named *.der, or PEM), e.g. issued
//   SKILLCELL_NODE_PRIVATE_KEY  by `skillcell pki issue` for NODE_CLIENT_URI; its key (PEM)
//   SKILLCELL_NODE_USER         "user:password" for the session
//   SKILLCELL_NODE_PKI          node-opcua's PKI folder (the same layout as ours: with the cell
//                               CA in trusted/, the server's certificate is verified by it)
const NODE_CLIENT_URI = "urn:skillcell:interop:node-opcua-client";
function securityFromEnvironment() {
    const env = process.env;
    const mode = env.SKILLCELL_NODE_SECURITY;
    const out = { securityMode: MessageSecurityMode.None, securityPolicy: SecurityPolicy.None, identity: undefined };
    if (mode) {
        if (!(mode in { Sign: 1, SignAndEncrypt: 1 })) throw new Error(`SKILLCELL_NODE_SECURITY=${mode}: Sign or SignAndEncrypt`);
        out.securityMode = MessageSecurityMode[mode];
        out.securityPolicy = SecurityPolicy.Aes256_Sha256_RsaPss;
        out.certificateFile = env.SKILLCELL_NODE_CERTIFICATE;
        out.privateKeyFile = env.SKILLCELL_NODE_PRIVATE_KEY;
    }
    if (env.SKILLCELL_NODE_USER) {
        const colon = env.SKILLCELL_NODE_USER.indexOf(":");
        out.identity = {
            type: UserTokenType.UserName,
            userName: env.SKILLCELL_NODE_USER.slice(0, colon),
            password: env.SKILLCELL_NODE_USER.slice(colon + 1)
        };
    }
    return out;
}

// Creates a client (security from the environment, see above), connects and opens a
// session. Returns { client, session }.
// onProblem(message) is called when the connection drops or the session is
// closed behind our back: node-opcua would otherwise reconnect silently and
// replay the request, hiding a protocol error of the server.
const closingHooks = new WeakMap();
async function connect(endpointUrl, applicationName, onProblem) {
    const security = securityFromEnvironment();
    const clientCertificateManager = new OPCUACertificateManager({
        automaticallyAcceptUnknownCertificate: true,
        rootFolder: process.env.SKILLCELL_NODE_PKI || path.join(pkiRoot(), "client")
    });
    const client = OPCUAClient.create({
        applicationName,
        // one applicationUri for all scripts: they share one client certificate
        applicationUri: NODE_CLIENT_URI,
        securityMode: security.securityMode,
        securityPolicy: security.securityPolicy,
        ...(security.certificateFile ? { certificateFile: security.certificateFile } : {}),
        ...(security.privateKeyFile ? { privateKeyFile: security.privateKeyFile } : {}),
        endpointMustExist: false,
        keepSessionAlive: false,
        clientCertificateManager,
        // fail fast: the scripts are bounded by their own overall timeout
        connectionStrategy: { maxRetry: 2, initialDelay: 250, maxDelay: 1000 },
        requestedSessionTimeout: 60000
    });
    const report = onProblem || ((msg) => process.stderr.write(`warning: ${msg}\n`));
    let closing = false;
    client.on("connection_lost", () => closing || report("connection lost"));
    client.on("start_reconnection", (err) => closing || report(`client reconnecting${err ? `: ${err.message}` : ""}`));
    client.on("close", (err) => err && !closing && report(`connection closed: ${err.message}`));
    await client.connect(endpointUrl);
    const session = await client.createSession(security.identity); // anonymous by default
    session.on("session_closed", (sc) => closing || report(`session closed by the server: ${sc ? sc.toString() : "?"}`));
    // disconnect() calls this before closing on purpose
    closingHooks.set(client, () => {
        closing = true;
    });
    return { client, session };
}

async function disconnect(client, session) {
    if (client && closingHooks.has(client)) closingHooks.get(client)();
    let firstError = null;
    if (session) {
        try {
            await session.close();
        } catch (err) {
            firstError = firstError || err;
        }
    }
    if (client) {
        try {
            await client.disconnect();
        } catch (err) {
            firstError = firstError || err;
        }
    }
    if (firstError) throw firstError;
}

// Reads Server.NamespaceArray (i=2255) and returns { index, namespaces }.
// index is -1 when the uri is not there.
async function resolveNamespaceIndex(session, uri) {
    const dv = await session.read({ nodeId: NAMESPACE_ARRAY, attributeId: AttributeIds.Value });
    if (dv.statusCode.isNotGood()) {
        throw new Error(`reading NamespaceArray (i=2255) returned ${dv.statusCode.toString()}`);
    }
    const namespaces = Array.from((dv.value && dv.value.value) || []);
    return { index: namespaces.indexOf(uri), namespaces };
}

// A string NodeId in namespace nsIndex, built explicitly (no string parsing,
// so identifiers containing '.' or ';' are taken literally).
function stringNodeId(nsIndex, identifier) {
    return new NodeId(NodeIdType.STRING, identifier, nsIndex);
}

/// Resolves with the first value `accept` returns non-undefined for, or rejects after ms.
function waitFor(emitter, event, accept, ms, what) {
    return new Promise((resolve, reject) => {
        const timer = setTimeout(() => {
            emitter.removeListener(event, listener);
            reject(new Error(`no ${what} within ${ms} ms`));
        }, ms);
        function listener(...args) {
            const result = accept(...args);
            if (result === undefined) return;
            clearTimeout(timer);
            emitter.removeListener(event, listener);
            resolve(result);
        }
        emitter.on(event, listener);
    });
}

// Nearest-rank percentile over an already sorted array.
function percentile(sorted, p) {
    if (sorted.length === 0) return NaN;
    const rank = Math.ceil((p / 100) * sorted.length);
    return sorted[Math.min(sorted.length, Math.max(1, rank)) - 1];
}

/// A subscription publishing every `publishingInterval` ms, once the server has created it.
async function startSubscription(session, publishingInterval) {
    const subscription = ClientSubscription.create(session, {
        requestedPublishingInterval: publishingInterval, requestedLifetimeCount: 600,
        requestedMaxKeepAliveCount: 20, maxNotificationsPerPublish: 100,
        publishingEnabled: true, priority: 1
    });
    await new Promise((resolve, reject) => {
        subscription.once("started", resolve);
        subscription.once("internal_error", reject);
    });
    return subscription;
}

/// A monitored item (sampling 0, discardOldest, plus `options`: queueSize, filter), once the
/// server has created it.
async function monitorItem(subscription, nodeId, attributeId, options) {
    const item = ClientMonitoredItem.create(subscription, { nodeId, attributeId },
        { samplingInterval: 0, discardOldest: true, ...options }, TimestampsToReturn.Both);
    await new Promise((resolve, reject) => {
        item.once("initialized", resolve);
        item.once("err", (e) => reject(new Error(`monitored item ${nodeId}: ${e}`)));
    });
    return item;
}

/// Runs a script's `main` (async) and exits: 0 when it resolves, 1 with "FAIL: ..." on stderr
/// when it rejects or has not ended after `seconds`.
function runMain(main, seconds) {
    const overall = setTimeout(() => {
        process.stderr.write(`FAIL: timed out after ${seconds} s\n`);
        process.exit(1);
    }, seconds * 1000);
    main().then(() => { clearTimeout(overall); process.exit(0); }, (err) => {
        process.stderr.write(`FAIL: ${err && err.stack ? err.stack : err}\n`);
        process.exit(1);
    });
}

module.exports = {
    monitorItem,
    runMain,
    startSubscription,
    DEMO_NAMESPACE_URI,
    StatusCodes,
    checkEndpointUrl,
    connect,
    disconnect,
    resolveNamespaceIndex,
    stringNodeId,
    percentile,
    waitFor
};
