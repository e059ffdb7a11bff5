// The skill model as any OPC UA client sees it, for node-opcua scripts: browsing, the type
// hierarchy, finding skill objects by type (a subtype counts), a child by browse name.
"use strict";

const { BrowseDirection, NodeClassMask } = require("node-opcua-client");
const { StatusCodes } = require("./common");

async function browse(session, nodeId, options = {}) {
    const result = await session.browse({
        nodeId,
        browseDirection: options.direction ?? BrowseDirection.Forward,
        referenceTypeId: options.referenceTypeId ?? "HierarchicalReferences",
        includeSubtypes: true,
        nodeClassMask: options.nodeClassMask ?? 0,
        resultMask: 63
    });
    if (result.statusCode !== StatusCodes.Good) {
        throw new Error(`browse ${nodeId}: ${result.statusCode.toString()}`);
    }
    return result.references;
}

/// True when `type` is `superType` or one of its subtypes, asking the server.
async function isSubtypeOf(session, type, superType, cache) {
    const key = type.toString();
    if (cache.has(key)) return cache.get(key);
    let result = false;
    let current = type;
    for (let depth = 0; depth < 32 && current; ++depth) {
        if (current.toString() === superType.toString()) { result = true; break; }
        const parents = await browse(session, current,
            { direction: BrowseDirection.Inverse, referenceTypeId: "HasSubtype" });
        current = parents.length ? parents[0].nodeId : null;
    }
    cache.set(key, result);
    return result;
}

async function findSkills(session, skillType) {
    const found = [];
    const cache = new Map();
    const queue = [{ nodeId: "ns=0;i=85", depth: 0 }];
    const seen = new Set();
    while (queue.length) {
        const { nodeId, depth } = queue.shift();
        if (seen.has(nodeId.toString()) || depth > 6) continue;
        seen.add(nodeId.toString());
        for (const ref of await browse(session, nodeId, { nodeClassMask: NodeClassMask.Object })) {
            if (ref.typeDefinition && await isSubtypeOf(session, ref.typeDefinition, skillType, cache)) {
                found.push(ref);
            } else {
                queue.push({ nodeId: ref.nodeId, depth: depth + 1 });
            }
        }
    }
    return found;
}

async function childByName(session, nodeId, name) {
    const refs = await browse(session, nodeId);
    const ref = refs.find((r) => r.browseName.name === name);
    if (!ref) throw new Error(`${nodeId.toString()} has no child ${name}`);
    return ref.nodeId;
}

module.exports = { browse, isSubtypeOf, findSkills, childByName };
