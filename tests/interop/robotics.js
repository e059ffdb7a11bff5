#!/usr/bin/env node
// node-opcua client that knows the OPC Foundation's DI and Robotics models and nothing of
// skillcell: finds a robot in DI's DeviceSet by browse paths (TranslateBrowsePathsToNodeIds)
// and reads its nameplate, its category and every axis's ActualPosition with its unit.
// usage: node robotics.js opc.tcp://HOST:PORT SYSTEM DEVICE AXIS...
// Prints "OK robotics <axis>=<position> ..." and exits 0, or the failure on stderr and 1.
"use strict";

require("./log_to_stderr"); // before node-opcua: keep stdout clean
const { AttributeIds, makeBrowsePath } = require("node-opcua-client");
const {
    StatusCodes, checkEndpointUrl, connect, disconnect, resolveNamespaceIndex, runMain
} = require("./common");

const DI = "http://opcfoundation.org/UA/DI/";
const ROBOTICS = "http://opcfoundation.org/UA/Robotics/";
const RADIAN = 4405297; // UNECE C81, as OPC 10000-8 numbers it
const [url, system, device, ...axes] = process.argv.slice(2);
checkEndpointUrl(url, "usage: node robotics.js opc.tcp://HOST:PORT SYSTEM DEVICE AXIS...");
if (!device || axes.length === 0) {
    process.stderr.write("usage: node robotics.js URL SYSTEM DEVICE AXIS...\n");
    process.exit(2);
}

async function main() {
    let problem = null;
    const { client, session } = await connect(url, "skillcell-robotics", (m) => { problem = m; });
    try {
        const ns = {};
        for (const [key, uri] of [["di", DI], ["rob", ROBOTICS]]) {
            const { index } = await resolveNamespaceIndex(session, uri);
            if (index < 0) throw new Error(`namespace ${uri} missing`);
            ns[key] = index;
        }
        // The server's own names (system, device, axes) are in namespace 1.
        const devicePath =
            `/${ns.di}:DeviceSet/1:${system}/${ns.rob}:MotionDevices/1:${device}`;
        const resolve = async (path) => {
            const r = await session.translateBrowsePath(makeBrowsePath("ObjectsFolder", path));
            if (r.statusCode !== StatusCodes.Good || !r.targets || r.targets.length !== 1) {
                throw new Error(`${path}: ${r.statusCode.toString()}`);
            }
            return r.targets[0].targetId;
        };
        const read = async (path) => {
            const dv = await session.read({ nodeId: await resolve(path),
                                            attributeId: AttributeIds.Value });
            if (dv.statusCode.isNotGood()) throw new Error(`${path}: ${dv.statusCode.toString()}`);
            return dv.value.value;
        };
        const manufacturer = await read(`${devicePath}/${ns.di}:Manufacturer`);
        const model = await read(`${devicePath}/${ns.di}:Model`);
        const category = await read(`${devicePath}/${ns.rob}:MotionDeviceCategory`);
        if (!manufacturer || !manufacturer.text) throw new Error("no Manufacturer");
        if (category !== 1) throw new Error(`MotionDeviceCategory ${category}, expected 1`);
        const out = [];
        for (const axis of axes) {
            const position =
                `${devicePath}/${ns.rob}:Axes/1:${axis}/${ns.di}:ParameterSet/${ns.rob}:ActualPosition`;
            const value = await read(position);
            if (typeof value !== "number") throw new Error(`${axis}: ActualPosition ${value}`);
            const eu = await read(`${position}/0:EngineeringUnits`);
            if (!eu || eu.unitId !== RADIAN) {
                throw new Error(`${axis}: EngineeringUnits ${JSON.stringify(eu)}, expected rad`);
            }
            out.push(`${axis}=${value.toFixed(4)}`);
        }
        process.stderr.write(`${manufacturer.text} ${model.text}\n`);
        if (problem) throw new Error(problem);
        console.log(`OK robotics ${out.join(" ")}`);
    } finally {
        await disconnect(client, session);
    }
}

runMain(main, 60);
