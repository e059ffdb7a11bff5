#!/usr/bin/env bash
# A work cell with security on, end to end, as an integrator sets it up: a cell CA
# (`skillcell pki init-ca`, SKILLCELL_CA_DIR), one user database, no --insecure anywhere.
# In a private network namespace (mDNS on loopback only):
#   LDS (--detect, its detector acting as user "observer"), a server with a skill, a world
#   model and a UR5 that reports its flange to the world as user "cell" (Operator).
# Checks:
#   - the components register with the secured LDS (over a secured channel: a None channel
#     serves discovery only) and the LDS's detector sees their skills;
#   - an operator runs the skill with `skillcell skill`; an observer is refused Start
#     (BadUserAccessDenied); `--insecure` is refused (BadSecurityPolicyRejected); a client with
#     a self-signed certificate is refused and its certificate lands in the server's rejected/;
#   - the UR5's world link authenticated as "cell" (the world logs the activation).
# Usage: secure_cell.sh PATH/TO/skillcell. Exit 77 (skip) when no network namespace can be
# made, unless SKILLCELL_REQUIRE_NETNS=1.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
DL_NEEDS_NODE=0
# shellcheck source=../interop/discovery_lib.sh
. "$here/../interop/discovery_lib.sh"
dl_init_skillcell "$0" "$@" # sets $skillcell

T=$DL_TMP
export SKILLCELL_CA_DIR=$T/ca
"$skillcell" pki init-ca --dir "$SKILLCELL_CA_DIR" >/dev/null
users=$T/users
printf 'op-pw\n' | "$skillcell" user add operator --role Operator --users "$users" >/dev/null
printf 'obs-pw\n' | "$skillcell" user add observer --role Observer --users "$users" >/dev/null
printf 'cell-pw\n' | "$skillcell" user add cell --role Operator --users "$users" >/dev/null
printf 'op-pw\n' >"$T/operator.pw"
printf 'obs-pw\n' >"$T/observer.pw"
printf 'cell-pw\n' >"$T/cell.pw"
dl_step "cell CA, users operator/observer/cell"

fast=(--mdns-ttl 5 --mdns-query-period 1)
dl_start lds "$skillcell" lds --port 0 --host 127.0.0.1 "${fast[@]}" --pki-dir "$T/pki-lds" \
  --users "$users" --detect --client-user observer --client-password-file "$T/observer.pw"
dl_wait_ready lds 20
lds_url=$DL_URL
dl_start server "$skillcell" server --port 0 --host 127.0.0.1 "${fast[@]}" \
  --pki-dir "$T/pki-server" --users "$users" \
  --noop-skill CartesianLinearMoveSkillType=Move --noop-skill-ms 100 \
  --client-user cell --client-password-file "$T/cell.pw"
dl_wait_ready server 20
server_url=$DL_URL
dl_start world "$skillcell" device world --port 0 --host 127.0.0.1 "${fast[@]}" \
  --pki-dir "$T/pki-world" --users "$users"
dl_wait_ready world 20
world_url=$DL_URL
dl_start ur5 "$skillcell" device ur5 --port 0 --host 127.0.0.1 "${fast[@]}" --speed 50 \
  --pki-dir "$T/pki-ur5" --users "$users" --world "$world_url" \
  --client-user cell --client-password-file "$T/cell.pw"
dl_wait_ready ur5 20

# Registration: FindServers on a None channel is discovery, allowed.
dl_poll 20 PRESENT '^REGISTERED urn:skillcell:server ' "$skillcell" discover --lds "$lds_url" --registered >/dev/null ||
  dl_fail "the server did not register with the secured LDS"
dl_poll 20 PRESENT '^REGISTERED urn:skillcell:device:ur5 ' "$skillcell" discover --lds "$lds_url" --registered >/dev/null ||
  dl_fail "the UR5 did not register with the secured LDS"
dl_step "both registered over secured channels"
grep -q 'RegisterServer.*refused' "$T/lds.err" && dl_fail "the LDS refused a registration"

# Detection by the LDS's detector (secured channel, user observer).
deadline=$((SECONDS + 20))
until grep -q '^SKILL ADDED .*urn:skillcell:server.*Move' "$T/lds.out" &&
  grep -q '^SKILL ADDED .*urn:skillcell:device:ur5.*CartesianLinearMove' "$T/lds.out"; do
  [ $SECONDS -lt $deadline ] || dl_fail "the LDS's detector did not see the skills"
  sleep 0.2
done
dl_step "the LDS's detector sees Move and the UR5's skills"
grep -q "activated for 'observer'" "$T/server.err" ||
  dl_fail "the detector's session on the server is not the observer's"

cli=(--pki-dir "$T/pki-cli")
out=$("$skillcell" skill "$server_url" Move "${cli[@]}" --user operator \
  --password-file "$T/operator.pw" --timeout 10) || dl_fail "the operator could not run Move: $out"
grep -q '^OUTCOME' <<<"$out" || dl_fail "no OUTCOME line: $out"
dl_step "operator: $(grep '^OUTCOME' <<<"$out")"

rc=0
err=$("$skillcell" skill "$server_url" Move "${cli[@]}" --user observer \
  --password-file "$T/observer.pw" --timeout 10 2>&1) || rc=$?
[ $rc -ne 0 ] || dl_fail "an observer ran Move: $err"
grep -q BadUserAccessDenied <<<"$err" || dl_fail "observer refused, but not with BadUserAccessDenied: $err"
grep -q "Call of .* refused (BadUserAccessDenied): roles .*Observer" "$T/server.err" ||
  dl_fail "the server did not log the observer's refused Start"
dl_step "observer: refused with BadUserAccessDenied, logged"

rc=0
err=$("$skillcell" skill "$server_url" Move --insecure --timeout 5 2>&1) || rc=$?
[ $rc -ne 0 ] && grep -q BadSecurityPolicyRejected <<<"$err" ||
  dl_fail "an --insecure client was not refused with BadSecurityPolicyRejected: $err"
dl_step "--insecure client: $(tail -n1 <<<"$err")"

# A stranger: it trusts the cell (its CA, as the CLI's PKI directory does), but its own
# certificate is self-signed, unknown to the cell.
mkdir -p "$T/pki-stranger"
cp -r "$T/pki-cli/trusted" "$T/pki-stranger/"
rc=0
err=$(env -u SKILLCELL_CA_DIR "$skillcell" skill "$server_url" Move --pki-dir "$T/pki-stranger" \
  --user operator --password-file "$T/operator.pw" --timeout 5 2>&1) || rc=$?
[ $rc -ne 0 ] || dl_fail "a client with a self-signed certificate ran Move"
ls "$T"/pki-server/rejected/certs/*.der >/dev/null 2>&1 ||
  dl_fail "the stranger's certificate is not in the server's rejected/: $err"
dl_step "self-signed client: $(tail -n1 <<<"$err")"

grep -q "activated for 'cell'" "$T/world.err" ||
  dl_fail "the UR5's world link did not authenticate as 'cell'"
if grep -qE '\[(warning|error)\]' "$T/world.err"; then
  dl_fail "the world model warned: $(grep -E '\[(warning|error)\]' "$T/world.err")"
fi
dl_step "the UR5's world link acts as 'cell'"

for c in ur5 world server lds; do
  dl_stop "$c" 15 || dl_fail "$c did not exit within 15 s of SIGTERM"
  [ "$DL_RC" = 0 ] || dl_fail "$c exited with status $DL_RC"
done
dl_step "PASS: secure cell"
