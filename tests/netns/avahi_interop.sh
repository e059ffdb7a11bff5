#!/usr/bin/env bash
# mDNS interop with Avahi, an independent implementation of RFC 6762/6763, on two hosts (see
# lib.sh): Avahi's daemon on h1 (with a D-Bus system bus of its own, so that nothing of the
# machine's is touched), a skillcell server and a skillcell watcher on h2.
#   - avahi-browse on h1 resolves the skillcell server: its instance, address, port and TXT;
#   - avahi-browse of the LDS subtype (_lds._sub._opcua-tcp._tcp) resolves a skillcell LDS
#     and not the server;
#   - the skillcell watcher on h2 sees an OPC UA server on h1 that avahi-publish announces for
#     it (and describes it over OPC UA), and sees it gone when avahi-publish stops.
# Usage: avahi_interop.sh SKILLCELL_BINARY. Needs root and Avahi (avahi-daemon, avahi-utils);
# otherwise exit 77 (1 if SKILLCELL_REQUIRE_NETNS=1).
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=lib.sh
. "$here/lib.sh"
BIN=$(realpath -- "${1:?usage: avahi_interop.sh SKILLCELL_BINARY}")

fail() { netns_fail "$@"; }

for tool in avahi-daemon avahi-browse avahi-publish dbus-daemon; do
  if ! command -v "$tool" >/dev/null; then
    echo "!!! SKIPPED: $tool is not installed (Debian: avahi-daemon avahi-utils dbus) !!!" >&2
    [ "${SKILLCELL_REQUIRE_NETNS:-0}" = 1 ] && exit 1
    exit 77
  fi
done

netns_trap
netns_setup_or_skip 2

# A system bus for Avahi alone, reachable only through a socket in this test's directory.
bus="$NETNS_DIR/system_bus_socket"
cat >"$NETNS_DIR/bus.conf" <<CONF
<!DOCTYPE busconfig PUBLIC "-//freedesktop//DTD D-Bus Bus Configuration 1.0//EN"
 "http://www.freedesktop.org/standards/dbus/1.0/busconfig.dtd">
<busconfig>
  <type>system</type>
  <listen>unix:path=$bus</listen>
  <auth>EXTERNAL</auth>
  <policy context="default">
    <allow user="root"/>
    <allow own="*"/>
    <allow send_destination="*"/>
    <allow receive_sender="*"/>
  </policy>
</busconfig>
CONF
cat >"$NETNS_DIR/avahi.conf" <<CONF
[server]
use-ipv4=yes
use-ipv6=no
allow-interfaces=eth0
enable-dbus=yes
ratelimit-interval-usec=0
[publish]
publish-hinfo=no
publish-workstation=no
CONF
export DBUS_SYSTEM_BUS_ADDRESS="unix:path=$bus"
start_in h1 dbus dbus-daemon --nofork --nopidfile --config-file="$NETNS_DIR/bus.conf"
deadline=$(($(now_ms) + 10000))
until [ -S "$bus" ]; do
  [ "$(now_ms)" -lt "$deadline" ] || fail "the private D-Bus did not start"
  sleep 0.05
done
# Avahi keeps its pid file in /run/avahi-daemon: a tmpfs of this namespace's own hides the
# machine's (ip netns exec gives every command a mount namespace of its own).
start_in h1 avahi sh -c 'mkdir -p /run/avahi-daemon && mount -t tmpfs tmpfs /run/avahi-daemon &&
  exec avahi-daemon --no-drop-root --no-chroot --no-rlimits --no-proc-title -f "$0"' \
  "$NETNS_DIR/avahi.conf"
wait_for_line "$NETNS_DIR/avahi.err" 'Server startup complete' 20 >/dev/null ||
  wait_for_line "$NETNS_DIR/avahi.out" 'Server startup complete' 1 >/dev/null ||
  fail "avahi-daemon did not start"
echo "ok: avahi-daemon runs on h1"

start_in h2 watcher "$BIN" discover --watch --duration 0 --mdns-query-period 5
wait_for_line "$NETNS_DIR/watcher.out" '^WATCHING' 10 >/dev/null || fail "watcher did not start"
start_in h2 server "$BIN" server --port 4841 --mdns-ttl 120 --mdns-name skillcell-pump \
  --application-uri urn:test:pump --pki-dir "$NETNS_DIR/pki-server" --insecure
wait_for_line "$NETNS_DIR/server.out" '^READY' 20 >/dev/null || fail "server did not start"

# Runs avahi-browse on h1 for TYPE until it resolves INSTANCE on 198.18.0.2:PORT (15 s at
# most); prints that line, or nothing. -r resolve, -p parseable, -t terminate once the cache
# is complete. The whole output stays in $NETNS_DIR/browse-NAME.out.
avahi_resolves() { # NAME TYPE INSTANCE PORT
  local out="$NETNS_DIR/browse-$1.out" deadline=$(($(now_ms) + 15000))
  while [ "$(now_ms)" -lt "$deadline" ]; do
    netns_exec h1 timeout 10 avahi-browse -rpt "$2" >"$out" 2>"$NETNS_DIR/browse-$1.err" || true
    grep -E "^=;eth0;IPv4;$3;_opcua-tcp\._tcp;local;[^;]+;198\.18\.0\.2;$4;" "$out" && return 0
    sleep 0.2
  done
  return 1
}

found=$(avahi_resolves pump _opcua-tcp._tcp skillcell-pump 4841)
[ -n "$found" ] || fail "avahi-browse did not resolve the skillcell server"
echo "$found" | grep -q '"path=' || fail "avahi-browse resolved no TXT path=: $found"
echo "$found" | grep -q '"caps=' || fail "avahi-browse resolved no TXT caps=: $found"
echo "ok: avahi-browse resolves the skillcell server: $found"

# Our LDS announces itself under the LDS subtype too (RFC 6763 7.1): avahi-browse of the
# subtype resolves it, and not the pump, which is no LDS.
start_in h2 lds "$BIN" lds --port 4842 --mdns-name skillcell-lds --application-uri urn:test:lds \
  --pki-dir "$NETNS_DIR/pki-lds" --insecure
wait_for_line "$NETNS_DIR/lds.out" '^READY' 20 >/dev/null || fail "lds did not start"
found=$(avahi_resolves lds _lds._sub._opcua-tcp._tcp skillcell-lds 4842)
[ -n "$found" ] || fail "avahi-browse of the LDS subtype did not resolve the skillcell LDS: $(cat "$NETNS_DIR/browse-lds.out")"
! grep -q 'skillcell-pump' "$NETNS_DIR/browse-lds.out" ||
  fail "avahi-browse of the LDS subtype lists the pump, which is no LDS"
echo "ok: avahi-browse of _lds._sub._opcua-tcp._tcp resolves the skillcell LDS alone: $found"

# An OPC UA server that does not announce itself (--no-discovery); Avahi announces it.
start_in h1 press "$BIN" server --port 4999 --no-discovery --application-uri urn:test:press \
  --pki-dir "$NETNS_DIR/pki-press" --insecure
wait_for_line "$NETNS_DIR/press.out" '^READY' 20 >/dev/null || fail "press did not start"
start_in h1 publish avahi-publish -s avahi-press _opcua-tcp._tcp 4999 "path=" "caps=DA"
wait_for_line "$NETNS_DIR/watcher.out" \
  '^ANNOUNCED avahi-press opc\.tcp://198\.18\.0\.1:4999 urn:test:press caps=DA' 15 >/dev/null || fail "the skillcell watcher did not see the service Avahi publishes"
echo "ok: the skillcell watcher sees the service avahi-publish announces"
proc_signal publish TERM
wait_for_line "$NETNS_DIR/watcher.out" '^GONE avahi-press goodbye' 10 >/dev/null ||
  fail "the skillcell watcher did not hear Avahi's goodbye"
echo "ok: and Avahi's goodbye"
echo "PASS"
