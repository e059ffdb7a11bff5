#!/usr/bin/env node
// FindServersOnNetwork, polled with node-opcua's client until a record shows up (or goes away).
//
// usage: node find_servers_on_network.js LDS_URL EXPECTED_SUBSTRING [--absent] [--timeout S]
//                                        [--period MS]
//
// Polls the LDS every --period ms (default 500) with FindServersOnNetwork(startingRecordId 0,
// no limit, no capability filter) and prints the records to stderr whenever the list changes,
// one line each: "record <recordId> <serverName> <discoveryUrl> caps=<a,b>".
// Succeeds when a record whose serverName or discoveryUrl contains EXPECTED_SUBSTRING is listed
// (with --absent: when none is). Last stdout line: "OK ..." (exit 0) or, after --timeout seconds
// (default 30), "FAILED ..." (exit 1). No session is created: the service needs none.
"use strict";

const { runPollScript } = require("./discovery_common");

const USAGE =
    "usage: node find_servers_on_network.js LDS_URL EXPECTED_SUBSTRING [--absent] [--timeout S] [--period MS]";

function describeRecord(r) {
    const caps = (r.serverCapabilities || []).join(",");
    return `record ${r.recordId} ${r.serverName} ${r.discoveryUrl} caps=${caps}`;
}

runPollScript({
    usage: USAGE,
    what: "FindServersOnNetwork",
    query: (client) =>
        client.findServersOnNetwork({ startingRecordId: 0, maxRecordsToReturn: 0, serverCapabilityFilter: [] }),
    matches: (r, expected) =>
        `${r.serverName || ""}`.includes(expected) || `${r.discoveryUrl || ""}`.includes(expected),
    describe: describeRecord
});
