#!/usr/bin/env bash
# `skillcell pki` as an operator runs it: init-ca (and refusing to overwrite), issue with the
# CA, list, trust (from rejected/ and from a file), reject, verify, revoke; usage errors exit 2 and
# failures exit 1 with a message on stderr.
# Usage: pki_cli_test.sh PATH/TO/skillcell
set -euo pipefail
skillcell=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
unset SKILLCELL_CA_DIR
export SKILLCELL_PKI_DIR="$tmp/default-pki"
fail() { echo "FAILED: $*" >&2; exit 1; }

# Runs skillcell pki ARGS, keeps stdout/stderr in $tmp/out, $tmp/err and checks the exit code.
run() {
  local want=$1; shift
  local rc=0
  "$skillcell" pki "$@" >"$tmp/out" 2>"$tmp/err" || rc=$?
  echo "--- skillcell pki $* (exit $rc)"; cat "$tmp/out" "$tmp/err"
  [ "$rc" = "$want" ] || fail "skillcell pki $*: exit $rc, expected $want"
}
expect() { grep -qF -- "$1" "$tmp/out" || fail "missing in output: $1"; }
expect_err() { grep -qF -- "$1" "$tmp/err" || fail "missing in stderr: $1"; }

# Usage errors.
run 2
run 2 frobnicate
run 2 init-ca
run 2 trust
run 2 init-ca --dir "$tmp/ca" --key-bits 1000
run 0 --help
expect "init-ca"
run 0 trust --help
expect "rejected/certs"

# A cell CA, once.
run 0 init-ca --dir "$tmp/ca" --name "Test Cell CA"
expect "created CA"
[ -f "$tmp/ca/certs/ca.der" ] && [ -f "$tmp/ca/crl/ca.crl" ] || fail "CA files missing"
[ "$(stat -c %a "$tmp/ca/private/ca_key.pem")" = 600 ] || fail "CA key not mode 0600"
run 1 init-ca --dir "$tmp/ca"
expect_err "not replacing"

# Issue a component's certificate; list shows it and the CA in trusted/.
run 0 issue --ca "$tmp/ca" --pki-dir "$tmp/robot" --uri urn:test:robot --dns robot.local
expect "issued"
run 0 issue --ca "$tmp/ca" --pki-dir "$tmp/robot" --uri urn:test:robot
expect "kept"
run 0 list --pki-dir "$tmp/robot"
expect "uri      urn:test:robot"
expect "Test Cell CA"
expect "[CA]"
grep -q "^trusted .*: 1$" "$tmp/out" || fail "the CA is not in trusted/"
grep -q "^rejected .*: 0$" "$tmp/out" || fail "rejected/ is not empty"

# Trust and reject: a certificate lands in rejected/ (as the validator would put it).
run 0 issue --ca "$tmp/ca" --pki-dir "$tmp/gripper" --uri urn:test:gripper
thumb=$(openssl x509 -inform DER -in "$tmp/gripper/own/certs/cert.der" -noout -fingerprint -sha1 |
        sed 's/.*=//; s/://g' | tr 'A-F' 'a-f')
[ ${#thumb} = 40 ] || fail "no thumbprint"
cp "$tmp/gripper/own/certs/cert.der" "$tmp/robot/rejected/certs/$thumb.der"
run 0 list --pki-dir "$tmp/robot"
expect "$thumb"
grep -q "^rejected .*: 1$" "$tmp/out" || fail "rejected/ should list one"
run 1 trust deadbeefdeadbeef --pki-dir "$tmp/robot"
expect_err "no certificate"
run 0 trust "${thumb:0:10}" --pki-dir "$tmp/robot"
[ -f "$tmp/robot/trusted/certs/$thumb.der" ] || fail "not moved to trusted/"
[ ! -e "$tmp/robot/rejected/certs/$thumb.der" ] || fail "still in rejected/"
run 0 reject "${thumb^^}" --pki-dir "$tmp/robot"
[ -f "$tmp/robot/rejected/certs/$thumb.der" ] || fail "not moved back to rejected/"
run 0 trust "$thumb.der" --pki-dir "$tmp/robot"
[ -f "$tmp/robot/trusted/certs/$thumb.der" ] || fail "trust by file name"
# Trusting a file from elsewhere copies it, named by thumbprint.
openssl req -x509 -newkey rsa:2048 -nodes -keyout "$tmp/k.pem" -out "$tmp/other.pem" \
  -subj "/CN=other" -days 2 2>/dev/null
run 0 trust "$tmp/other.pem" --pki-dir "$tmp/robot"
expect "trusted $tmp/robot/trusted/certs/"
[ -f "$tmp/other.pem" ] || fail "the source file was moved"

# Verify: the gripper's certificate passes at the robot (same CA), with URI and host checks.
run 0 verify "$tmp/gripper/own/certs/cert.der" --pki-dir "$tmp/robot" --uri urn:test:gripper
expect "Good"
run 1 verify "$tmp/gripper/own/certs/cert.der" --pki-dir "$tmp/robot" --uri urn:test:other
expect "BadCertificateUriInvalid"
run 1 verify "$tmp/gripper/own/certs/cert.der" --pki-dir "$tmp/robot" --host elsewhere.example
expect "BadCertificateHostNameInvalid"
openssl req -x509 -newkey rsa:2048 -nodes -keyout "$tmp/k2.pem" -out "$tmp/stranger.pem" \
  -subj "/CN=stranger" -days 2 2>/dev/null
rejected_before=$(ls "$tmp/robot/rejected/certs" | wc -l)
run 1 verify "$tmp/stranger.pem" --pki-dir "$tmp/robot"
expect "BadCertificateUntrusted"
[ "$(ls "$tmp/robot/rejected/certs" | wc -l)" = "$rejected_before" ] || fail "verify wrote to rejected/"
head -c 100 /dev/urandom >"$tmp/garbage.der"
run 1 verify "$tmp/garbage.der" --pki-dir "$tmp/robot"
expect "BadCertificateInvalid"

# Revoke: the CA's CRL lists the serial; once the robot has the new CRL (every start, or
# `pki issue` again, reinstalls it) the gripper's certificate is refused.
run 0 revoke --ca "$tmp/ca" "$tmp/gripper/own/certs/cert.der"
serial=$(openssl x509 -inform DER -in "$tmp/gripper/own/certs/cert.der" -noout -serial | sed 's/.*=//')
openssl crl -inform DER -in "$tmp/ca/crl/ca.crl" -noout -text | grep -q "$serial" ||
  fail "serial $serial not in the CRL"
run 0 issue --ca "$tmp/ca" --pki-dir "$tmp/robot" --uri urn:test:robot
run 1 verify "$tmp/gripper/own/certs/cert.der" --pki-dir "$tmp/robot"
expect "BadCertificateRevoked"
run 2 revoke --ca "$tmp/ca" "$tmp/nothing.der"

# The default PKI directory follows $SKILLCELL_PKI_DIR, as the components do.
run 1 list
expect_err "$tmp/default-pki"
echo "PASSED"
