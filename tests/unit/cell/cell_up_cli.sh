#!/usr/bin/env bash
# `skillcell cell up`, `cell status` and `cell down` on a small cell (robot_cell.toml):
#  - a wrong cell file: exit 2, every problem with FILE:LINE:COLUMN, nothing started;
#  - up: the endpoints and the generated users are printed, `cell status` shows every
#    component up with the UR5's skills as detected; the components are users by their
#    certificates (cell-NAME, x509$ in the users file, no password of theirs), and the UR5's
#    session on the world is activated as cell-ur5;
#  - a second `cell up` of the same work directory is refused while the first runs;
#  - the UR5 is given the world model's certificate and uses it (it does not ask the world
#    for its endpoints); given a certificate the world does not have, it asks, and comes up;
#  - the UR5 killed with SIGKILL: reported with the last lines of its log, restarted
#    (restart = "on-failure", the default) on the same endpoint, its skills detected again;
#  - the LDS killed (restart = "never"): reported, stays down, `cell status` exits 1;
#  - `cell down`: the supervisor ends with 0 and no component is left running;
#  - a second `cell up` of the same work directory keeps the CA and the users, and SIGINT
#    (Ctrl-C) stops it as cleanly;
#  - a cell file that names its own CA and user database: without the password of the user
#    'cell' beside the database nothing starts; with it the components get their certificates
#    from that CA and detect each other as that user.
# `cell up` makes its own network namespace (root). Without root the test is skipped (77),
# unless SKILLCELL_REQUIRE_NETNS=1, as in CI.
# Usage: cell_up_cli.sh PATH/TO/skillcell SOURCE_DIR
set -euo pipefail
skillcell=$1
src=$2
# shellcheck source=../../support/cell_up.sh
source "$src/tests/support/cell_up.sh"
status_json() { "$skillcell" cell status --json --work-dir "$work"; }
# The value of KEY of component NAME in `cell status --json`.
field() {
  status_json | python3 -c "import json,sys
d=json.load(sys.stdin)
print(next(str(c.get('$2','')) for c in d['components'] if c['name']=='$1'))"
}
# Waits (at most $1 tries, 0.5 s apart) until the command in the other arguments succeeds.
until_ok() {
  local tries=$1
  shift
  for _ in $(seq "$tries"); do
    "$@" >/dev/null 2>&1 && return 0
    sleep 0.5
  done
  return 1
}
skills_of_ur5() { field ur5 skills | grep -q CartesianLinearMoveSkillType; }
cell=$src/tests/unit/cell/robot_cell.toml

# A wrong cell file: nothing starts.
rc=0
"$skillcell" cell up "$src/tests/data/cells/several_problems.toml" --work-dir "$work" \
  >"$tmp/bad.out" 2>"$tmp/bad.err" || rc=$?
[ "$rc" = 2 ] || fail "a wrong cell file: exit $rc, expected 2"
grep -q "several_problems.toml:12:9: robot 'ur5': model 'ur6'" "$tmp/bad.err" ||
  fail "no FILE:LINE:COLUMN problem: $(cat "$tmp/bad.err")"
grep -q 'nothing started' "$tmp/bad.err" || fail "does not say that nothing started"
[ ! -e "$work" ] || fail "a wrong cell file made the work directory"

# A wrong --host: exit 2, the reason, nothing started.
for bad in "ur5:robot-pc|expected COMPONENT=HOST" \
  "mes=mes-pc|the cell has no component 'mes'; it has: lds, world, ur5" \
  "ur5=Robot_PC|host 'Robot_PC': use 1 to 12 lower-case letters"; do
  rc=0
  "$skillcell" cell up "$cell" --work-dir "$work" --host "${bad%%|*}" >"$tmp/bad.out" \
    2>"$tmp/bad.err" || rc=$?
  [ "$rc" = 2 ] || fail "--host ${bad%%|*}: exit $rc, expected 2"
  grep -qF -- "--host ${bad%%|*}: ${bad#*|}" "$tmp/bad.err" ||
    fail "--host ${bad%%|*}: not the reason '${bad#*|}': $(cat "$tmp/bad.err")"
  grep -q 'nothing started' "$tmp/bad.err" || fail "--host ${bad%%|*}: does not say so"
  [ ! -e "$work" ] || fail "a wrong --host made the work directory"
done

# Up.
"$skillcell" cell up "$cell" --work-dir "$work" >"$tmp/up.out" 2>"$tmp/up.err" &
supervisor=$!
until_ok 240 grep -q 'is up' "$tmp/up.out" || fail "the cell did not come up"
for line in '^  lds +opc\.tcp://' '^  world +opc\.tcp://' '^  ur5 +opc\.tcp://' \
  "^  operator +Operator +$work/operator\.pw$" "^  engineer +Engineer +$work/engineer\.pw$"; do
  grep -qE "$line" "$tmp/up.out" || fail "cell up did not print: $line"
done
until_ok 60 skills_of_ur5 || fail "the UR5's skills were not detected"
grep -qE '^cell-ur5:Operator:x509\$[0-9a-f]{40}$' "$work/users" ||
  fail "the UR5 is not a user by its certificate: $(cut -c1-40 "$work/users")"
! grep -qE '^cell(-[a-z0-9-]+)?:.*scrypt' "$work/users" || fail "a component has a password"
[ ! -e "$work/cell.pw" ] || fail "a password file for the components"
grep -q "activated for 'cell-ur5'" "$work/logs/world.log" ||
  fail "the UR5's session on the world is not cell-ur5's"
"$skillcell" cell status --work-dir "$work" >"$tmp/status.out" || fail "status: exit $?"
grep -qE '^  ur5 +up ' "$tmp/status.out" || fail "ur5 is not up: $(cat "$tmp/status.out")"
grep -qE 'skill Skills/CartesianLinearMove +CartesianLinearMoveSkillType' "$tmp/status.out" ||
  fail "status does not show the UR5's skills: $(cat "$tmp/status.out")"

# One supervisor per work directory.
rc=0
timeout 60 "$skillcell" cell up "$cell" --work-dir "$work" >/dev/null 2>"$tmp/second.err" || rc=$?
[ "$rc" = 1 ] || fail "a second cell up in the same work directory: exit $rc, expected 1"
grep -q 'a cell is up already' "$tmp/second.err" || fail "second up: $(cat "$tmp/second.err")"

# The UR5 reached the world with the certificate the cell gave it, without asking first.
endpoint=$(field ur5 endpoint)
pid=$(field ur5 pid)
worldcert=$work/pki-world/own/certs/cert-nistP256.der
tr '\0' ' ' <"/proc/$pid/cmdline" | grep -qF -- "--world-certificate $worldcert" ||
  fail "the UR5 was not given the world's certificate: $(tr '\0' ' ' <"/proc/$pid/cmdline")"
! grep -q 'asking the world for its endpoints' "$work/logs/ur5.log" ||
  fail "the UR5 asked the world for its endpoints: $(grep asking "$work/logs/ur5.log")"
# Given a certificate the world does not have (here the UR5's own), the restarted UR5 asks.
cp "$worldcert" "$tmp/world-cert.der"
cp "$work/pki-ur5/own/certs/cert-nistP256.der" "$worldcert"

# The UR5 killed: reported with its log, restarted on its endpoint.
kill -KILL "$pid"
restarted() { [ "$(field ur5 restarts)" = 1 ] && [ "$(field ur5 state)" = up ]; }
until_ok 60 restarted || fail "the UR5 was not restarted"
cp "$tmp/world-cert.der" "$worldcert"
grep -q "with the certificate of $worldcert: .*asking the world for its endpoints" \
  "$work/logs/ur5.log" || fail "the UR5 did not say that it asked: $(tail -5 "$work/logs/ur5.log")"
grep -q 'cell: ur5 ended (killed by signal 9' "$tmp/up.err" || fail "the UR5's end not reported"
grep -q '^    | ' "$tmp/up.err" || fail "no lines of the UR5's log in the report"
[ "$(field ur5 endpoint)" = "$endpoint" ] || fail "the UR5 came back on another endpoint"
[ "$(field ur5 pid)" != "$pid" ] || fail "the UR5's pid did not change"
until_ok 60 skills_of_ur5 || fail "the restarted UR5's skills were not detected"

# The LDS killed: restart = "never".
kill -KILL "$(field lds pid)"
until_ok 60 test "$(field lds state)" = down || fail "the LDS is not reported down"
grep -q 'cell: lds stays down (restart = "never")' "$tmp/up.err" || fail "no 'stays down'"
rc=0
"$skillcell" cell status --work-dir "$work" >"$tmp/status.out" || rc=$?
[ "$rc" = 1 ] || fail "status with a component down: exit $rc, expected 1"

# Down: every component ends, and the supervisor with 0.
pids=$(status_json | python3 -c "import json,sys
print(' '.join(str(c['pid']) for c in json.load(sys.stdin)['components'] if c.get('pid')))")
"$skillcell" cell down --work-dir "$work" >"$tmp/down.out" || fail "cell down: exit $?"
rc=0
wait "$supervisor" || rc=$?
supervisor=
[ "$rc" = 0 ] || fail "cell up ended with $rc after cell down"
for p in $pids; do
  ! kill -0 "$p" 2>/dev/null || fail "component pid $p still runs after cell down"
done
[ ! -e "$work/control.sock" ] || fail "the control socket is left behind"
rc=0
"$skillcell" cell status --work-dir "$work" >/dev/null 2>&1 || rc=$?
[ "$rc" = 2 ] || fail "status of a stopped cell: exit $rc, expected 2"

# Up again on the same work directory: the same CA and users; Ctrl-C stops it.
ca=$(sha256sum "$work/ca/certs/ca.der")
password=$(cat "$work/operator.pw")
"$skillcell" cell up "$cell" --work-dir "$work" >"$tmp/up2.out" 2>"$tmp/up2.err" &
supervisor=$!
until_ok 240 grep -q 'is up' "$tmp/up2.out" || fail "the cell did not come up again"
[ "$(sha256sum "$work/ca/certs/ca.der")" = "$ca" ] || fail "the second up made a new CA"
[ "$(cat "$work/operator.pw")" = "$password" ] || fail "the second up made new passwords"
pids=$(status_json | python3 -c "import json,sys
print(' '.join(str(c['pid']) for c in json.load(sys.stdin)['components'] if c.get('pid')))")
kill -INT "$supervisor"
rc=0
wait "$supervisor" || rc=$?
supervisor=
[ "$rc" = 0 ] || fail "cell up ended with $rc after SIGINT"
grep -q 'stopping cell-up-test (interrupted)' "$tmp/up2.out" || fail "no stop message"
for p in $pids; do
  ! kill -0 "$p" 2>/dev/null || fail "component pid $p still runs after SIGINT"
done
# The cell's own CA and users, from files the cell file names.
own=$tmp/own
mkdir -p "$own"
"$skillcell" pki init-ca --dir "$own/ca" --name "test cell CA" >/dev/null 2>&1 || fail "pki init-ca"
echo "cell-password" | "$skillcell" user add cell --role Operator --users "$own/users" >/dev/null 2>&1 ||
  fail "user add"
sed -e 's/^name = "cell-up-test"$/name = "cell-up-own"/' \
  -e 's/^enabled = true$/enabled = true\nca = "ca"\nusers = "users"/' "$cell" >"$own/cell.toml"
grep -q '^ca = "ca"$' "$own/cell.toml" || fail "the test's cell file: $(cat "$own/cell.toml")"
rc=0
"$skillcell" cell up "$own/cell.toml" --work-dir "$tmp/work-own" >/dev/null 2>"$tmp/own.err" || rc=$?
[ "$rc" = 1 ] || fail "users without cell.pw: exit $rc, expected 1"
grep -q "$own/users: the components act as the user 'cell'.*$own/cell.pw" "$tmp/own.err" ||
  fail "no reason for the missing password: $(cat "$tmp/own.err")"
echo "cell-password" >"$own/cell.pw"
"$skillcell" cell up "$own/cell.toml" --work-dir "$tmp/work-own" >"$tmp/up3.out" 2>"$tmp/up3.err" &
supervisor=$!
until_ok 240 grep -q 'is up' "$tmp/up3.out" || fail "the cell with its own CA did not come up"
[ ! -e "$tmp/work-own/ca" ] || fail "a CA was generated although the cell file names one"
[ "$(readlink -f "$tmp/work-own/pki-ur5/cell-ca")" = "$(readlink -f "$own/ca")" ] ||
  fail "the UR5's certificate is not from the cell file's CA"
own_skills() {
  "$skillcell" cell status --json --work-dir "$tmp/work-own" | grep -q CartesianLinearMoveSkillType
}
until_ok 60 own_skills || fail "the UR5's skills were not detected as the cell file's user"
"$skillcell" cell down --work-dir "$tmp/work-own" >/dev/null || fail "cell down: exit $?"
wait "$supervisor" || fail "cell up (own CA) ended with $?"
supervisor=
echo OK
