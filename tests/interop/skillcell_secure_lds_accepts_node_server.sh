#!/usr/bin/env bash
# Interop (discovery, security): a node-opcua server registers with our secured LDS over
# SignAndEncrypt, and only with a certificate the LDS trusts and that names its URI.
# Usage: skillcell_secure_lds_accepts_node_server.sh PATH/TO/skillcell
# Runs in a private network namespace (loopback only), everything in a temporary directory:
#  - a cell CA (`skillcell pki init-ca`); `skillcell lds` WITHOUT --insecure, SKILLCELL_CA_DIR set
#    (its certificate comes from the CA, it trusts the CA): Sign/SignAndEncrypt endpoints only;
#    RegisterServer(2) is refused on a None channel;
#  - register_server.js with a certificate issued by the CA for its URI (`skillcell pki issue`):
#    READY, its RegisterServer2 went over SignAndEncrypt (node-opcua's RegisterServerManager takes
#    the most secure endpoint), `skillcell discover --lds URL --registered` lists it;
#  - register_server.js with node-opcua's own self-signed certificate (--keep-trying): its secure
#    channel is refused (BadCertificateUntrusted), its certificate lands in the LDS's
#    rejected/certs, no READY, not listed; after `skillcell pki trust THUMBPRINT` its next
#    attempt registers it (READY, SignAndEncrypt, listed);
#  - register_server.js with a certificate of the CA naming another application URI than the
#    one it registers: RegisterServer2 and RegisterServer are answered BadServerUriInvalid,
#    FAILED, not listed (the certificate itself is trusted: not in rejected/);
#  - SIGTERM to the registered node servers: each unregisters (Good, over SignAndEncrypt) and is
#    gone from the list.
# Skips (exit 77) without node-opcua or without the rights to make a network namespace, unless
# SKILLCELL_REQUIRE_NODE=1 / SKILLCELL_REQUIRE_NETNS=1 (CI). SKILLCELL_INTEROP_KEEP_LOGS=1 keeps
# the logs.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=discovery_lib.sh
. "$here/discovery_lib.sh"
dl_init_skillcell "$0" "$@" # sets $skillcell

CA_URI_NODE=urn:skillcell:interop:node-secure-registered
SELF_URI_NODE=urn:skillcell:interop:node-self-signed
CLAIMED_URI=urn:skillcell:interop:node-claimed
CERT_URI=urn:skillcell:interop:node-certified-other
# node-opcua's PKI folders (its self-signed certificate) in this test's directory: a fresh
# certificate per run, nothing shared with other tests
export SKILLCELL_INTEROP_PKI="$DL_TMP/node-pki"
lds_pki="$DL_TMP/pki-lds"

# wait_line NAME FILE REGEX TIMEOUT_S: bounded wait for a line of $DL_TMP/NAME.FILE (out|err)
# matching the extended REGEX; prints it. Returns 1 (reason on stderr) at the deadline.
wait_line() {
  local name=$1 file=$2 regex=$3 timeout_s=$4 deadline line
  deadline=$((SECONDS + timeout_s))
  while :; do
    line=$(grep -m1 -E -- "$regex" "$DL_TMP/$name.$file" || true)
    if [ -n "$line" ]; then
      printf '%s\n' "$line"
      return 0
    fi
    if [ $SECONDS -ge $deadline ]; then
      echo "wait_line: no line matching '$regex' in the std$file of $name within $timeout_s s" >&2
      return 1
    fi
    sleep 0.2
  done
}

# registered URI [PORT]: regex of the `discover --registered` line of URI (at PORT)
registered() { echo "^REGISTERED $(dl_re "$1") .*:${2:-[0-9]+}(/|\$| )"; }

# a None channel carries no registration, so a None-mode RegisterServer(2) must never appear
insecure_re='register: RegisterServer2?Request over (None|Sign) '
online_good_re='register: RegisterServer2Request over SignAndEncrypt [^ ]+ isOnline=true .*-> Good'

"$skillcell" pki init-ca --dir "$DL_TMP/ca" >/dev/null
dl_start ours env SKILLCELL_CA_DIR="$DL_TMP/ca" "$skillcell" lds --port 0 --host 127.0.0.1 \
  --mdns-name ours-secure-lds --pki-dir "$lds_pki"
dl_wait_ready ours 20
lds_url=$DL_URL

# 1. certificate issued by the cell CA for the node server's URI
"$skillcell" pki issue --ca "$DL_TMP/ca" --uri "$CA_URI_NODE" --pki-dir "$DL_TMP/pki-node" \
  --ip 127.0.0.1 --dns "$(hostname)" >/dev/null
dl_start nodesrv node "$here/register_server.js" "$lds_url" --port 0 --application-uri "$CA_URI_NODE" \
  --certificate "$DL_TMP/pki-node/own/certs/cert.der" --private-key "$DL_TMP/pki-node/own/private/key.pem"
dl_wait_ready nodesrv 60
node_port=$DL_PORT
line=$(grep -m1 -E "$online_good_re" "$DL_TMP/nodesrv.err") ||
  dl_fail "the node server's registration did not go over SignAndEncrypt"
dl_step "node server (CA certificate): ${line#register_server.js: }"
! grep -E -q "$insecure_re" "$DL_TMP/nodesrv.err" || dl_fail "a registration went over None or Sign"
grep -q -E 'LDS endpoint [^ ]+ SignAndEncrypt ' "$DL_TMP/nodesrv.err" ||
  dl_fail "node-opcua saw no SignAndEncrypt endpoint of our LDS"
! grep -q -E 'LDS endpoint [^ ]+ None ' "$DL_TMP/nodesrv.err" || dl_fail "our secured LDS offers a None endpoint"
# Under the cell CA our LDS also offers ECC_nistP256, which node-opcua does not implement: it
# must see those endpoints and still register over an RSA policy.
grep -q -E 'LDS endpoint [^ ]+ SignAndEncrypt [^ ]+#ECC_nistP256 ' "$DL_TMP/nodesrv.err" ||
  dl_fail "node-opcua saw no ECC_nistP256 endpoint of our LDS (under a cell CA)"
! printf '%s\n' "$line" | grep -q 'ECC_nistP256' || dl_fail "node-opcua registered over ECC_nistP256?"
line=$(dl_poll 30 PRESENT "$(registered "$CA_URI_NODE" "$node_port")" \
  "$skillcell" discover --lds "$lds_url" --registered) ||
  dl_fail "skillcell discover --registered does not list $CA_URI_NODE with port $node_port"
dl_step "ours (FindServers): $line"

# 2. node-opcua's self-signed certificate (not trusted) and 3. a CA certificate naming another
# URI than the one registered, started together (each node start takes seconds)
"$skillcell" pki issue --ca "$DL_TMP/ca" --uri "$CERT_URI" --pki-dir "$DL_TMP/pki-other" \
  --ip 127.0.0.1 --dns "$(hostname)" >/dev/null
dl_start selfsrv node "$here/register_server.js" "$lds_url" --port 0 --application-uri "$SELF_URI_NODE" \
  --keep-trying
dl_start othersrv node "$here/register_server.js" "$lds_url" --port 0 --application-uri "$CLAIMED_URI" \
  --certificate "$DL_TMP/pki-other/own/certs/cert.der" --private-key "$DL_TMP/pki-other/own/private/key.pem"

# 2a. refused: untrusted
thumb=$(wait_line selfsrv err 'certificate thumbprint=[0-9a-f]{40} ' 60 |
  sed -E 's/.*thumbprint=([0-9a-f]{40}) .*/\1/') || dl_fail "the self-signed node server did not start"
wait_line ours err "client certificate refused \(BadCertificateUntrusted\).*thumbprint $thumb" 30 >/dev/null ||
  dl_fail "our LDS did not refuse the self-signed certificate $thumb as untrusted"
line=$(wait_line selfsrv err 'register: connect over SignAndEncrypt [^ ]+ to .* failed' 30) ||
  dl_fail "the self-signed node server saw no refused connection"
dl_step "self-signed node server: ${line#register_server.js: }"
[ -f "$lds_pki/rejected/certs/$thumb.der" ] ||
  dl_fail "the self-signed certificate $thumb is not in the LDS's rejected/certs: $(ls "$lds_pki/rejected/certs")"
dl_step "the LDS refused $thumb (BadCertificateUntrusted) and put it into rejected/certs"
! grep -q -E '^READY' "$DL_TMP/selfsrv.out" || dl_fail "the self-signed node server got registered untrusted"
! grep -q -E 'register: RegisterServer2?Request' "$DL_TMP/selfsrv.err" ||
  dl_fail "a RegisterServer(2) went through on an untrusted certificate's channel"

# 3. refused: the certificate names $CERT_URI, the server registers $CLAIMED_URI
line=$(wait_line othersrv out '^(READY|FAILED)( |$)' 60) ||
  dl_fail "the node server with another URI printed neither READY nor FAILED"
case "$line" in
  FAILED*BadServerUriInvalid*) dl_step "node server with another URI: $line" ;;
  *) dl_fail "a certificate naming $CERT_URI registered $CLAIMED_URI or failed otherwise: $line" ;;
esac
wait_line ours err "RegisterServer for $(dl_re "$CLAIMED_URI") refused: the channel's certificate names '$(dl_re "$CERT_URI")'" 10 >/dev/null ||
  dl_fail "our LDS did not log why it refused $CLAIMED_URI"
other_thumb=$(wait_line othersrv err 'certificate thumbprint=[0-9a-f]{40} ' 5 |
  sed -E 's/.*thumbprint=([0-9a-f]{40}) .*/\1/') || dl_fail "no certificate thumbprint in the log of othersrv"
[ ! -e "$lds_pki/rejected/certs/$other_thumb.der" ] ||
  dl_fail "the CA-issued certificate $other_thumb was put into rejected/ (the CA is trusted)"
dl_stop othersrv 20 || dl_fail "the node server with another URI did not exit within 20 s"

out=$(timeout 15 "$skillcell" discover --lds "$lds_url" --registered) ||
  dl_fail "skillcell discover --registered failed: $out"
for uri in "$SELF_URI_NODE" "$CLAIMED_URI" "$CERT_URI"; do
  ! printf '%s\n' "$out" | grep -q -E "$(registered "$uri")" || dl_fail "$uri is listed: $out"
done
dl_step "neither the untrusted nor the misnamed node server is listed"

# 2b. the operator trusts the rejected certificate; node-opcua's next attempt registers
"$skillcell" pki trust "$thumb" --pki-dir "$lds_pki" >/dev/null
[ -f "$lds_pki/trusted/certs/$thumb.der" ] || dl_fail "skillcell pki trust did not move $thumb to trusted/certs"
dl_step "skillcell pki trust $thumb"
dl_wait_ready selfsrv 30
self_port=$DL_PORT
line=$(grep -m1 -E "$online_good_re" "$DL_TMP/selfsrv.err") ||
  dl_fail "the trusted node server's registration did not go over SignAndEncrypt"
dl_step "self-signed node server, trusted: ${line#register_server.js: }"
! grep -E -q "$insecure_re" "$DL_TMP/selfsrv.err" || dl_fail "a registration went over None or Sign"
line=$(dl_poll 30 PRESENT "$(registered "$SELF_URI_NODE" "$self_port")" \
  "$skillcell" discover --lds "$lds_url" --registered) ||
  dl_fail "skillcell discover --registered does not list $SELF_URI_NODE with port $self_port"
dl_step "ours (FindServers): $line"

# 4. SIGTERM: each unregisters over SignAndEncrypt and is gone
for name in nodesrv selfsrv; do
  dl_stop "$name" 20 || dl_fail "$name did not exit within 20 s of SIGTERM"
  [ "$DL_RC" = 0 ] || dl_fail "$name exited with status $DL_RC after SIGTERM"
  grep -q 'unregistration: RegisterServer2Request -> Good' "$DL_TMP/$name.err" ||
    dl_fail "our LDS did not accept the unregistration of $name: $(grep -m1 'unregistration' "$DL_TMP/$name.err" || true)"
  grep -q -E 'register: RegisterServer2Request over SignAndEncrypt [^ ]+ isOnline=false .*-> Good' "$DL_TMP/$name.err" ||
    dl_fail "the unregistration of $name did not go over SignAndEncrypt"
  dl_step "$name unregistered (Good, SignAndEncrypt)"
done
dl_poll 30 ABSENT "$(registered "$CA_URI_NODE")" "$skillcell" discover --lds "$lds_url" --registered ||
  dl_fail "skillcell discover --registered still lists $CA_URI_NODE after it unregistered"
dl_poll 30 ABSENT "$(registered "$SELF_URI_NODE")" "$skillcell" discover --lds "$lds_url" --registered ||
  dl_fail "skillcell discover --registered still lists $SELF_URI_NODE after it unregistered"
dl_step "both gone from FindServers"

dl_stop ours 15 || dl_fail "our LDS did not exit within 15 s of SIGTERM"
[ "$DL_RC" = 0 ] || dl_fail "our LDS exited with status $DL_RC after SIGTERM"
dl_step "OK"
