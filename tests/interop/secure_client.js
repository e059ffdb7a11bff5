#!/usr/bin/env node
// node-opcua client against a skillcell server with security on: every security policy
// with Sign and SignAndEncrypt, user name + password authentication, and role checks.
//
// usage: node secure_client.js opc.tcp://HOST:PORT --pki DIR --operator USER:PASSWORD
//                              --observer USER:PASSWORD
//                              [--x509-user CERT.der:KEY.pem --x509-stranger CERT.der:KEY.pem]
//        node secure_client.js opc.tcp://HOST:PORT --pki DIR --expect-untrusted
//
// For each of Basic256Sha256, Aes128_Sha256_RsaOaep, Aes256_Sha256_RsaPss and each mode:
// connect, open a session as the operator, read the server state, call Demo.Add (operators
// may), close. Then, over Aes256_Sha256_RsaPss/SignAndEncrypt: the observer may read but
// Demo.Add is refused with BadUserAccessDenied; a wrong password and an anonymous session are
// refused. With --x509-user: a session with an X.509 user token (the certificate the server's
// users file knows as an Operator, the token signed with its key) may call Demo.Add; one with
// --x509-stranger's certificate, which the users file does not know, is refused with
// BadUserAccessDenied. --expect-untrusted: the first connection must fail because the server does not
// trust our certificate yet (it then sits in the server's rejected/ folder).
// Prints "OK ..." lines and exits 0, or the failures and 1.
"use strict";

require("./log_to_stderr");
const path = require("path");
const {
    OPCUAClient,
    MessageSecurityMode,
    SecurityPolicy,
    UserTokenType,
    AttributeIds,
    DataType,
    StatusCodes
} = require("node-opcua-client");
const { OPCUACertificateManager } = require("node-opcua-certificate-manager");
const { readPrivateKey, keyOperationsFromPrivateKey } = require("node-opcua-crypto");
const fs = require("fs");
const { resolveNamespaceIndex, stringNodeId, DEMO_NAMESPACE_URI } = require("./common");

const USAGE =
    "usage: node secure_client.js URL --pki DIR (--operator U:P --observer U:P | --expect-untrusted)";
const url = process.argv[2];
const args = process.argv.slice(3);
function option(name) {
    const i = args.indexOf(name);
    return i >= 0 ? args[i + 1] : undefined;
}
const pki = option("--pki");
if (!url || !pki) {
    process.stderr.write(`${USAGE}\n`);
    process.exit(2);
}
const failures = [];
function fail(message) {
    failures.push(message);
    process.stderr.write(`FAIL ${message}\n`);
}

const POLICIES = [
    ["Basic256Sha256", SecurityPolicy.Basic256Sha256],
    ["Aes128_Sha256_RsaOaep", SecurityPolicy.Aes128_Sha256_RsaOaep],
    ["Aes256_Sha256_RsaPss", SecurityPolicy.Aes256_Sha256_RsaPss]
];
const MODES = [
    ["Sign", MessageSecurityMode.Sign],
    ["SignAndEncrypt", MessageSecurityMode.SignAndEncrypt]
];

function makeClient(policy, mode) {
    const clientCertificateManager = new OPCUACertificateManager({
        automaticallyAcceptUnknownCertificate: true,
        rootFolder: path.join(pki, "node-client")
    });
    return OPCUAClient.create({
        applicationName: "skillcell interop secure client",
        applicationUri: "urn:skillcell:interop:node-opcua-secure-client",
        securityMode: mode,
        securityPolicy: policy,
        endpointMustExist: false,
        keepSessionAlive: false,
        clientCertificateManager,
        connectionStrategy: { maxRetry: 0, initialDelay: 100, maxDelay: 200 },
        requestedSessionTimeout: 30000
    });
}

function credentials(text) {
    const colon = text.indexOf(":");
    return { type: UserTokenType.UserName, userName: text.slice(0, colon), password: text.slice(colon + 1) };
}

// An X.509 user identity from "CERT.der:KEY.pem".
function x509Identity(text) {
    const [cert, key] = text.split(":");
    return {
        type: UserTokenType.Certificate,
        certificateData: fs.readFileSync(cert),
        keyOperations: keyOperationsFromPrivateKey(readPrivateKey(key))
    };
}

async function callAdd(session) {
    const { index: ns } = await resolveNamespaceIndex(session, DEMO_NAMESPACE_URI);
    if (ns < 0) throw new Error(`${DEMO_NAMESPACE_URI} is not in the namespace array`);
    const result = await session.call({
        objectId: stringNodeId(ns, "Demo"),
        methodId: stringNodeId(ns, "Demo.Add"),
        inputArguments: [
            { dataType: DataType.Double, value: 2 },
            { dataType: DataType.Double, value: 3 }
        ]
    });
    return result;
}

async function withSession(policy, mode, identity, body) {
    const client = makeClient(policy, mode);
    try {
        await client.connect(url);
        let session;
        try {
            session = await client.createSession(identity);
        } catch (err) {
            return { error: err };
        }
        try {
            return { value: await body(session) };
        } finally {
            await session.close();
        }
    } finally {
        await client.disconnect();
    }
}

async function main() {
    if (args.includes("--expect-untrusted")) {
        const client = makeClient(SecurityPolicy.Basic256Sha256, MessageSecurityMode.SignAndEncrypt);
        try {
            await client.connect(url);
            fail("connected although the server does not trust our certificate");
        } catch (err) {
            process.stdout.write(`OK untrusted client refused: ${err.message.split("\n")[0]}\n`);
        } finally {
            await client.disconnect();
        }
        return;
    }
    const operator = credentials(option("--operator"));
    const observer = credentials(option("--observer"));
    for (const [policyName, policy] of POLICIES) {
        for (const [modeName, mode] of MODES) {
            const name = `${policyName}/${modeName}`;
            try {
                const r = await withSession(policy, mode, operator, async (session) => {
                    const state = await session.read({ nodeId: "ns=0;i=2259", attributeId: AttributeIds.Value });
                    if (state.statusCode !== StatusCodes.Good || state.value.value !== 0) {
                        fail(`${name}: ServerStatus.State read gave ${state.statusCode.toString()} ${state.value.value}`);
                    }
                    const add = await callAdd(session);
                    if (add.statusCode !== StatusCodes.Good || add.outputArguments[0].value !== 5) {
                        fail(`${name}: Demo.Add as operator gave ${add.statusCode.toString()}`);
                    }
                    return true;
                });
                if (r.error) fail(`${name}: operator session refused: ${r.error.message}`);
                else process.stdout.write(`OK ${name}: read and call as operator\n`);
            } catch (err) {
                fail(`${name}: ${err.message}`);
            }
        }
    }
    const strongest = SecurityPolicy.Aes256_Sha256_RsaPss;
    const encrypt = MessageSecurityMode.SignAndEncrypt;
    const asObserver = await withSession(strongest, encrypt, observer, async (session) => {
        const state = await session.read({ nodeId: "ns=0;i=2259", attributeId: AttributeIds.Value });
        const add = await callAdd(session);
        return { read: state.statusCode, call: add.statusCode };
    });
    if (asObserver.error) fail(`observer session refused: ${asObserver.error.message}`);
    else if (asObserver.value.read !== StatusCodes.Good || asObserver.value.call !== StatusCodes.BadUserAccessDenied) {
        fail(`observer: read ${asObserver.value.read.toString()}, call ${asObserver.value.call.toString()} (want Good, BadUserAccessDenied)`);
    } else {
        process.stdout.write("OK observer may read, Demo.Add refused with BadUserAccessDenied\n");
    }
    const wrong = await withSession(strongest, encrypt, { ...operator, password: operator.password + "x" }, async () => true);
    if (!wrong.error || !/BadUserAccessDenied/.test(wrong.error.message)) {
        fail(`wrong password: ${wrong.error ? wrong.error.message : "accepted"}`);
    } else {
        process.stdout.write("OK wrong password refused with BadUserAccessDenied\n");
    }
    if (option("--x509-user")) {
        const machine = await withSession(strongest, encrypt, x509Identity(option("--x509-user")), async (session) => {
            const add = await callAdd(session);
            return add.statusCode;
        });
        if (machine.error) fail(`X.509 user session refused: ${machine.error.message}`);
        else if (machine.value !== StatusCodes.Good) fail(`X.509 user (Operator): Demo.Add gave ${machine.value.toString()}`);
        else process.stdout.write("OK X.509 user token accepted, Demo.Add as its Operator role\n");
        const stranger = await withSession(strongest, encrypt, x509Identity(option("--x509-stranger")), async () => true);
        if (!stranger.error || !/BadUserAccessDenied/.test(stranger.error.message)) {
            fail(`unknown X.509 user: ${stranger.error ? stranger.error.message : "accepted"}`);
        } else {
            process.stdout.write("OK unknown X.509 user refused with BadUserAccessDenied\n");
        }
    }
    const anonymous = await withSession(strongest, encrypt, { type: UserTokenType.Anonymous }, async () => true);
    if (!anonymous.error) fail("anonymous session accepted on a device server");
    else process.stdout.write(`OK anonymous refused: ${anonymous.error.message.split("\n")[0]}\n`);
}

const timer = setTimeout(() => {
    fail("timed out after 120 s");
    process.exit(1);
}, 120000);
main()
    .catch((err) => fail(`unexpected: ${err.stack || err}`))
    .finally(() => {
        clearTimeout(timer);
        process.exit(failures.length ? 1 : 0);
    });
