#!/usr/bin/env bash
# `skillcell check` as a device maker runs it, against `skillcell server --noop-skill`
# (skills::Skill with a no-op behaviour): exit codes and output of the command itself.
#   static and --exercise checks pass (exit 0), also with a run long enough to Suspend;
#   --json is one valid document; no skill below --start fails (exit 1);
#   usage errors and an endpoint nobody listens on exit 2.
# Usage: check_command_vs_noop_skill.sh PATH/TO/skillcell
set -euo pipefail
skillcell=$1
tmp=$(mktemp -d)
pid=""
cleanup() {
  [ -n "$pid" ] && kill "$pid" 2>/dev/null && wait "$pid" 2>/dev/null
  rm -rf "$tmp"
}
trap cleanup EXIT
fail() { echo "FAILED: $*" >&2; exit 1; }

mkfifo "$tmp/ready"
"$skillcell" server --port 0 --host 127.0.0.1 --no-discovery --pki-dir "$tmp/pki" --insecure \
  --noop-skill CartesianLinearMoveSkillType=Move --noop-skill GraspGripperSkillType=Grasp \
  --noop-skill-ms 300 >"$tmp/ready" 2>"$tmp/server.log" &
pid=$!
exec 3<"$tmp/ready"
if ! read -r -t 20 word url <&3 || [ "$word" != READY ]; then
  echo "server did not become ready:" >&2; cat "$tmp/server.log" >&2; exit 1
fi

# Runs `skillcell check`, shows its output, and compares its exit code.
check() {
  local want=$1; shift
  local rc=0
  timeout 60 "$skillcell" check --insecure "$@" >"$tmp/out" 2>"$tmp/err" || rc=$?
  echo "--- skillcell check $* (exit $rc)"
  grep -v -e '^PASS' -e '"verdict": "PASS"' "$tmp/out" || true
  cat "$tmp/err"
  [ "$rc" = "$want" ] || { cat "$tmp/out"; fail "skillcell check $*: exit $rc, expected $want"; }
}
expect_line() { grep -qF -- "$1" "$tmp/out" || fail "missing line: $1"; }

check 0 "$url"
expect_line "PASS  server  skills: 2 found: Objects/Skills/Move, Objects/Skills/Grasp"
expect_line "RESULT: PASS"

check 0 "$url" --exercise --timeout 5000 --strict
expect_line "PASS  Objects/Skills/Move  Suspend in Running: Good, event RunningToSuspended, CurrentState Suspended"
expect_line "PASS  Objects/Skills/Grasp  run: RunningToReady"
expect_line "PASS  Objects/Skills/Grasp  exercise end: left in Ready"

check 0 "$url" --json
if command -v python3 >/dev/null; then
  python3 -c 'import json, sys
r = json.load(sys.stdin)
assert r["result"] == "PASS" and r["counts"]["fail"] == 0 and len(r["skills"]) == 2, r["counts"]' \
    <"$tmp/out" || fail "--json: not the expected document"
fi

check 1 "$url" --start i=2253 --failures-only
expect_line "FAIL  server  skills: expected at least one object below Server whose type is a subtype of SkillType"

check 2
check 2 "$url" --no-such-option
check 2 "$url" --start "not a node id"
check 2 "opc.tcp://127.0.0.1:1" --connect-timeout 1000

kill -0 "$pid" 2>/dev/null || { echo "the server died:" >&2; cat "$tmp/server.log" >&2; exit 1; }
echo ok
