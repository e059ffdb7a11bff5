#!/usr/bin/env bash
# Interop: node-opcua's client calls the world model's methods (`skillcell device world`) with
# the server's default security: MoveTool and AddRobot (Engineer's), and the per-robot ones
# naming their robot (SetFlangePose, DockAtFlange, MountTool, UnmountTool, ObjectAtGripPoint,
# Grasp, Release), and the role check.
# Usage: node_world_move_tool.sh PATH/TO/skillcell
#   1. an Operator and an Engineer (`skillcell user add`); the world with its default robot
#      `robot`, docks d1, d2, d3, the tools parallel (in d1) and suction (in d2), and a box,
#      on loopback;
#   2. node's first connection is refused, its certificate trusted with `skillcell pki trust`;
#   3. world_move_tool.js as the operator (MoveTool and AddRobot refused, SetFlangePose for an
#      unknown robot BadNotFound, nothing changed), then as the engineer (the move; AddRobot of
#      robot2, browsed and read back; robot2 moved to d2, mounting suction, grasping and
#      releasing the box while `robot` stays put; bad input (another structure than a
#      3DFrame included), taken ids, an empty and an unknown robot id with their exact status
#      codes; a new session reads the result);
#   4. the refusals are in the world's log, each with its reason (a wrong structure is the
#      Call service's, never the world's), and the world is still running and stops cleanly;
#   5. the world killed (SIGKILL) and started again on its state file, where it was:
#      world_move_tool.js --as restored (robot2 as left; a Grasp BadWaitingForInitialData until
#      its flange is reported again, then Good).
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
printf '%s\n' 'eng-secret-2' | "$skillcell" user add engineer --role Engineer --pki-dir "$pki"

world=("$skillcell" device world --host 127.0.0.1 --no-discovery --pki-dir "$pki"
  --dock 'd1@0.4,-0.3,0.1' --dock 'd2@0.5,-0.3,0.1' --dock 'd3@0.6,-0.3,0.1'
  --tool 'parallel:d1@0,0,0.15' --tool 'suction:d2@0,0,0.12' --object 'box:0.04,0.04,0.04@0.2,0.2,0.42'
  --state-file "$tmp/world.json")
interop_start world 20 "${world[@]}" --port 0
pid=$last_pid
echo "world ready at $url"
fail() { echo "FAIL: $*" >&2; echo "world log:" >&2; tail -n 60 "$tmp/world.log" >&2; exit 1; }

# common.js's connect(): Aes256_Sha256_RsaPss/SignAndEncrypt, node's own PKI (and self-signed
# certificate) in $tmp, the user from SKILLCELL_NODE_USER.
export SKILLCELL_NODE_SECURITY=SignAndEncrypt SKILLCELL_NODE_PKI=$tmp/node
node_as() {
  local user=$1
  shift
  SKILLCELL_NODE_USER=$user timeout 30 node "$here/world_move_tool.js" "$url" "$@"
}

node_as operator:op-secret-1 --expect-untrusted || fail "the untrusted client was not refused"
shopt -s nullglob
rejected=("$pki"/rejected/certs/*.der)
[ ${#rejected[@]} -eq 1 ] || fail "expected node's certificate in rejected/, found ${#rejected[@]}"
"$skillcell" pki trust "${rejected[0]}" --pki-dir "$pki" || fail "skillcell pki trust failed"

node_as operator:op-secret-1 --as operator || fail "world_move_tool.js as the operator"
node_as engineer:eng-secret-2 --as engineer || fail "world_move_tool.js as the engineer"

# The server's side of the refusals: the role check, then the World's own.
for method in MoveTool AddRobot; do
  grep -q "Call of .*World.$method refused (BadUserAccessDenied)" "$tmp/world.log" ||
    fail "the operator's $method refusal was not logged"
done
! grep -q "Call of .*World.SetFlangePose refused (BadUserAccessDenied)" "$tmp/world.log" ||
  fail "SetFlangePose (an Operator's method) refused to the operator"
for status in BadNotFound BadInvalidState; do
  grep -q "world: MoveTool refused ($status)" "$tmp/world.log" || fail "no MoveTool refusal with $status logged"
done
grep -q "world: AddRobot refused (BadNodeIdExists): id robot2 is taken" "$tmp/world.log" ||
  fail "the second AddRobot of robot2 was not logged"
grep -q "world: AddRobot refused (BadInvalidArgument): empty robot id" "$tmp/world.log" ||
  fail "AddRobot's refusal of an empty id was not logged"
for method in SetFlangePose MountTool UnmountTool Grasp Release DockAtFlange ObjectAtGripPoint; do
  grep -q "world: $method refused (BadNotFound): no robot nosuchrobot in the world" "$tmp/world.log" ||
    fail "no $method refusal for the unknown robot logged"
done
for method in SetFlangePose Release DockAtFlange; do
  grep -q "world: $method refused (BadInvalidArgument): empty robot id" "$tmp/world.log" ||
    fail "no $method refusal of an empty robot id logged"
done
grep -q "world: AddRobot refused (BadOutOfRange): Base holds a NaN or infinite number" "$tmp/world.log" ||
  fail "AddRobot's refusal of a NaN in the base was not logged with its reason"
! grep -q "world: [A-Za-z]* refused (BadTypeMismatch)" "$tmp/world.log" ||
  fail "a wrongly typed argument reached the world (the Call service's check let it through)"
! grep -Eq "world: [A-Za-z]+ refused \([A-Za-z]+\): *$" "$tmp/world.log" ||
  fail "a refusal was logged without its reason: $(grep -E "world: [A-Za-z]+ refused \([A-Za-z]+\): *$" "$tmp/world.log" | head -n 1)"
kill -0 "$pid" 2>/dev/null || fail "the world died during the test"

# Killed, and started again where it was on its state file.
kill -KILL "$pid"
wait "$pid" || true
port=${url##*:}
interop_start world2 20 "${world[@]}" --port "$port"
pid=$last_pid
node_as operator:op-secret-1 --as restored || fail "world_move_tool.js on the restored world"
grep -q "world: Grasp refused (BadWaitingForInitialData)" "$tmp/world2.log" ||
  fail "the restored world's Grasp refusal was not logged"
kill -0 "$pid" 2>/dev/null || fail "the restored world died during the test"
kill -TERM "$pid"
for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
kill -0 "$pid" 2>/dev/null && fail "the world still runs 5 s after SIGTERM"
wait "$pid" || fail "the world did not exit 0 on SIGTERM"
pid=""
echo "OK"
