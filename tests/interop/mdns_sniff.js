#!/usr/bin/env node
// Debugging aid for the discovery interop tests: prints every mDNS packet seen on
// 224.0.0.251:5353, one line per resource record, section by section, e.g.
//   +1.234s response from 127.0.0.1:5353 flags=0x400
//     answer     PTR  _opcua-tcp._tcp.local ttl=28800 -> ours-under-test._opcua-tcp._tcp.local
//     additional SRV  ours-under-test._opcua-tcp._tcp.local ttl=120 -> host.local:4840
// Listens only (sends nothing); inside a private network namespace it sees all the traffic.
// The first stdout line, "READY mdns 224.0.0.251:5353", says that it has joined the group.
//
// usage: node mdns_sniff.js [--duration S]     (default: until SIGTERM/SIGINT)
"use strict";

const multicastDns = require("multicast-dns");
const { parseArgs, requirePrivateNetwork } = require("./discovery_common");

const USAGE = "usage: node mdns_sniff.js [--duration S]";
const { opts } = parseArgs(process.argv.slice(2), { "--duration": "number" }, USAGE, 0);
requirePrivateNetwork("mdns_sniff.js");

const t0 = Date.now();
const mdns = multicastDns({ loopback: true });

function data(rr) {
    const d = rr.data;
    switch (rr.type) {
        case "SRV":
            return `${d.target}:${d.port} prio=${d.priority || 0} weight=${d.weight || 0}`;
        case "TXT":
            return (Array.isArray(d) ? d : [d]).map((b) => JSON.stringify(Buffer.from(b).toString())).join(" ");
        default:
            return typeof d === "object" ? JSON.stringify(d) : String(d);
    }
}

mdns.on("packet", (packet, rinfo) => {
    const t = ((Date.now() - t0) / 1000).toFixed(3);
    const lines = [`+${t}s ${packet.type} from ${rinfo.address}:${rinfo.port} id=${packet.id} flags=0x${(packet.flags || 0).toString(16)}`];
    for (const q of packet.questions || []) {
        lines.push(`  question   ${q.type.padEnd(4)} ${q.name}${q.class === "UNKNOWN_32769" || q.class === 32769 ? " (QU)" : ""}`);
    }
    for (const [section, rrs] of [
        ["answer", packet.answers],
        ["authority", packet.authorities],
        ["additional", packet.additionals]
    ]) {
        for (const rr of rrs || []) {
            lines.push(`  ${section.padEnd(10)} ${String(rr.type).padEnd(4)} ${rr.name} ttl=${rr.ttl}${rr.flush ? " flush" : ""} -> ${data(rr)}`);
        }
    }
    process.stdout.write(lines.join("\n") + "\n");
});
mdns.on("ready", () => process.stdout.write("READY mdns 224.0.0.251:5353\n"));
mdns.on("warning", (err) => process.stderr.write(`mdns_sniff.js: warning: ${err.message}\n`));
mdns.on("error", (err) => {
    process.stderr.write(`mdns_sniff.js: ${err.message}\n`);
    process.exit(1);
});

const stop = () => mdns.destroy(() => process.exit(0));
process.on("SIGTERM", stop);
process.on("SIGINT", stop);
if (opts.duration !== undefined) setTimeout(stop, opts.duration * 1000);
