#!/usr/bin/env bash
# Interop: node-opcua's client hands the semantic MES (`skillcell mes`) a process through its
# ExecuteProcess skill (execute_process.js), with the knowledge base (`skillcell kb
# --demo-process`, its own Virtuoso in a temporary directory) behind it and no cell: the MES
# reads the paper's process, finds before any motion that no component offers the skills of
# its steps and refuses it, naming each, a reason node-opcua receives in the RunningToHalted
# event; a process the KB does not know stops with that. Then node-opcua drives the MES's
# orders (orders.js): submits, lists, reads, follows and cancels one, and is refused with the
# precise status codes for bad input, a second cancel and unknown ids. Skips (exit 77) without node-opcua, unless SKILLCELL_REQUIRE_NODE=1 (CI).
# Usage: node_runs_mes_process.sh PATH/TO/skillcell
set -euo pipefail
skillcell=$1
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=SCRIPTDIR/interop_lib.sh
source "$here/interop_lib.sh"
interop_require_node
interop_temp_dir
mes_pid=""
trap 'if [ -n "$mes_pid" ]; then kill "$mes_pid" 2>/dev/null; wait "$mes_pid" 2>/dev/null; fi; interop_cleanup' EXIT

# A component on loopback, without discovery or security (interop_start: READY, $url).
start() {
  local name=$1 timeout=$2
  shift 2
  interop_start "$name" "$timeout" "$skillcell" "$@" --port 0 --host 127.0.0.1 --no-discovery \
    --insecure --pki-dir "$tmp/pki-$name"
}

waiting=$here/../data/mes/waits_for_a_gripper.ttl
start kb 120 kb --demo-process --process "$waiting" --http-port 0 --data-dir "$tmp/kb"
pid=$last_pid
sparql=$(sed -n 's/^SPARQL //p' "$tmp/kb.before")
start mes 20 mes --kb "$sparql" --journal "$tmp/journal.sqlite" --skill-wait-ms 300
mes_pid=$last_pid
echo "KB $sparql, MES $url"
fail() { echo "FAIL: $*" >&2; echo "MES log:" >&2; tail -n 40 "$tmp/mes.log" >&2; exit 1; }

timeout 120 node "$here/execute_process.js" "$url" http://skillcell.dev/demo#pickAndPlaceTwoBoxes \
  "halted:the cell cannot run http://skillcell.dev/demo#pickAndPlaceTwoBoxes: step 1 (ChangeToolSkillType): no component in the cell offers a ChangeToolSkillType; step 2" \
  reading checking refused || fail "the demo process without a cell"
timeout 120 node "$here/execute_process.js" "$url" http://skillcell.dev/demo#noSuchProcess \
  "halted:has no process <http://skillcell.dev/demo#noSuchProcess>" reading stopped ||
  fail "an unknown process"
timeout 120 node "$here/orders.js" "$url" http://skillcell.dev/test/orders#waitsForAGripper ||
  fail "orders through node-opcua"
kill -0 "$mes_pid" 2>/dev/null || fail "the MES died during the test"
echo "OK"
