#!/usr/bin/env bash
# Interop (discovery): node-opcua's LDS-ME (lds.js) learns our server from our mDNS.
# Usage: node_lds_sees_skillcell_server.sh PATH/TO/skillcell
# Runs in a private network namespace (loopback only: no mDNS on a real network). Phases:
#  1. node LDS first, refusing unsecured registration (so what it lists can only come from
#     mDNS), then `skillcell server --mdns-name ours-under-test`: node's FindServersOnNetwork must
#     list a record for it whose URL has our port; after SIGTERM (our goodbye) it must go away.
#  2. the other start order: our server first, then the node LDS, whose mDNS browser sends one
#     PTR query for _opcua-tcp._tcp.local at start-up (and never again): our server must answer
#     it (checked on the wire with mdns_sniff.js) and the LDS must list our server.
#  3. node LDS accepting unsecured registration: our server finds it by mDNS (its record:
#     SRV target 127.0.0.1, TXT path=/DiscoveryServer caps=LDS) and registers; node's
#     FindServers must list urn:test:ours; after SIGTERM (unregistration) it must go away.
#     (node's LDS sends no A record in a loopback-only namespace: our server must use the IPv4
#     literal SRV target directly.)
# Skips (exit 77) without node-opcua or without the rights to make a network namespace,
# unless SKILLCELL_REQUIRE_NODE=1 / SKILLCELL_REQUIRE_NETNS=1 (CI). Set
# SKILLCELL_INTEROP_PHASES="1 3" to run some phases only, SKILLCELL_INTEROP_KEEP_LOGS=1 to keep
# the logs. Each of our servers keeps its PKI (application certificate) in the test's temporary
# directory ($DL_TMP/pki-ours1 ...), never under $HOME.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=discovery_lib.sh
. "$here/discovery_lib.sh"
dl_init_skillcell "$0" "$@" # sets $skillcell

OUR_URI=urn:test:ours
OUR_MDNS=ours-under-test
server_args=(server --insecure --port 0 --host 127.0.0.1 --application-uri "$OUR_URI" --mdns-name "$OUR_MDNS")
phases=${SKILLCELL_INTEROP_PHASES:-1 2 3}

# FindServersOnNetwork on node's LDS must list our record, with our port in its URL.
expect_record() {
  local lds_url=$1 our_port=$2 out
  out=$(dl_node find_servers_on_network.js "$lds_url" "$OUR_MDNS" --timeout 30) ||
    dl_fail "node's LDS does not list $OUR_MDNS (FindServersOnNetwork): $out"
  dl_step "$out"
  [[ $out == *":$our_port"* ]] || dl_fail "the record's discoveryUrl does not carry our port $our_port: $out"
}

expect_no_record() {
  local lds_url=$1 out
  out=$(dl_node find_servers_on_network.js "$lds_url" "$OUR_MDNS" --absent --timeout 30) ||
    dl_fail "node's LDS still lists $OUR_MDNS after our server stopped (goodbye missed?): $out"
  dl_step "$out"
}

stop_our_server() {
  dl_stop "$1" 20 || dl_fail "our server did not exit within 20 s of SIGTERM"
  [ "$DL_RC" = 0 ] || dl_fail "our server exited with status $DL_RC after SIGTERM"
}

if [[ " $phases " == *" 1 "* ]]; then
  dl_step "phase 1: node LDS first (registration refused), our server second"
  dl_start lds1 node "$here/lds.js" --port 0 --refuse-unsecured-registration
  dl_wait_ready lds1 60
  lds_url=$DL_URL
  dl_start ours1 "$skillcell" "${server_args[@]}" --pki-dir "$DL_TMP/pki-ours1"
  dl_wait_ready ours1 20
  expect_record "$lds_url" "$DL_PORT"
  stop_our_server ours1
  expect_no_record "$lds_url"
  dl_stop lds1 15 || true
fi

if [[ " $phases " == *" 2 "* ]]; then
  dl_step "phase 2: our server first, node LDS second (its start-up query)"
  dl_start sniff2 node "$here/mdns_sniff.js"
  dl_wait_ready sniff2 20
  dl_start ours2 "$skillcell" "${server_args[@]}" --pki-dir "$DL_TMP/pki-ours2"
  dl_wait_ready ours2 20
  our_port=$DL_PORT
  # let our start-up announcements (RFC 6762 8.3: at least two) pass first, so that what
  # follows the LDS's query is the answer to it: wait for two of our PTR records on the wire and
  # then 1.5 s of silence (sniff2.out not written to)
  ptr_re="PTR +_opcua-tcp\._tcp\.local ttl=[1-9][0-9]* -> $(dl_re "$OUR_MDNS")\._opcua-tcp\._tcp\.local"
  # shellcheck disable=SC2016
  dl_poll 30 PRESENT '^quiet$' bash -c '
    [ "$(grep -c -E "$1" "$2")" -ge 2 ] || exit 0
    [ $(( $(date +%s%3N) - $(date -r "$2" +%s%3N) )) -ge 1500 ] && echo quiet' _ "$ptr_re" "$DL_TMP/sniff2.out" \
    >/dev/null || dl_fail "mdns_sniff.js did not see two announcements of $OUR_MDNS followed by 1.5 s of silence"
  sniff_mark=$(wc -l <"$DL_TMP/sniff2.out")
  dl_start lds2 node "$here/lds.js" --port 0 --refuse-unsecured-registration
  dl_wait_ready lds2 60
  expect_record "$DL_URL" "$our_port"
  # On the wire, after the LDS started: a PTR query for _opcua-tcp._tcp.local, then within 1.5 s
  # a response of ours carrying our PTR record.
  answer=$(awk -v name="$OUR_MDNS._opcua-tcp._tcp.local" -v mark="$sniff_mark" '
    NR <= mark { next }
    /^\+[0-9.]+s / { t = substr($1, 2) + 0; kind = $2 }
    kind == "query" && $1 == "question" && $2 == "PTR" && $3 == "_opcua-tcp._tcp.local" { q = t }
    kind == "response" && q != "" && t >= q && t - q <= 1.5 && $2 == "PTR" && $NF == name && $4 != "ttl=0" {
      printf "query at +%.3fs answered at +%.3fs (%s section)\n", q, t, $1; exit }
  ' "$DL_TMP/sniff2.out")
  [ -n "$answer" ] || dl_fail "our server did not answer the node LDS's PTR query within 1.5 s (see sniff2.out)"
  dl_step "our server answered node's start-up query: $answer"
  stop_our_server ours2
  expect_no_record "$DL_URL"
  dl_stop lds2 15 || true
  dl_stop sniff2 5 || true
fi

if [[ " $phases " == *" 3 "* ]]; then
  dl_step "phase 3: node LDS accepting unsecured registration; our server registers with it"
  dl_start lds3 node "$here/lds.js" --port 0
  dl_wait_ready lds3 60
  lds_url=$DL_URL
  dl_start ours3 "$skillcell" "${server_args[@]}" --pki-dir "$DL_TMP/pki-ours3"
  dl_wait_ready ours3 20
  out=$(dl_node find_servers.js "$lds_url" "$OUR_URI" --timeout 40) ||
    dl_fail "node's LDS does not list $OUR_URI (FindServers): our server did not register: $out" \
      "(node's LDS announces SRV target 127.0.0.1 with no A record here: our server must use the" \
      "IPv4 literal directly)"
  dl_step "$out"
  dl_step "node LDS: $(grep -m1 "lds.js: registered $OUR_URI" "$DL_TMP/lds3.err" || echo "no registration line")"
  expect_record "$lds_url" "$DL_PORT"
  stop_our_server ours3
  grep -q "lds.js: unregistered $OUR_URI" "$DL_TMP/lds3.err" ||
    dl_fail "our server did not unregister from node's LDS on SIGTERM"
  out=$(dl_node find_servers.js "$lds_url" "$OUR_URI" --absent --timeout 20) ||
    dl_fail "node's LDS still lists $OUR_URI (FindServers) after our server stopped: $out"
  dl_step "$out"
  expect_no_record "$lds_url"
  dl_stop lds3 15 || true
fi
dl_step "OK"
