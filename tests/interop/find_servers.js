#!/usr/bin/env node
// FindServers, polled with node-opcua's client until a server shows up (or goes away).
//
// usage: node find_servers.js URL EXPECTED_SUBSTRING [--absent] [--timeout S] [--period MS]
//
// Polls every --period ms (default 500) with FindServers (no serverUris filter) and prints the
// ApplicationDescriptions to stderr whenever the list changes, one line each:
// "server <applicationUri> type=<applicationType> name=<applicationName> urls=<discoveryUrls>".
// Succeeds when an entry whose applicationUri, applicationName or one of its discoveryUrls
// contains EXPECTED_SUBSTRING is listed (with --absent: when none is). Last stdout line: "OK ..."
// (exit 0) or, after --timeout seconds (default 30), "FAILED ..." (exit 1).
"use strict";

const { ApplicationType } = require("node-opcua-client");
const { runPollScript } = require("./discovery_common");

const USAGE = "usage: node find_servers.js URL EXPECTED_SUBSTRING [--absent] [--timeout S] [--period MS]";

function describeServer(s) {
    const name = (s.applicationName && s.applicationName.text) || "";
    const urls = (s.discoveryUrls || []).join(",");
    return `server ${s.applicationUri} type=${ApplicationType[s.applicationType]} name=${name} urls=${urls}`;
}

runPollScript({
    usage: USAGE,
    what: "FindServers",
    query: (client, url) => client.findServers({ endpointUrl: url, localeIds: [], serverUris: [] }),
    matches: (s, expected) =>
        `${s.applicationUri || ""}`.includes(expected) ||
        `${(s.applicationName && s.applicationName.text) || ""}`.includes(expected) ||
        (s.discoveryUrls || []).some((u) => `${u}`.includes(expected)),
    describe: describeServer
});
