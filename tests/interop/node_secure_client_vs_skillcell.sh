#!/usr/bin/env bash
# Interop, security: node-opcua's client against a skillcell server with its default
# security (secured endpoints only, no anonymous users).
# Usage: node_secure_client_vs_skillcell.sh PATH/TO/skillcell
#   1. adds two users with `skillcell user add` (an Operator and an Observer);
#   2. starts the server; node's first connection is refused (its certificate is unknown)
#      and lands in the server's rejected/ folder;
#   3. the operator's step: `skillcell pki trust` moves it to trusted/, no restart;
#   4. secure_client.js: every policy with Sign and SignAndEncrypt as the operator, the
#      observer refused Demo.Add, a wrong password and anonymous refused; an X.509 user token
#      of a certificate added with `skillcell user add --certificate` (as the cell adds its
#      components) accepted as that user's Operator role, an unknown one refused.
# Everything lives in a temporary directory. Skips (77) without node-opcua unless
# SKILLCELL_REQUIRE_NODE=1.
set -euo pipefail
skillcell=$1
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=SCRIPTDIR/interop_lib.sh
source "$here/interop_lib.sh"
interop_require_node
interop_temp_dir
pki=$tmp/pki
printf '%s\n' 'op-secret-1' | "$skillcell" user add operator --role Operator --pki-dir "$pki"
printf '%s\n' 'obs-secret-2' | "$skillcell" user add observer --role Observer --pki-dir "$pki"
# Two X.509 user certificates: "machine" is added as an Operator, the stranger is not.
for who in machine stranger; do
  openssl req -x509 -newkey rsa:2048 -nodes -keyout "$tmp/$who.pem" -out "$tmp/$who.crt" \
    -days 2 -subj "/CN=skillcell interop $who" 2>/dev/null
  openssl x509 -in "$tmp/$who.crt" -outform DER -out "$tmp/$who.der"
done
"$skillcell" user add machine --role Operator --certificate "$tmp/machine.der" --pki-dir "$pki"
"$skillcell" user list --pki-dir "$pki"
if grep -q 'op-secret-1' "$pki/users"; then echo "password stored in clear text" >&2; exit 1; fi

mkfifo "$tmp/ready"
"$skillcell" server --port 0 --host 127.0.0.1 --no-discovery --pki-dir "$pki" \
  >"$tmp/ready" 2>"$tmp/server.log" &
pid=$!
exec 3<"$tmp/ready"
if ! read -r -t 20 word url <&3 || [ "$word" != READY ]; then
  echo "server did not become ready:" >&2; cat "$tmp/server.log" >&2; exit 1
fi
echo "server ready at $url"
fail() { echo "FAIL: $*" >&2; echo "server log:" >&2; tail -n 60 "$tmp/server.log" >&2; exit 1; }

timeout 60 node "$here/secure_client.js" "$url" --pki "$tmp/node" --expect-untrusted ||
  fail "the untrusted client was not refused"
shopt -s nullglob
rejected=("$pki"/rejected/certs/*.der)
[ ${#rejected[@]} -eq 1 ] || fail "expected node's certificate in rejected/, found ${#rejected[@]}"
grep -q "BadCertificateUntrusted" "$tmp/server.log" || fail "the refusal was not logged"
"$skillcell" pki trust "${rejected[0]}" --pki-dir "$pki" || fail "skillcell pki trust failed"

timeout 150 node "$here/secure_client.js" "$url" --pki "$tmp/node" \
  --operator operator:op-secret-1 --observer observer:obs-secret-2 \
  --x509-user "$tmp/machine.der:$tmp/machine.pem" \
  --x509-stranger "$tmp/stranger.der:$tmp/stranger.pem" || fail "secure_client.js failed"
kill -0 "$pid" 2>/dev/null || fail "our server died during the test"
grep -q "BadUserAccessDenied" "$tmp/server.log" || fail "the wrong password was not logged"
echo "OK"
