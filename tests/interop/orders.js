#!/usr/bin/env node
// node-opcua client and the semantic MES's orders (docs/mes.md, "Orders"), knowing only what
// the MES publishes: the object Objects/Orders, its methods by browse name and their argument
// lists.
//   1. SubmitOrder refuses an empty process IRI and a priority out of -100..100
//      (BadInvalidArgument);
//   2. an order of WAITING_IRI (a process that waits long for a skill no component offers)
//      is accepted with an id; its object Orders/<id> appears, and its State, followed by
//      subscription, says the MES waits for the skill ("checking"); ListOrders and GetOrder show it with its process
//      and priority;
//   3. CancelOrder cancels it: State becomes "cancelled", and GetOrder says so; a second
//      CancelOrder is refused (BadInvalidState), and an unknown id (BadNotFound), for
//      GetOrder too;
//   4. an order of a process the KB does not hold ends "stopped", GetOrder giving the reason.
// usage: node orders.js opc.tcp://HOST:PORT WAITING_IRI
// Prints "OK orders" and exits 0, or prints the failure on stderr and exits 1.
"use strict";

require("./log_to_stderr"); // before node-opcua: keep stdout clean
const { AttributeIds, DataType, Variant, VariantArrayType } = require("node-opcua-client");
const {
    StatusCodes, checkEndpointUrl, connect, disconnect, monitorItem, runMain, startSubscription,
    waitFor
} = require("./common");
const { childByName } = require("./skill_model");

const USAGE = "usage: node orders.js opc.tcp://HOST:PORT WAITING_PROCESS_IRI";
const [url, waitingIri] = process.argv.slice(2);
checkEndpointUrl(url, USAGE);
if (!waitingIri) { process.stderr.write(`${USAGE}\n`); process.exit(2); }
const UNKNOWN_IRI = "http://skillcell.dev/test/orders#noSuchProcess";
const NO_SUCH_ORDER = 987654321;

function expect(what, status, wanted) {
    if (status !== wanted) throw new Error(`${what}: ${status.toString()}, expected ${wanted.toString()}`);
}

const text = (value) => new Variant({ dataType: DataType.String, value });
const int32 = (value) => new Variant({ dataType: DataType.Int32, value });
const int64 = (value) => new Variant({ dataType: DataType.Int64, arrayType: VariantArrayType.Scalar, value: [0, value] });
const number = (int64Value) => (Array.isArray(int64Value) ? int64Value[0] * 2 ** 32 + int64Value[1] : Number(int64Value));

async function main() {
    let problem = null;
    const { client, session } = await connect(url, "skillcell-orders", (m) => { problem = m; });
    try {
        const orders = await childByName(session, "ns=0;i=85", "Orders");
        const methodIds = {};
        for (const name of ["SubmitOrder", "CancelOrder", "ListOrders", "GetOrder"]) {
            methodIds[name] = await childByName(session, orders, name);
        }
        const call = (name, args) => session.call({ objectId: orders, methodId: methodIds[name], inputArguments: args });

        // 1. Refusals of bad input.
        expect("SubmitOrder of an empty IRI", (await call("SubmitOrder", [text(""), int32(0)])).statusCode,
            StatusCodes.BadInvalidArgument);
        expect("SubmitOrder with priority 101", (await call("SubmitOrder", [text(waitingIri), int32(101)])).statusCode,
            StatusCodes.BadInvalidArgument);
        process.stderr.write("ok  SubmitOrder refuses an empty IRI and priority 101 (BadInvalidArgument)\n");

        // 2. An order accepted, followed by its State.
        const submitted = await call("SubmitOrder", [text(waitingIri), int32(7)]);
        expect("SubmitOrder", submitted.statusCode, StatusCodes.Good);
        const id = number(submitted.outputArguments[0].value);
        if (!(id > 0)) throw new Error(`SubmitOrder gave the order id ${submitted.outputArguments[0].value}`);
        if (submitted.outputArguments[1].value !== false) throw new Error("a new order reported as resumed");
        process.stderr.write(`ok  SubmitOrder accepted order ${id}\n`);

        const subscription = await startSubscription(session, 20);
        // Orders/<id>/State by subscription. The object appears with the MES's first progress
        // of the order, posted to the server's thread: browsed for, a bounded number of times.
        const follow = async (order) => {
            let object = null;
            for (let i = 0; i < 100 && !object; ++i) {
                try {
                    object = await childByName(session, orders, String(order));
                } catch (e) {
                    await new Promise((r) => setTimeout(r, 50));
                }
            }
            if (!object) throw new Error(`no object Orders/${order}`);
            const item = await monitorItem(subscription, await childByName(session, object, "State"),
                AttributeIds.Value, { queueSize: 100 });
            const states = [];
            item.on("changed", (dv) => states.push(dv.value.value));
            const reached = async (want, what) => {
                const has = () => (states.some(want) ? true : undefined);
                if (!has()) await waitFor(item, "changed", has, 20000, what);
            };
            return { states, reached };
        };
        const first = await follow(id);
        const states = first.states;
        // "checking": the MES has read the process and waits for a skill no component offers.
        await first.reached((s) => s === "checking", "State checking");
        process.stderr.write(`ok  Orders/${id}/State: ${states.join(", ")}\n`);

        const listed = await call("ListOrders", [int32(10)]);
        expect("ListOrders", listed.statusCode, StatusCodes.Good);
        const [ids, processes, listedStates, priorities] = listed.outputArguments.map((a) => Array.from(a.value || []));
        const at = ids.map(number).indexOf(id);
        if (at < 0) throw new Error(`ListOrders lacks order ${id}: [${ids.map(number)}]`);
        if (processes[at] !== waitingIri || priorities[at] !== 7) {
            throw new Error(`ListOrders shows order ${id} as ${processes[at]}, priority ${priorities[at]}`);
        }
        process.stderr.write(`ok  ListOrders shows order ${id}: ${listedStates[at]}, priority 7\n`);
        const got = await call("GetOrder", [int64(id)]);
        expect("GetOrder", got.statusCode, StatusCodes.Good);
        if (got.outputArguments[0].value !== waitingIri) throw new Error(`GetOrder's process: ${got.outputArguments[0].value}`);
        process.stderr.write(`ok  GetOrder: ${got.outputArguments[1].value}, ${got.outputArguments[2].value}\n`);

        // 3. Cancelled; refusals of a second cancel and of unknown ids.
        expect("CancelOrder", (await call("CancelOrder", [int64(id)])).statusCode, StatusCodes.Good);
        await first.reached((s) => s === "cancelled", "State cancelled");
        const after = await call("GetOrder", [int64(id)]);
        if (after.outputArguments[1].value !== "cancelled") throw new Error(`GetOrder after the cancel: ${after.outputArguments[1].value}`);
        process.stderr.write(`ok  CancelOrder: order ${id} cancelled\n`);
        expect("a second CancelOrder", (await call("CancelOrder", [int64(id)])).statusCode, StatusCodes.BadInvalidState);
        expect("CancelOrder of an unknown id", (await call("CancelOrder", [int64(NO_SUCH_ORDER)])).statusCode, StatusCodes.BadNotFound);
        expect("GetOrder of an unknown id", (await call("GetOrder", [int64(NO_SUCH_ORDER)])).statusCode, StatusCodes.BadNotFound);
        process.stderr.write("ok  a second cancel: BadInvalidState; unknown ids: BadNotFound\n");

        // 4. A process the KB does not hold: the order stops, with the reason.
        const unknown = await call("SubmitOrder", [text(UNKNOWN_IRI), int32(0)]);
        expect("SubmitOrder of an unknown process", unknown.statusCode, StatusCodes.Good);
        const second = number(unknown.outputArguments[0].value);
        await (await follow(second)).reached((s) => s === "stopped", `order ${second} stopped`);
        const stopped = await call("GetOrder", [int64(second)]);
        expect("GetOrder", stopped.statusCode, StatusCodes.Good);
        const ended = stopped.outputArguments[2].value;
        if (!ended || !ended.includes("has no process")) throw new Error(`order ${second} of an unknown process: ${ended}`);
        process.stderr.write(`ok  order ${second} of an unknown process stopped: ${ended}\n`);

        await subscription.terminate();
        if (problem) throw new Error(problem);
        process.stdout.write("OK orders\n");
    } finally {
        await disconnect(client, session);
    }
}

runMain(main, 90);
