#!/usr/bin/env node
// node-opcua clients and a component's reservation with fencing (docs/skills.md,
// "Reservation"), knowing only the Skills model: the object under Objects whose type is
// ReservationType (ns = http://skillcell.dev/UA/Skills/, i=1003) and its children by name.
//   1. session A reserves (Reserve "node A") and gets a token;
//   2. session B, without the token, is refused: a parameter write and Start with
//      BadUserAccessDenied, Reserve for another holder with BadResourceUnavailable, Use and
//      Release with a made-up token with BadInvalidArgument;
//   3. session B with the token (Use) is accepted: it writes the parameter and runs the skill;
//   4. session C takes the reservation over (Takeover): a greater token; A and B, whose
//      token is stale now, are refused (write: BadUserAccessDenied, Use and Release of the old
//      token: BadInvalidArgument); C releases, and the component is free for anyone again;
//   5. session D reserves and closes its session: its lease is over, so E, another holder,
//      reserves without Takeover.
// usage: node reservation.js opc.tcp://HOST:PORT SKILL_NAME
// Prints "OK reservation" and exits 0, or prints the failure on stderr and exits 1.
"use strict";

require("./log_to_stderr"); // before node-opcua: keep stdout clean
const { AttributeIds, DataType, Variant, VariantArrayType } = require("node-opcua-client");
const {
    StatusCodes, checkEndpointUrl, connect, disconnect, resolveNamespaceIndex, runMain
} = require("./common");
const { childByName, findSkills } = require("./skill_model");

const SKILLS_URI = "http://skillcell.dev/UA/Skills/";
const [url, skillName] = process.argv.slice(2);
checkEndpointUrl(url, "usage: node reservation.js opc.tcp://HOST:PORT SKILL_NAME");
if (!skillName) { process.stderr.write("usage: node reservation.js URL SKILL_NAME\n"); process.exit(2); }

function expect(what, status, wanted) {
    if (status !== wanted) throw new Error(`${what}: ${status.toString()}, expected ${wanted.toString()}`);
}

// The object under Objects whose type definition is `typeId`.
async function objectOfType(session, typeId) {
    const browsed = await session.browse({ nodeId: "ns=0;i=85", referenceTypeId: "ns=0;i=33",
        includeSubtypes: true, browseDirection: 0, resultMask: 0x3f });
    const hit = browsed.references.find((r) => r.typeDefinition.toString() === typeId);
    if (!hit) throw new Error(`no object of type ${typeId} under Objects`);
    return hit.nodeId;
}

async function main() {
    const problems = [];
    const a = await connect(url, "skillcell-reservation-a", (m) => problems.push(m));
    const b = await connect(url, "skillcell-reservation-b", (m) => problems.push(m));
    const c = await connect(url, "skillcell-reservation-c", (m) => problems.push(m));
    try {
        const { index: ns } = await resolveNamespaceIndex(a.session, SKILLS_URI);
        if (ns < 0) throw new Error(`namespace ${SKILLS_URI} missing`);
        const reservation = await objectOfType(a.session, `ns=${ns};i=1003`);
        const method = async (name) => childByName(a.session, reservation, name);
        const [reserveId, useId, releaseId] = [await method("Reserve"), await method("Use"), await method("Release")];
        const holderNode = await method("Holder");
        const tokenNode = await method("FencingToken");
        const call = (session, methodId, args) => session.call({ objectId: reservation, methodId, inputArguments: args });
        const reserve = (session, holder, takeover) => call(session, reserveId, [
            new Variant({ dataType: DataType.String, value: holder }),
            new Variant({ dataType: DataType.Boolean, value: takeover })]);
        const token = (t) => new Variant({ dataType: DataType.UInt64, arrayType: VariantArrayType.Scalar, value: t });

        const skills = await findSkills(a.session, `ns=${ns};i=1002`);
        const skill = skills.find((s) => s.browseName.name === skillName);
        if (!skill) throw new Error(`skill ${skillName} not found`);
        const parameter = await childByName(a.session, await childByName(a.session, skill.nodeId, "ParameterSet"), "MaxVelocity");
        const startId = await childByName(a.session, skill.nodeId, "Start");
        const write = (session, v) => session.write({ nodeId: parameter, attributeId: AttributeIds.Value,
            value: { value: { dataType: DataType.Double, value: v } } });
        const start = (session) => session.call({ objectId: skill.nodeId, methodId: startId });

        // 1. A reserves.
        const granted = await reserve(a.session, "node A", false);
        expect("Reserve by A", granted.statusCode, StatusCodes.Good);
        const tokenA = granted.outputArguments[0].value; // UInt64: [high, low]
        const holder = await a.session.read({ nodeId: holderNode, attributeId: AttributeIds.Value });
        if (holder.value.value !== "node A") throw new Error(`Holder: ${holder.value.value}`);

        // 2. B without the token.
        expect("B writes without the token", await write(b.session, 0.5), StatusCodes.BadUserAccessDenied);
        expect("B starts without the token", (await start(b.session)).statusCode, StatusCodes.BadUserAccessDenied);
        expect("B reserves while A holds it", (await reserve(b.session, "node B", false)).statusCode,
            StatusCodes.BadResourceUnavailable);
        expect("B uses a made-up token", (await call(b.session, useId, [token([0, 7])])).statusCode,
            StatusCodes.BadInvalidArgument);
        expect("B releases with a made-up token", (await call(b.session, releaseId, [token([0, 7])])).statusCode,
            StatusCodes.BadInvalidArgument);

        // 3. B with the token.
        expect("B uses A's token", (await call(b.session, useId, [token(tokenA)])).statusCode, StatusCodes.Good);
        expect("B writes with the token", await write(b.session, 0.5), StatusCodes.Good);
        expect("B starts with the token", (await start(b.session)).statusCode, StatusCodes.Good);

        // 4. C takes over; A and B are fenced off.
        const taken = await reserve(c.session, "node C", true);
        expect("Takeover by C", taken.statusCode, StatusCodes.Good);
        const tokenC = taken.outputArguments[0].value;
        const asBig = (t) => (BigInt(t[0]) << 32n) + BigInt(t[1]);
        if (!(asBig(tokenC) > asBig(tokenA))) throw new Error(`token ${tokenC} not greater than ${tokenA}`);
        const current = await a.session.read({ nodeId: tokenNode, attributeId: AttributeIds.Value });
        if (asBig(current.value.value) !== asBig(tokenC)) throw new Error(`FencingToken ${current.value.value}`);
        expect("A writes with its stale token", await write(a.session, 0.4), StatusCodes.BadUserAccessDenied);
        expect("B writes with the stale token", await write(b.session, 0.4), StatusCodes.BadUserAccessDenied);
        expect("A uses its stale token", (await call(a.session, useId, [token(tokenA)])).statusCode,
            StatusCodes.BadInvalidArgument);
        expect("A releases with its stale token", (await call(a.session, releaseId, [token(tokenA)])).statusCode,
            StatusCodes.BadInvalidArgument);
        expect("C writes", await write(c.session, 0.4), StatusCodes.Good);
        expect("C releases", (await call(c.session, releaseId, [token(tokenC)])).statusCode, StatusCodes.Good);
        expect("A writes once it is free", await write(a.session, 0.3), StatusCodes.Good);

        // 5. D's sessions are its lease: closed, another holder may reserve.
        const d = await connect(url, "skillcell-reservation-d", (m) => problems.push(m));
        try {
            expect("Reserve by D", (await reserve(d.session, "node D", false)).statusCode, StatusCodes.Good);
            expect("E reserves while D's session lives", (await reserve(c.session, "node E", false)).statusCode,
                StatusCodes.BadResourceUnavailable);
        } finally {
            await disconnect(d.client, d.session); // CloseSession, then the connection
        }
        const afterD = await reserve(c.session, "node E", false);
        expect("E reserves once D's session is closed", afterD.statusCode, StatusCodes.Good);
        const holderE = await c.session.read({ nodeId: holderNode, attributeId: AttributeIds.Value });
        if (holderE.value.value !== "node E") throw new Error(`Holder after D: ${holderE.value.value}`);
        expect("E releases", (await call(c.session, releaseId, [token(afterD.outputArguments[0].value)])).statusCode,
            StatusCodes.Good);
        if (problems.length) throw new Error(problems.join("; "));
        process.stdout.write("OK reservation\n");
    } finally {
        for (const s of [a, b, c]) await disconnect(s.client, s.session);
    }
}

runMain(main, 60);
