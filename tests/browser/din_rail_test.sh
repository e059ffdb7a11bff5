#!/usr/bin/env bash
# The DIN-rail demonstrator in a real browser (Debian's Chromium, driven by playwright-core):
# `skillcell cell up examples/cells/din-rail.toml` brings up the cell in its own network
# namespace; din_rail.test.js runs its process from the dashboard as the Operator and watches
# the picture show the rail and the three terminal blocks snapped onto it, side by side. Then
# the journal, read by SQLite itself, must show the order completed, its five steps finished.
# SCREENSHOT_DIR (if set) receives the picture.
# Usage: din_rail_test.sh SKILLCELL_BINARY SOURCE_DIR
set -euo pipefail
skillcell=$1
src=$2
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=require_browser.sh
source "$here/require_browser.sh"
# shellcheck source=../support/cell_up.sh
source "$src/tests/support/cell_up.sh"

"$skillcell" cell up "$src/examples/cells/din-rail.toml" --speed 20 --work-dir "$work" \
  >"$tmp/up.out" 2>"$tmp/up.err" &
supervisor=$!
for _ in $(seq 600); do
  grep -q 'is up' "$tmp/up.out" && break
  kill -0 "$supervisor" 2>/dev/null || break
  sleep 0.5  # a bounded poll of the output a child process writes
done
grep -q 'is up' "$tmp/up.out" || fail "the cell did not come up"
page=$(grep -o 'PAGE https://[^ ]*' "$tmp/up.out" | head -1 | cut -d' ' -f2)
netns=$(grep -o '/proc/[0-9]*/ns/net' "$tmp/up.out" | head -1)
[ -n "$page" ] && [ -n "$netns" ] || fail "cell up printed no dashboard page or network"
spki=$(openssl x509 -inform der -in "$work/pki-dashboard/own/certs/cert.der" -pubkey -noout |
  openssl pkey -pubin -outform der | openssl dgst -sha256 -binary | base64)

DASHBOARD_URL="$page" DASHBOARD_SPKI="$spki" CELL_WORK_DIR="$work" \
  nsenter --net="$netns" node "$here/din_rail.test.js" || fail "in the browser"

runs=$(sqlite3 "$work/journal.sqlite" "SELECT group_concat(state, ' ') FROM runs")
[ "$runs" = "completed" ] || fail "the journal's orders: $runs"
steps=$(sqlite3 "$work/journal.sqlite" \
  "SELECT group_concat(idx || ':' || state, ' ') FROM (SELECT * FROM steps WHERE run = 1 ORDER BY idx)")
[ "$steps" = "1:finished 2:finished 3:finished 4:finished 5:finished" ] ||
  fail "the journal's steps: $steps"
echo "ok  the journal: the order completed, its five steps finished"
"$skillcell" cell down --work-dir "$work" >/dev/null || fail "cell down"
rc=0
wait "$supervisor" || rc=$?
supervisor=
[ "$rc" = 0 ] || fail "cell up exited $rc"
