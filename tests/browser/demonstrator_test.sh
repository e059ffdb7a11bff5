#!/usr/bin/env bash
# One of the paper's demonstrators in a real browser (Debian's Chromium, driven by
# playwright-core): `skillcell cell up examples/cells/NAME.toml` brings up the cell in its own
# network namespace; NAME.test.js (dashes as underscores) runs its process from the dashboard
# as the Operator and watches the picture show the result: the terminal blocks snapped onto
# the rail side by side (din-rail), the fuses seated in their slots (fuse-box), each box
# where its branch put it (two-robots). Then the journal, read by SQLite itself, must show the
# order completed, its STEPS steps finished.
# SCREENSHOT_DIR (if set) receives the picture.
# Usage: demonstrator_test.sh SKILLCELL_BINARY SOURCE_DIR NAME STEPS
set -euo pipefail
skillcell=$1
src=$2
name=$3
count=$4
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=require_browser.sh
source "$here/require_browser.sh"
# shellcheck source=../support/cell_up.sh
source "$src/tests/support/cell_up.sh"

up_with_dashboard "$skillcell" "$src/examples/cells/$name.toml" --speed 20

DASHBOARD_URL="$page" DASHBOARD_SPKI="$spki" CELL_WORK_DIR="$work" \
  nsenter --net="$netns" node "$here/${name//-/_}.test.js" || fail "in the browser"

runs=$(sqlite3 "$work/journal.sqlite" "SELECT group_concat(state, ' ') FROM runs")
[ "$runs" = "completed" ] || fail "the journal's orders: $runs"
steps=$(sqlite3 "$work/journal.sqlite" \
  "SELECT group_concat(idx || ':' || state, ' ') FROM (SELECT * FROM steps WHERE run = 1 ORDER BY idx)")
expected=$(for i in $(seq "$count"); do printf '%s:finished ' "$i"; done)
[ "$steps" = "${expected% }" ] || fail "the journal's steps: $steps"
echo "ok  the journal: the order completed, its $count steps finished"
down "$skillcell"
