#!/usr/bin/env bash
# mDNS over IPv6 (ff02::fb) alone: two hosts (see lib.sh), both ends with --mdns-ip 6, so no
# IPv4 multicast socket exists at all. A watcher on h2 must see the server on h1 announced
# (with its routable IPv4 discovery URL, described over OPC UA) and gone after its goodbye.
# Usage: discovery_ipv6.sh SKILLCELL_BINARY. Needs root; otherwise exit 77 (1 if
# SKILLCELL_REQUIRE_NETNS=1).
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=lib.sh
. "$here/lib.sh"
BIN=$(realpath -- "${1:?usage: discovery_ipv6.sh SKILLCELL_BINARY}")

fail() { netns_fail "$@"; }

netns_trap
netns_setup_or_skip 2

# The link-local addresses must finish duplicate address detection before they can send.
for h in h1 h2; do
  deadline=$(($(now_ms) + 10000))
  until netns_exec "$h" ip -6 addr show dev eth0 scope link | grep -q inet6 &&
      ! netns_exec "$h" ip -6 addr show dev eth0 | grep -q tentative; do
    [ "$(now_ms)" -lt "$deadline" ] || fail "$h has no usable IPv6 link-local address"
    sleep 0.1
  done
done
echo "ok: IPv6 link-local addresses ready"

start_in h2 watcher "$BIN" discover --watch --duration 0 --mdns-ip 6 --mdns-query-period 1
wait_for_line "$NETNS_DIR/watcher.out" '^WATCHING' 10 >/dev/null || fail "watcher did not start"
start_in h1 server "$BIN" server --port 4841 --mdns-ip 6 --mdns-ttl 5 --mdns-query-period 1 \
  --mdns-name v6-server --application-uri urn:test:v6 --pki-dir "$NETNS_DIR/pki-server" --insecure
wait_for_line "$NETNS_DIR/server.out" '^READY' 20 >/dev/null || fail "server did not start"
grep -q "mDNS over IPv4" "$NETNS_DIR/server.err" && fail "the server did not get IPv6 mDNS"

wait_for_line "$NETNS_DIR/watcher.out" \
  '^ANNOUNCED v6-server opc\.tcp://198\.18\.0\.1:4841 urn:test:v6 ' 10 >/dev/null ||
  fail "h2 did not see the server announced over IPv6"
echo "ok: announced over IPv6 and described"

proc_signal server TERM
proc_wait_exit server 10 || fail "server did not exit"
wait_for_line "$NETNS_DIR/watcher.out" '^GONE v6-server goodbye' 5 >/dev/null ||
  fail "h2 did not hear the goodbye over IPv6"
echo "ok: goodbye over IPv6"
echo "PASS"
