#!/usr/bin/env bash
# Interop (discovery): our LDS-ME accepts the registration of a node-opcua server.
# Usage: skillcell_lds_accepts_node_server.sh PATH/TO/skillcell
# Runs in a private network namespace (loopback only: no mDNS on a real network):
#  - `skillcell lds --mdns-name ours-lds`, plus a node-opcua LDS (lds.js, refusing
#    registrations) as an independent mDNS observer;
#  - register_server.js: a node-opcua server registering with our LDS (GetEndpoints, then
#    RegisterServer2 with mdnsServerName = its applicationUri; READY only once our LDS answered
#    without a fault);
#  - `skillcell discover --lds URL --registered` (FindServers) must list its applicationUri with its
#    URL, `skillcell discover --lds URL` (FindServersOnNetwork) a RECORD for it (our LDS announces
#    what registers with RegisterServer2 + mDNS configuration); node's find_servers.js and
#    find_servers_on_network.js must decode both answers of our LDS; node's LDS must list the
#    record our LDS announces, and our LDS itself (caps LDS);
#  - SIGTERM to the node server (it unregisters): gone from all of these lists, bounded.
# Skips (exit 77) without node-opcua or without the rights to make a network namespace, unless
# SKILLCELL_REQUIRE_NODE=1 / SKILLCELL_REQUIRE_NETNS=1 (CI). SKILLCELL_INTEROP_KEEP_LOGS=1 keeps the
# logs. node-opcua registers only with an LDS whose endpoints carry a serverCertificate (even for
# SecurityPolicy None): register_server.js prints FAILED at once when ours carry none. Our LDS
# keeps its PKI (application certificate) in the test's temporary directory ($DL_TMP/pki-lds),
# never under $HOME.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=discovery_lib.sh
. "$here/discovery_lib.sh"
dl_init_skillcell "$0" "$@" # sets $skillcell

NODE_URI=urn:skillcell:interop:node-registered
OUR_LDS_MDNS=ours-lds

dl_start sniff node "$here/mdns_sniff.js" # only for the logs
dl_wait_ready sniff 20
dl_start ours "$skillcell" lds --port 0 --host 127.0.0.1 --mdns-name "$OUR_LDS_MDNS" \
  --pki-dir "$DL_TMP/pki-lds" --insecure
dl_wait_ready ours 20
lds_url=$DL_URL
dl_start observer node "$here/lds.js" --port 0 --refuse-unsecured-registration \
  --application-uri urn:skillcell:interop:node-observer
dl_wait_ready observer 60
observer_url=$DL_URL

dl_start nodesrv node "$here/register_server.js" "$lds_url" --port 0 --application-uri "$NODE_URI"
dl_wait_ready nodesrv 60
node_port=$DL_PORT
dl_step "node server: $(grep -m1 'register: RegisterServer' "$DL_TMP/nodesrv.err" || true)"

uri_re=$(dl_re "$NODE_URI")
registered_re="^REGISTERED $uri_re .*:$node_port(/|\$| )"
record_re="^RECORD [0-9]+ $uri_re [^ ]*:$node_port(/| |\$)"

line=$(dl_poll 30 PRESENT "$registered_re" "$skillcell" discover --lds "$lds_url" --registered) ||
  dl_fail "skillcell discover --registered does not list $NODE_URI with port $node_port"
dl_step "ours (FindServers): $line"
line=$(dl_poll 30 PRESENT "$record_re" "$skillcell" discover --lds "$lds_url") ||
  dl_fail "skillcell discover does not list a RECORD for $NODE_URI with port $node_port"
dl_step "ours (FindServersOnNetwork): $line"

out=$(dl_node find_servers_on_network.js "$lds_url" "$NODE_URI" --timeout 20) ||
  dl_fail "node's client finds no record for $NODE_URI on our LDS: $out"
dl_step "node client on our LDS: $out"
[[ $out == *":$node_port"* ]] || dl_fail "the record's discoveryUrl does not carry port $node_port: $out"
out=$(dl_node find_servers.js "$lds_url" "$NODE_URI" --timeout 20) ||
  dl_fail "node's client does not find $NODE_URI with FindServers on our LDS: $out"
dl_step "node client on our LDS: $out"

# our LDS's mDNS, decoded by node's browser (sterfive-bonjour-service)
out=$(dl_node find_servers_on_network.js "$observer_url" "$NODE_URI" --timeout 20) ||
  dl_fail "node's LDS does not see our LDS's mDNS announcement of $NODE_URI: $out"
dl_step "node LDS (observer): $out"
[[ $out == *":$node_port"* ]] || dl_fail "the announced record does not carry port $node_port: $out"
out=$(dl_node find_servers_on_network.js "$observer_url" "$OUR_LDS_MDNS" --timeout 20) ||
  dl_fail "node's LDS does not see our LDS's own announcement $OUR_LDS_MDNS: $out"
dl_step "node LDS (observer): $out"
[[ $out == *"caps=LDS"* ]] || dl_fail "our LDS's own record lacks the LDS capability: $out"

dl_stop nodesrv 20 || dl_fail "the node server did not exit within 20 s of SIGTERM"
dl_step "node server: $(grep -m1 'unregistration:\|no unregistration' "$DL_TMP/nodesrv.err" || true)"
grep -q 'unregistration: RegisterServer2\?Request -> Good' "$DL_TMP/nodesrv.err" ||
  dl_fail "our LDS did not accept the node server's unregistration"

dl_poll 30 ABSENT "$registered_re" "$skillcell" discover --lds "$lds_url" --registered ||
  dl_fail "skillcell discover --registered still lists $NODE_URI after it unregistered"
dl_poll 30 ABSENT "$record_re" "$skillcell" discover --lds "$lds_url" ||
  dl_fail "skillcell discover still lists a RECORD for $NODE_URI after it unregistered"
out=$(dl_node find_servers_on_network.js "$lds_url" "$NODE_URI" --absent --timeout 20) ||
  dl_fail "node's client still finds a record for $NODE_URI on our LDS: $out"
out=$(dl_node find_servers_on_network.js "$observer_url" "$NODE_URI" --absent --timeout 20) ||
  dl_fail "node's LDS still lists $NODE_URI: our LDS's mDNS goodbye missed? $out"
dl_step "gone from FindServers and FindServersOnNetwork of both LDSs"

dl_stop ours 15 || dl_fail "our LDS did not exit within 15 s of SIGTERM"
[ "$DL_RC" = 0 ] || dl_fail "our LDS exited with status $DL_RC after SIGTERM"
dl_step "OK"
