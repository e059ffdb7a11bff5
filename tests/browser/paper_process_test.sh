#!/usr/bin/env bash
# The paper's process started from the dashboard in a real browser (Debian's Chromium,
# driven by playwright-core): `skillcell cell up examples/cells/paper.toml` brings up the
# whole cell (LDS, KB with Virtuoso and Konclude, world, tool changer, UR5, pick-and-place,
# MES, dashboard) in its own network namespace; paper_process.test.js runs inside it, tries
# the process as the Observer (refused), runs it as the Operator and watches it complete.
# Then the journal, read by SQLite itself, must show that order, its five steps finished, and
# the second order (of a process that waits for a gripper no component offers), cancelled
# from the page.
# SCREENSHOT_DIR (if set) receives the pictures.
# Usage: paper_process_test.sh SKILLCELL_BINARY SOURCE_DIR
set -euo pipefail
skillcell=$1
src=$2
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=require_browser.sh
source "$here/require_browser.sh"
# shellcheck source=../support/cell_up.sh
source "$src/tests/support/cell_up.sh"

# Speed 20: a process of some seconds, slow enough to watch, quick enough for CI.
up_with_dashboard "$skillcell" "$src/examples/cells/paper.toml" --speed 20
# A process that waits for a gripper's MoveGripper, which no component offers while no tool is
# mounted: its order, run from the page, stays at the MES until the page cancels it. Added
# by the Engineer, as an integrator would.
kb=$(sed -n 's/^ *kb  *\(opc\.tcp:[^ ]*\).*/\1/p' "$tmp/up.out" | head -1)
[ -n "$kb" ] || fail "cell up printed no knowledge base endpoint"
nsenter --net="$netns" "$skillcell" process add "$src/tests/data/mes/waits_for_a_gripper.ttl" \
  --kb "$kb" --pki-dir "$work/pki-operator" --user engineer \
  --password-file "$work/engineer.pw" >"$tmp/add.out" 2>&1 ||
  { cat "$tmp/add.out" >&2; fail "process add"; }

DASHBOARD_URL="$page" DASHBOARD_SPKI="$spki" CELL_WORK_DIR="$work" \
  nsenter --net="$netns" node "$here/paper_process.test.js" || fail "in the browser"

runs=$(sqlite3 "$work/journal.sqlite" "SELECT group_concat(state, ' ') FROM runs")
[ "$runs" = "completed cancelled" ] || fail "the journal's orders: $runs"
steps=$(sqlite3 "$work/journal.sqlite" \
  "SELECT group_concat(idx || ':' || state, ' ') FROM (SELECT * FROM steps WHERE run = 1 ORDER BY idx)")
[ "$steps" = "1:finished 2:finished 3:finished 4:finished 5:finished" ] ||
  fail "the journal's steps: $steps"
echo "ok  the journal: order 1 completed, its five steps finished; order 2 cancelled"
down "$skillcell"
