#!/usr/bin/env bash
# Interop: `skillcell check` against skills served by node-opcua, an independent
# implementation of the skill model (skill_server.js: our companion models loaded into
# node-opcua, a CartesianLinearMoveSkillType with a state machine behind its methods, and a
# broken one next to it).
#   1. the conforming skill passes the static checks       (exit 0)
#   2. and --exercise: interlocking, transitions (Suspend and Resume during the run),
#      events                                                 (exit 0)
#   3. the broken skill fails, with the precise findings     (exit 1)
#   4. --json over the whole server is one valid document   (exit 1: the broken skill)
#   5. an endpoint nobody listens on                         (exit 2)
# Usage: skillcell_check_vs_node_skill_server.sh PATH/TO/skillcell MODELS_DIR
# Skips (exit 77) without node-opcua, unless SKILLCELL_REQUIRE_NODE=1, as in CI.
set -euo pipefail
skillcell=$1
models=$2
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=SCRIPTDIR/interop_lib.sh
source "$here/interop_lib.sh"
interop_require_node
interop_temp_dir
export SKILLCELL_INTEROP_PKI="$tmp/pki"  # node-opcua's certificates: never under $HOME
mkfifo "$tmp/ready"
timeout 170 node "$here/skill_server.js" "$models" >"$tmp/ready" 2>"$tmp/server.log" &
pid=$!
exec 3<"$tmp/ready"
if ! read -r -t 60 word url good bad <&3 || [ "$word" != READY ]; then
  echo "node-opcua skill server did not become ready:" >&2; cat "$tmp/server.log" >&2; exit 1
fi
echo "node-opcua skill server at $url (conforming skill under $good, broken one under $bad)"

fail() { echo "FAILED: $*" >&2; exit 1; }
# Runs `skillcell check`, shows its output, and compares its exit code.
check() {
  local want=$1; shift
  local rc=0
  timeout 60 "$skillcell" check --insecure "$@" >"$tmp/out" 2>"$tmp/err" || rc=$?
  echo "--- skillcell check $* (exit $rc)"
  if [ "${quiet:-0}" = 1 ]; then wc -c <"$tmp/out" | sed 's/$/ bytes on stdout/'; else cat "$tmp/out"; fi
  cat "$tmp/err"
  [ "$rc" = "$want" ] || fail "skillcell check $*: exit $rc, expected $want"
}
expect_line() { grep -qF -- "$1" "$tmp/out" || fail "missing line: $1"; }

check 0 "$url" --start "$good"
expect_line "RESULT: PASS"
expect_line "PASS  Good/Move  ParameterSet/TargetPosition: Variable, 3DFrameType, 3DFrame"
expect_line "PASS  Good/Move  CurrentState value: Ready (Id i=2400, Number 12)"

check 0 "$url" --start "$good" --exercise --timeout 5000
expect_line "PASS  Good/Move  Resume in Ready: BadInvalidState"
expect_line "PASS  Good/Move  Halt in Ready: Good, event ReadyToHalted, CurrentState Halted"
expect_line "PASS  Good/Move  Reset in Halted: Good, event HaltedToReady, CurrentState Ready"
expect_line "PASS  Good/Move  Suspend in Running: Good, event RunningToSuspended, CurrentState Suspended"
expect_line "PASS  Good/Move  Reset in Suspended: BadInvalidState"
expect_line "PASS  Good/Move  Resume in Suspended: Good, event SuspendedToRunning"
expect_line "PASS  Good/Move  run: RunningToReady"
expect_line "PASS  Good/Move  exercise end: left in Ready"

check 1 "$url" --start "$bad" --failures-only
expect_line "FAIL  Bad/Broken  Suspend: expected Method (required by the skill model"
expect_line "FAIL  Bad/Broken  CurrentState value: expected one of Halted, Ready, Running, Suspended, found 'Idle'"
if grep -q "^PASS" "$tmp/out"; then fail "--failures-only printed PASS lines"; fi

quiet=1 check 1 "$url" --json
node -e '
  const r = JSON.parse(require("fs").readFileSync(0, "utf8"));
  if (r.result !== "FAIL" || r.skills.length !== 2 || r.counts.fail < 2) process.exit(1);
  if (!r.findings.some((f) => f.verdict === "FAIL" && f.check === "Suspend")) process.exit(1);
' <"$tmp/out" || fail "--json: not the expected document"

check 2 "opc.tcp://127.0.0.1:1" --connect-timeout 1000

kill -0 "$pid" 2>/dev/null || { echo "the node-opcua server died:" >&2; cat "$tmp/server.log" >&2; exit 1; }
echo "ok"
