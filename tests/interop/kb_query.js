#!/usr/bin/env node
// node-opcua client using the knowledge base's OPC UA interface (`skillcell kb`):
//   1. finds Objects/KnowledgeBase and its Query and Update methods by browse name;
//   2. Query: every skill type that is a GripperSkillType, as SPARQL JSON results;
//   3. Update: inserts a triple, and Query finds it;
//   4. Load: a graph from Turtle, which Query finds; Turtle with a syntax error is refused
//      (BadSyntaxError) and changes nothing; the KB's own graphs are not for loading;
//   5. a query with a syntax error is refused with BadSyntaxError, a missing argument with
//      BadArgumentsMissing (or BadInvalidArgument).
// usage: node kb_query.js opc.tcp://HOST:PORT
// Prints "OK kb" and exits 0, or prints the failure on stderr and exits 1.
"use strict";

require("./log_to_stderr"); // before node-opcua: keep stdout clean
const { BrowseDirection, DataType, StatusCodes } = require("node-opcua-client");
const { checkEndpointUrl, connect, disconnect } = require("./common");

const url = process.argv[2];
checkEndpointUrl(url, "node kb_query.js opc.tcp://HOST:PORT");

async function childByName(session, parent, name) {
    const result = await session.browse({
        nodeId: parent,
        browseDirection: BrowseDirection.Forward,
        includeSubtypes: true,
        resultMask: 0x3f
    });
    const ref = result.references.find((r) => r.browseName.name === name);
    if (!ref) throw new Error(`no ${name} below ${parent.toString()}`);
    return ref.nodeId;
}

const str = (value) => ({ dataType: DataType.String, value });

async function main() {
    const { client, session } = await connect(url, "skillcell kb interop");
    try {
        const kb = await childByName(session, "i=85", "KnowledgeBase");
        const query = await childByName(session, kb, "Query");
        const update = await childByName(session, kb, "Update");
        const load = await childByName(session, kb, "Load");

        const gripperTypes =
            "SELECT ?t WHERE { ?t <http://www.w3.org/2000/01/rdf-schema#subClassOf>+ " +
            "<http://skillcell.dev/UA/GripperSkills/GripperSkillType> }";
        let r = await session.call({ objectId: kb, methodId: query, inputArguments: [str(gripperTypes), str("")] });
        if (r.statusCode !== StatusCodes.Good) throw new Error(`Query: ${r.statusCode.toString()}`);
        const [result, contentType] = r.outputArguments.map((v) => v.value);
        if (!String(contentType).includes("sparql-results+json")) throw new Error(`content type ${contentType}`);
        const json = JSON.parse(result);
        const types = json.results.bindings.map((b) => b.t.value).sort();
        for (const t of ["GraspGripperSkillType", "MoveGripperSkillType", "ReleaseGripperSkillType"]) {
            if (!types.includes(`http://skillcell.dev/UA/GripperSkills/${t}`)) {
                throw new Error(`Query: ${t} missing from ${types.join(", ")}`);
            }
        }

        r = await session.call({
            objectId: kb,
            methodId: update,
            inputArguments: [str('INSERT DATA { GRAPH <urn:node:test> { <urn:node:a> <urn:node:p> "from node-opcua" } }')]
        });
        if (r.statusCode !== StatusCodes.Good) throw new Error(`Update: ${r.statusCode.toString()}`);
        r = await session.call({
            objectId: kb,
            methodId: query,
            inputArguments: [str('ASK { GRAPH <urn:node:test> { <urn:node:a> <urn:node:p> "from node-opcua" } }'), str("")]
        });
        if (r.statusCode !== StatusCodes.Good || !JSON.parse(r.outputArguments[0].value).boolean) {
            throw new Error("the update is not visible to a query");
        }

        const ask = async (pattern) => {
            const a = await session.call({ objectId: kb, methodId: query, inputArguments: [str(`ASK { ${pattern} }`), str("")] });
            if (a.statusCode !== StatusCodes.Good) throw new Error(`ASK: ${a.statusCode.toString()}`);
            return JSON.parse(a.outputArguments[0].value).boolean;
        };
        const graph = "http://skillcell.dev/processes/node";
        r = await session.call({
            objectId: kb,
            methodId: load,
            inputArguments: [str(graph), str('<urn:node:b> <urn:node:p> "loaded by node-opcua" .')]
        });
        if (r.statusCode !== StatusCodes.Good) throw new Error(`Load: ${r.statusCode.toString()}`);
        if (!(await ask(`GRAPH <${graph}> { <urn:node:b> <urn:node:p> "loaded by node-opcua" }`))) {
            throw new Error("the loaded graph is not visible to a query");
        }
        r = await session.call({ objectId: kb, methodId: load, inputArguments: [str(graph), str("<urn:node:c> <urn:node:p> .")] });
        if (r.statusCode !== StatusCodes.BadSyntaxError) {
            throw new Error(`Load of broken Turtle gave ${r.statusCode.toString()}, expected BadSyntaxError`);
        }
        if (!(await ask(`GRAPH <${graph}> { <urn:node:b> <urn:node:p> "loaded by node-opcua" }`))) {
            throw new Error("a refused Load changed the graph");
        }
        r = await session.call({ objectId: kb, methodId: load, inputArguments: [str("urn:skillcell:kb:graphs"), str("")] });
        if (r.statusCode !== StatusCodes.BadInvalidArgument) {
            throw new Error(`Load into the KB's registry gave ${r.statusCode.toString()}, expected BadInvalidArgument`);
        }

        r = await session.call({ objectId: kb, methodId: query, inputArguments: [str("SELECT ?x WHERE { ?x"), str("")] });
        if (r.statusCode !== StatusCodes.BadSyntaxError) {
            throw new Error(`a syntax error gave ${r.statusCode.toString()}, expected BadSyntaxError`);
        }
        r = await session.call({ objectId: kb, methodId: query, inputArguments: [] });
        if (r.statusCode !== StatusCodes.BadArgumentsMissing && r.statusCode !== StatusCodes.BadInvalidArgument) {
            throw new Error(`no arguments gave ${r.statusCode.toString()}`);
        }
        console.log("OK kb");
    } finally {
        await disconnect(client, session);
    }
}

const timer = setTimeout(() => {
    console.error("timeout");
    process.exit(1);
}, 60000);
main()
    .then(() => {
        clearTimeout(timer);
        process.exit(0);
    })
    .catch((err) => {
        console.error(`FAILED: ${err.message}`);
        process.exit(1);
    });
