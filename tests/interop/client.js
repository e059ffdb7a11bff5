#!/usr/bin/env node
// node-opcua conformance client for the skillcell interop tests.
//
// usage: node client.js opc.tcp://HOST:PORT [--skip-method] [--strict] [--max-refs N] [--no-demo]
//
//   (a) browses recursively from RootFolder (i=84), forward HierarchicalReferences
//       (and subtypes), following BrowseNext continuation points; cycle-safe; at
//       most 20000 nodes
//   (b) reads every attribute id 1..27 of every node found
//   (c) write / read-back checks on the ns=<urn:skillcell:demo>;s=Demo.* variables
//   (d) Demo.Add method calls (skipped with --skip-method)
//   (e) prints "OK nodes=N attributes=M" and exits 0, or prints every failure on
//       stderr and exits 1. The whole run is bounded by a 60 s timeout.
//
// --strict     additionally checks, per NodeClass, that mandatory attributes
//              exist, that attributes foreign to the NodeClass are reported as
//              BadAttributeIdInvalid, and that no attribute read says
//              BadNodeIdUnknown for a node the server itself returned.
// --no-demo    a server without the Demo namespace (a device): (c) and (d) are skipped.
// --max-refs N requestedMaxReferencesPerNode for Browse (default 0 = server
//              decides); a small N forces continuation points / BrowseNext.
"use strict";

require("./log_to_stderr"); // before node-opcua: keep stdout clean
const {
    AttributeIds,
    BrowseDirection,
    DataType,
    NodeClass,
    NodeId,
    StatusCodes,
    VariantArrayType,
    resolveNodeId
} = require("node-opcua-client");
const {
    DEMO_NAMESPACE_URI,
    checkEndpointUrl,
    connect,
    disconnect,
    resolveNamespaceIndex,
    stringNodeId
} = require("./common");

const USAGE = "usage: node client.js opc.tcp://HOST:PORT [--skip-method] [--strict] [--max-refs N] [--no-demo]";
const OVERALL_TIMEOUT_MS = 60000;
const MAX_NODES = 20000;
const ROOT_FOLDER = "ns=0;i=84";
const HIERARCHICAL_REFERENCES = "ns=0;i=33";
const BROWSE_BATCH_DEFAULT = 100; // nodes per Browse request
const READ_BATCH_DEFAULT = 27 * 20; // ReadValueIds per Read request
const MAX_ATTRIBUTE_ID = 27;
const OP_LIMIT_MAX_NODES_PER_READ = "ns=0;i=11705";
const OP_LIMIT_MAX_NODES_PER_BROWSE = "ns=0;i=11710";

const ATTRIBUTE_NAMES = [
    "", "NodeId", "NodeClass", "BrowseName", "DisplayName", "Description", "WriteMask",
    "UserWriteMask", "IsAbstract", "Symmetric", "InverseName", "ContainsNoLoops",
    "EventNotifier", "Value", "DataType", "ValueRank", "ArrayDimensions", "AccessLevel",
    "UserAccessLevel", "MinimumSamplingInterval", "Historizing", "Executable",
    "UserExecutable", "DataTypeDefinition", "RolePermissions", "UserRolePermissions",
    "AccessRestrictions", "AccessLevelEx"
];

// --strict tables (OPC UA Part 3, chapter 5): attributes each NodeClass may
// have, and the mandatory ones among them.
const COMMON_ATTRS = [1, 2, 3, 4, 5, 6, 7, 24, 25, 26];
const CLASS_ATTRS = {
    [NodeClass.Object]: { allowed: [12], mandatory: [12] },
    [NodeClass.Variable]: { allowed: [13, 14, 15, 16, 17, 18, 19, 20, 27], mandatory: [13, 14, 15, 17, 18, 20] },
    [NodeClass.Method]: { allowed: [21, 22], mandatory: [21, 22] },
    [NodeClass.ObjectType]: { allowed: [8], mandatory: [8] },
    [NodeClass.VariableType]: { allowed: [8, 13, 14, 15, 16], mandatory: [8, 14, 15] },
    [NodeClass.ReferenceType]: { allowed: [8, 9, 10], mandatory: [8, 9] },
    [NodeClass.DataType]: { allowed: [8, 23], mandatory: [8] },
    [NodeClass.View]: { allowed: [11, 12], mandatory: [11, 12] }
};

// ---------------------------------------------------------------------------

const failures = [];
function fail(msg) {
    failures.push(msg);
}

function parseArgs(argv) {
    const opts = { url: null, skipMethod: false, strict: false, maxRefs: 0, demo: true };
    for (let i = 0; i < argv.length; i++) {
        const a = argv[i];
        if (a === "--skip-method") opts.skipMethod = true;
        else if (a === "--no-demo") opts.demo = false;
        else if (a === "--strict") opts.strict = true;
        else if (a === "--max-refs" && i + 1 < argv.length) opts.maxRefs = Number(argv[++i]);
        else if (a === "-h" || a === "--help") {
            process.stdout.write(USAGE + "\n");
            process.exit(0);
        } else if (!a.startsWith("--") && opts.url === null) opts.url = a;
        else {
            process.stderr.write(`client.js: unknown argument '${a}'\n${USAGE}\n`);
            process.exit(2);
        }
    }
    checkEndpointUrl(opts.url, USAGE);
    if (!Number.isInteger(opts.maxRefs) || opts.maxRefs < 0) {
        process.stderr.write(`client.js: --max-refs needs a non-negative integer\n`);
        process.exit(2);
    }
    return opts;
}

// Bad status codes are compared on their code part (upper 16 bits) only.
function codeOf(sc) {
    return (sc.value & 0xffff0000) >>> 0;
}
function is(sc, expected) {
    return codeOf(sc) === codeOf(expected);
}
function scName(sc) {
    return `${sc.name} (0x${(sc.value >>> 0).toString(16).padStart(8, "0")})`;
}

function chunk(array, size) {
    const out = [];
    for (let i = 0; i < array.length; i += size) out.push(array.slice(i, i + size));
    return out;
}

// Reads an optional UInt32 operation limit; 0 / missing / bad means "no limit".
async function readOperationLimit(session, nodeId) {
    try {
        const dv = await session.read({ nodeId, attributeId: AttributeIds.Value });
        if (dv.statusCode.isGood() && dv.value && typeof dv.value.value === "number") {
            return dv.value.value;
        }
    } catch (err) {
        // a server without the OperationLimits object is fine
    }
    return 0;
}

// ---------------------------------------------------------------------------
// (a) recursive browse

// Turns a ReferenceDescription's target ExpandedNodeId into a local NodeId,
// or null when it points to another server / an unknown namespace URI.
function localTarget(expanded, namespaces) {
    if (expanded.serverIndex && expanded.serverIndex !== 0) return null;
    let ns = expanded.namespace;
    if (expanded.namespaceUri) {
        ns = namespaces.indexOf(expanded.namespaceUri);
        if (ns < 0) return null;
    }
    return new NodeId(expanded.identifierType, expanded.value, ns);
}

async function browseAll(session, namespaces, opts, browseBatch) {
    session.requestedMaxReferencesPerNode = opts.maxRefs;

    // key -> { nodeId, nodeClass, browseName, parent }; nodeClass/browseName as
    // announced by the reference that led to the node (root: from nothing).
    const found = new Map();
    const rootId = resolveNodeId(ROOT_FOLDER);
    found.set(rootId.toString(), { nodeId: rootId, nodeClass: NodeClass.Object, browseName: null });
    let queue = [rootId];
    let capped = false;
    const stats = { browseRequests: 0, browseNextRequests: 0, references: 0, continuationPoints: 0, vanished: 0 };
    const browseSuspects = []; // nodes that Browse said BadNodeIdUnknown for

    const description = (nodeId) => ({
        nodeId,
        browseDirection: BrowseDirection.Forward,
        referenceTypeId: HIERARCHICAL_REFERENCES,
        includeSubtypes: true,
        nodeClassMask: 0,
        resultMask: 0x3f
    });

    const consume = (parent, source, references) => {
        for (const ref of references) {
            stats.references++;
            if (!ref.isForward) {
                fail(`browse ${source}: got an inverse reference in a forward browse (${ref.nodeId.toString()})`);
                continue;
            }
            const target = localTarget(ref.nodeId, namespaces);
            if (!target) continue;
            const key = target.toString();
            if (found.has(key)) continue; // cycle / multiple parents
            if (found.size >= MAX_NODES) {
                capped = true;
                continue;
            }
            found.set(key, { nodeId: target, nodeClass: ref.nodeClass, browseName: ref.browseName, parent });
            queue.push(target);
        }
    };

    // Browses `nodes`, follows all continuation points; returns the nodes the
    // server refused with BadNoContinuationPoints (to be retried one by one).
    const browseBatchOnce = async (nodes) => {
        stats.browseRequests++;
        const results = await session.browse(nodes.map(description));
        if (results.length !== nodes.length) {
            fail(`Browse: asked for ${nodes.length} nodes, got ${results.length} results`);
        }
        const retry = [];
        let pending = [];
        results.forEach((r, i) => {
            const src = nodes[i] ? nodes[i].toString() : `#${i}`;
            if (is(r.statusCode, StatusCodes.BadNoContinuationPoints)) {
                retry.push(nodes[i]);
                return;
            }
            if (is(r.statusCode, StatusCodes.BadNodeIdUnknown) && nodes[i]) {
                browseSuspects.push({ key: src, message: `Browse ${src}: ${scName(r.statusCode)}` });
                return;
            }
            if (r.statusCode.isNotGood()) {
                fail(`Browse ${src}: ${scName(r.statusCode)}`);
                return;
            }
            consume(nodes[i], src, r.references || []);
            if (r.continuationPoint && r.continuationPoint.length > 0) {
                stats.continuationPoints++;
                pending.push({ node: nodes[i], src, cp: r.continuationPoint });
            }
        });
        while (pending.length > 0) {
            if (capped) {
                // release what is left, we will not use it
                stats.browseNextRequests++;
                await session.browseNext(pending.map((p) => p.cp), true);
                break;
            }
            stats.browseNextRequests++;
            const next = await session.browseNext(pending.map((p) => p.cp), false);
            if (next.length !== pending.length) {
                fail(`BrowseNext: sent ${pending.length} continuation points, got ${next.length} results`);
            }
            const again = [];
            next.forEach((r, i) => {
                if (!pending[i]) return;
                const { node, src } = pending[i];
                if (r.statusCode.isNotGood()) {
                    fail(`BrowseNext ${src}: ${scName(r.statusCode)}`);
                    return;
                }
                consume(node, src, r.references || []);
                if (r.continuationPoint && r.continuationPoint.length > 0) {
                    stats.continuationPoints++;
                    again.push({ node, src, cp: r.continuationPoint });
                }
            });
            pending = again;
        }
        return retry;
    };

    while (queue.length > 0 && !capped) {
        const level = queue;
        queue = [];
        for (const batch of chunk(level, browseBatch)) {
            const retry = await browseBatchOnce(batch);
            for (const nodeId of retry) {
                const stillRefused = await browseBatchOnce([nodeId]);
                for (const n of stillRefused) {
                    fail(`Browse ${n.toString()}: BadNoContinuationPoints even when browsed alone`);
                }
            }
            if (capped) break;
        }
    }
    // see readAllAttributes: tolerated only if the node is really gone
    for (const { key, message } of browseSuspects) {
        const node = found.get(key);
        if (node && node.parent && !(await parentStillReferences(session, node.parent, key))) {
            stats.vanished++;
        } else {
            fail(message);
        }
    }
    return { found, capped, stats };
}

// ---------------------------------------------------------------------------
// (b) read every attribute of every node

// true when a forward hierarchical browse of `parent` still returns `key`.
async function parentStillReferences(session, parent, key) {
    const saved = session.requestedMaxReferencesPerNode;
    session.requestedMaxReferencesPerNode = 0;
    try {
        let r = await session.browse({
            nodeId: parent,
            browseDirection: BrowseDirection.Forward,
            referenceTypeId: HIERARCHICAL_REFERENCES,
            includeSubtypes: true,
            nodeClassMask: 0,
            resultMask: 0
        });
        for (;;) {
            if (r.statusCode.isNotGood()) return false;
            const local = (e) => new NodeId(e.identifierType, e.value, e.namespace).toString();
            if ((r.references || []).some((ref) => local(ref.nodeId) === key)) {
                if (r.continuationPoint && r.continuationPoint.length > 0) {
                    await session.browseNext(r.continuationPoint, true);
                }
                return true;
            }
            if (!r.continuationPoint || r.continuationPoint.length === 0) return false;
            r = await session.browseNext(r.continuationPoint, false);
        }
    } finally {
        session.requestedMaxReferencesPerNode = saved;
    }
}

function sameQualifiedName(a, b) {
    return a && b && a.namespaceIndex === b.namespaceIndex && a.name === b.name;
}

async function readAllAttributes(session, found, opts, readBatch) {
    const nodes = Array.from(found.values());
    const items = [];
    for (const node of nodes) {
        for (let attributeId = 1; attributeId <= MAX_ATTRIBUTE_ID; attributeId++) {
            items.push({ node, attributeId });
        }
    }
    const stats = { reads: 0, existing: 0, readRequests: 0, otherBad: new Map(), vanished: 0 };
    // nodes whose mandatory attributes said BadNodeIdUnknown: key -> messages
    const suspects = new Map();
    // per node: attributeId -> statusCode, for the --strict checks
    const perNode = new Map();

    for (const part of chunk(items, readBatch)) {
        stats.readRequests++;
        const dataValues = await session.read(
            part.map((it) => ({ nodeId: it.node.nodeId, attributeId: it.attributeId })),
            0
        );
        if (dataValues.length !== part.length) {
            fail(`Read: asked for ${part.length} attributes, got ${dataValues.length} results`);
            continue;
        }
        dataValues.forEach((dv, i) => {
            const { node, attributeId } = part[i];
            const key = node.nodeId.toString();
            const where = `${key} ${ATTRIBUTE_NAMES[attributeId]}(${attributeId})`;
            const sc = dv.statusCode;
            stats.reads++;
            if (!perNode.has(key)) perNode.set(key, new Map());
            perNode.get(key).set(attributeId, sc);

            if (is(sc, StatusCodes.BadAttributeIdInvalid)) {
                if (attributeId <= 4) fail(`Read ${where}: mandatory attribute reported as ${scName(sc)}`);
                return;
            }
            stats.existing++;
            if (sc.isNotGood()) {
                if (is(sc, StatusCodes.BadNodeIdUnknown) && (attributeId <= 4 || opts.strict)) {
                    if (!suspects.has(key)) suspects.set(key, []);
                    suspects.get(key).push(`Read ${where}: ${scName(sc)}`);
                } else if (attributeId <= 4) {
                    fail(`Read ${where}: ${scName(sc)}`);
                } else {
                    const k = `${ATTRIBUTE_NAMES[attributeId]}:${sc.name}`;
                    stats.otherBad.set(k, (stats.otherBad.get(k) || 0) + 1);
                    if (opts.strict && is(sc, StatusCodes.BadNodeIdInvalid)) {
                        fail(`Read ${where}: ${scName(sc)} for a node returned by Browse`);
                    }
                }
                return;
            }
            const v = dv.value ? dv.value.value : undefined;
            switch (attributeId) {
                case AttributeIds.NodeId:
                    if (!(v instanceof NodeId) || !v.toString || v.toString() !== key) {
                        fail(`Read ${where}: value ${v && v.toString ? v.toString() : v} differs from the browsed NodeId`);
                    }
                    break;
                case AttributeIds.NodeClass:
                    if (typeof v !== "number" || !Number.isInteger(v) || !(v in CLASS_ATTRS)) {
                        fail(`Read ${where}: invalid NodeClass value ${v}`);
                    } else if (node.nodeClass && node.nodeClass !== v) {
                        fail(`Read ${where}: ${NodeClass[v]} but the reference said ${NodeClass[node.nodeClass]}`);
                    } else {
                        node.readNodeClass = v;
                    }
                    break;
                case AttributeIds.BrowseName:
                    if (!v || typeof v.name !== "string" || v.name.length === 0) {
                        fail(`Read ${where}: empty or invalid QualifiedName`);
                    } else if (node.browseName && !sameQualifiedName(node.browseName, v)) {
                        fail(`Read ${where}: ${v.toString()} but the reference said ${node.browseName.toString()}`);
                    }
                    break;
                case AttributeIds.DisplayName:
                    if (!v || typeof v.text !== "string") {
                        fail(`Read ${where}: invalid LocalizedText`);
                    }
                    break;
                default:
                    break;
            }
        });
    }

    // A node may legitimately disappear between Browse and Read (node-opcua,
    // for one, exposes a diagnostics object per session, gone once that
    // session closes). Such a node is only tolerated when browsing its
    // parent again no longer returns it.
    for (const [key, messages] of suspects) {
        const node = found.get(key);
        const stillThere = node.parent ? await parentStillReferences(session, node.parent, key) : true;
        if (stillThere) {
            messages.forEach(fail);
        } else {
            stats.vanished++;
            perNode.delete(key);
        }
    }

    if (opts.strict) {
        for (const node of nodes) {
            const key = node.nodeId.toString();
            const cls = node.readNodeClass;
            const table = CLASS_ATTRS[cls];
            const codes = perNode.get(key);
            if (!table || !codes) continue;
            const allowed = new Set([...COMMON_ATTRS, ...table.allowed]);
            for (let attributeId = 1; attributeId <= MAX_ATTRIBUTE_ID; attributeId++) {
                const sc = codes.get(attributeId);
                if (!sc) continue;
                const invalid = is(sc, StatusCodes.BadAttributeIdInvalid);
                const where = `${key} (${NodeClass[cls]}) ${ATTRIBUTE_NAMES[attributeId]}(${attributeId})`;
                if (table.mandatory.includes(attributeId) && invalid) {
                    fail(`strict: ${where} is mandatory but reported BadAttributeIdInvalid`);
                }
                if (!allowed.has(attributeId) && !invalid) {
                    fail(`strict: ${where} does not exist for this NodeClass but reported ${scName(sc)}`);
                }
            }
        }
    }
    return stats;
}

// ---------------------------------------------------------------------------
// (c) Demo variables

const DEMO_VARIABLES = [
    // name, expected DataType NodeId (ns=0 numeric), valueRank
    ["Demo.Double", DataType.Double, -1],
    ["Demo.Int32", DataType.Int32, -1],
    ["Demo.String", DataType.String, -1],
    ["Demo.Boolean", DataType.Boolean, -1],
    ["Demo.DoubleArray", DataType.Double, 1],
    ["Demo.ReadOnly", DataType.UInt32, -1]
];

async function readValue(session, nodeId) {
    return session.read({ nodeId, attributeId: AttributeIds.Value });
}

async function writeValue(session, nodeId, variant) {
    return session.write({ nodeId, attributeId: AttributeIds.Value, value: { value: variant } });
}

function sameValue(actual, expected) {
    if (Array.isArray(expected)) {
        if (!actual || typeof actual.length !== "number" || actual.length !== expected.length) return false;
        return expected.every((x, i) => actual[i] === x);
    }
    return actual === expected;
}

function show(v) {
    if (v && typeof v === "object" && typeof v.length === "number") return `[${Array.from(v).join(",")}]`;
    return JSON.stringify(v);
}

async function writeAndCheck(session, ns, name, dataType, value, isArray) {
    const nodeId = stringNodeId(ns, name);
    const variant = isArray
        ? { dataType, arrayType: VariantArrayType.Array, value }
        : { dataType, value };
    const sc = await writeValue(session, nodeId, variant);
    if (sc.isNotGood()) {
        fail(`Write ${name} = ${show(value)}: ${scName(sc)}`);
        return;
    }
    const dv = await readValue(session, nodeId);
    if (dv.statusCode.isNotGood()) {
        fail(`Read back ${name}: ${scName(dv.statusCode)}`);
        return;
    }
    const got = dv.value;
    if (!got || got.dataType !== dataType) {
        fail(`Read back ${name}: dataType ${got ? DataType[got.dataType] : "none"}, expected ${DataType[dataType]}`);
        return;
    }
    const gotIsArray = got.arrayType === VariantArrayType.Array;
    if (gotIsArray !== Boolean(isArray)) {
        fail(`Read back ${name}: arrayType ${VariantArrayType[got.arrayType]}, expected ${isArray ? "Array" : "Scalar"}`);
        return;
    }
    if (!sameValue(got.value, value)) {
        fail(`Read back ${name}: ${show(got.value)}, expected ${show(value)}`);
    }
}

async function checkDemoVariables(session, ns, found) {
    const demo = stringNodeId(ns, "Demo");
    if (!found.has(demo.toString())) {
        fail(`${demo.toString()} was not reached by the browse from RootFolder`);
    }
    for (const [name, dataType, valueRank] of DEMO_VARIABLES) {
        const nodeId = stringNodeId(ns, name);
        const key = nodeId.toString();
        if (!found.has(key)) fail(`${key} was not reached by the browse from RootFolder`);
        const [dt, vr, nc] = await session.read([
            { nodeId, attributeId: AttributeIds.DataType },
            { nodeId, attributeId: AttributeIds.ValueRank },
            { nodeId, attributeId: AttributeIds.NodeClass }
        ]);
        if (nc.statusCode.isNotGood() || nc.value.value !== NodeClass.Variable) {
            fail(`${key}: NodeClass ${nc.statusCode.isGood() ? NodeClass[nc.value.value] : scName(nc.statusCode)}, expected Variable`);
            continue;
        }
        const dtId = dt.statusCode.isGood() ? dt.value.value : null;
        if (!dtId || dtId.namespace !== 0 || dtId.value !== dataType) {
            fail(`${key}: DataType ${dtId ? dtId.toString() : scName(dt.statusCode)}, expected i=${dataType} (${DataType[dataType]})`);
        }
        if (vr.statusCode.isNotGood() || vr.value.value !== valueRank) {
            fail(`${key}: ValueRank ${vr.statusCode.isGood() ? vr.value.value : scName(vr.statusCode)}, expected ${valueRank}`);
        }
    }

    await writeAndCheck(session, ns, "Demo.Double", DataType.Double, 3.25, false);
    await writeAndCheck(session, ns, "Demo.Int32", DataType.Int32, -7, false);
    await writeAndCheck(session, ns, "Demo.String", DataType.String, "h\u00e9llo w\u00f6rld \u2713", false);
    await writeAndCheck(session, ns, "Demo.Boolean", DataType.Boolean, false, false);
    await writeAndCheck(session, ns, "Demo.DoubleArray", DataType.Double, [0.5, -1, 1e300, 4], true);

    const ro = stringNodeId(ns, "Demo.ReadOnly");
    const before = await readValue(session, ro);
    if (before.statusCode.isNotGood()) fail(`Read Demo.ReadOnly: ${scName(before.statusCode)}`);
    const sc = await writeValue(session, ro, { dataType: DataType.UInt32, value: 8 });
    if (!is(sc, StatusCodes.BadNotWritable) && !is(sc, StatusCodes.BadUserAccessDenied)) {
        fail(`Write Demo.ReadOnly: ${scName(sc)}, expected BadNotWritable or BadUserAccessDenied`);
    }
    const after = await readValue(session, ro);
    if (after.statusCode.isGood() && before.statusCode.isGood() && after.value.value !== before.value.value) {
        fail(`Demo.ReadOnly changed from ${before.value.value} to ${after.value.value} although the write should have been refused`);
    }
}

// ---------------------------------------------------------------------------
// (d) Demo.Add

async function checkDemoMethod(session, ns) {
    const objectId = stringNodeId(ns, "Demo");
    const methodId = stringNodeId(ns, "Demo.Add");
    const dbl = (value) => ({ dataType: DataType.Double, value });

    const ok = await session.call({ objectId, methodId, inputArguments: [dbl(2), dbl(3.5)] });
    if (ok.statusCode.isNotGood()) {
        fail(`Call Demo.Add(2, 3.5): ${scName(ok.statusCode)}`);
    } else {
        const out = ok.outputArguments || [];
        if (out.length !== 1) {
            fail(`Call Demo.Add(2, 3.5): ${out.length} output arguments, expected 1`);
        } else if (out[0].dataType !== DataType.Double || out[0].value !== 5.5) {
            fail(`Call Demo.Add(2, 3.5): got ${DataType[out[0].dataType]} ${show(out[0].value)}, expected Double 5.5`);
        }
    }

    const missing = await session.call({ objectId, methodId, inputArguments: [dbl(2)] });
    if (!is(missing.statusCode, StatusCodes.BadArgumentsMissing)) {
        fail(`Call Demo.Add(2): ${scName(missing.statusCode)}, expected BadArgumentsMissing`);
    }

    const tooMany = await session.call({ objectId, methodId, inputArguments: [dbl(1), dbl(2), dbl(3)] });
    if (!is(tooMany.statusCode, StatusCodes.BadTooManyArguments)) {
        fail(`Call Demo.Add(1, 2, 3): ${scName(tooMany.statusCode)}, expected BadTooManyArguments`);
    }

    const wrongType = await session.call({
        objectId,
        methodId,
        inputArguments: [{ dataType: DataType.String, value: "2" }, dbl(3.5)]
    });
    if (!is(wrongType.statusCode, StatusCodes.BadTypeMismatch) && !is(wrongType.statusCode, StatusCodes.BadInvalidArgument)) {
        fail(`Call Demo.Add("2", 3.5): ${scName(wrongType.statusCode)}, expected BadTypeMismatch or BadInvalidArgument`);
    } else {
        // Part 4 5.11.2: inputArgumentResults tells which argument was wrong
        const iar = wrongType.inputArgumentResults || [];
        if (iar.length > 0 && (iar.length !== 2 || iar[0].isGood())) {
            fail(`Call Demo.Add("2", 3.5): inputArgumentResults [${iar.map((s) => s.name).join(",")}] do not flag argument 0`);
        }
    }
}

// ---------------------------------------------------------------------------

async function main() {
    const opts = parseArgs(process.argv.slice(2));
    const t0 = Date.now();
    let client = null;
    let session = null;
    let nodes = 0;
    let attributes = 0;
    try {
        ({ client, session } = await connect(opts.url, "skillcell-interop-client", fail));

        const { index: ns, namespaces } = await resolveNamespaceIndex(session, DEMO_NAMESPACE_URI);
        if (ns < 0 && opts.demo) fail(`namespace ${DEMO_NAMESPACE_URI} not in NamespaceArray [${namespaces.join(", ")}]`);

        const maxBrowse = await readOperationLimit(session, OP_LIMIT_MAX_NODES_PER_BROWSE);
        const maxRead = await readOperationLimit(session, OP_LIMIT_MAX_NODES_PER_READ);
        const browseBatch = maxBrowse > 0 ? Math.min(maxBrowse, BROWSE_BATCH_DEFAULT) : BROWSE_BATCH_DEFAULT;
        const readBatch = maxRead > 0 ? Math.min(maxRead, READ_BATCH_DEFAULT) : READ_BATCH_DEFAULT;

        const { found, capped, stats: bs } = await browseAll(session, namespaces, opts, browseBatch);
        nodes = found.size;
        process.stdout.write(
            `browsed nodes=${nodes} references=${bs.references} browse_requests=${bs.browseRequests} ` +
                `browse_next_requests=${bs.browseNextRequests} continuation_points=${bs.continuationPoints}` +
                `${bs.vanished ? ` vanished_nodes=${bs.vanished}` : ""}${capped ? ` (capped at ${MAX_NODES})` : ""}\n`
        );

        const rs = await readAllAttributes(session, found, opts, readBatch);
        attributes = rs.existing;
        process.stdout.write(
            `read attribute_reads=${rs.reads} existing=${rs.existing} read_requests=${rs.readRequests}` +
                `${rs.vanished ? ` vanished_nodes=${rs.vanished}` : ""}\n`
        );
        if (rs.otherBad.size > 0) {
            const parts = Array.from(rs.otherBad.entries()).map(([k, n]) => `${k}=${n}`);
            process.stdout.write(`info: non-Good optional attributes: ${parts.join(" ")}\n`);
        }

        if (ns >= 0) {
            await checkDemoVariables(session, ns, found);
            if (!opts.skipMethod) await checkDemoMethod(session, ns);
        }
    } catch (err) {
        fail(`exception: ${err && err.stack ? err.stack : err}`);
    }
    try {
        await disconnect(client, session);
    } catch (err) {
        fail(`exception while closing: ${err && err.message ? err.message : err}`);
    }

    const seconds = ((Date.now() - t0) / 1000).toFixed(1);
    if (failures.length > 0) {
        for (const f of failures) process.stderr.write(`FAIL ${f}\n`);
        process.stdout.write(`FAILED failures=${failures.length} nodes=${nodes} attributes=${attributes} seconds=${seconds}\n`);
        return 1;
    }
    process.stdout.write(`OK nodes=${nodes} attributes=${attributes} seconds=${seconds}\n`);
    return 0;
}

const watchdog = setTimeout(() => {
    for (const f of failures) process.stderr.write(`FAIL ${f}\n`);
    process.stderr.write(`FAIL overall timeout of ${OVERALL_TIMEOUT_MS / 1000} s exceeded\n`);
    process.exit(1);
}, OVERALL_TIMEOUT_MS);

main().then(
    (code) => {
        clearTimeout(watchdog);
        process.exit(code);
    },
    (err) => {
        process.stderr.write(`FAIL unexpected: ${err && err.stack ? err.stack : err}\n`);
        process.exit(1);
    }
);
