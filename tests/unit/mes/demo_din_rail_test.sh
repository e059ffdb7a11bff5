#!/usr/bin/env bash
# The paper's second demonstrator end to end: `skillcell demo --cell examples/cells/din-rail.toml`
# (quick: high speed, no boot profile, one detection run per component). The whole cell starts
# as processes and the MES runs the cell's own process (examples/processes/din-rail.ttl) with
# not one line of MES code for it. The evidence holds:
#   - the world model: tb1, tb2 and tb3 snapped on rail1 side by side at their width (2.6,
#     7.8, 13.0 mm from its start), lying flat on it, no tool mounted;
#   - the MES's journal, read by SQLite: one completed run of 5 steps, each finished at the
#     first attempt, steps 2-4 by the PlaceTerminalBlock skill.
# The demo makes its own network namespace (root). Without root the test is skipped (77),
# unless SKILLCELL_REQUIRE_NETNS=1, as in CI.
# Usage: demo_din_rail_test.sh PATH/TO/skillcell SOURCE_DIR
set -euo pipefail
skillcell=$1
source_dir=$2
# shellcheck source=demo_test_lib.sh
source "$(dirname "$0")/demo_test_lib.sh"
demo_require_netns

rc=0
timeout 600 "$skillcell" demo --cell "$source_dir/examples/cells/din-rail.toml" --speed 50 \
  --boot-profile none --runs 1 --work-dir "$tmp/work" >"$tmp/out" 2>&1 || rc=$?
cat "$tmp/out"
[ "$rc" = 0 ] || fail "skillcell demo exited $rc"

expect() { grep -qE -- "$1" "$tmp/out" || fail "missing in the demo's output: $1"; }
expect 'outcome: Finished'
# Each block on the rail at its place, flat on the rail's face (z = 7.5 mm + half its height).
for b in 'tb1 2\.6' 'tb2 7\.8' 'tb3 13\.0'; do
  set -- $b
  grep -A1 "World/Objects/$1/Pose" "$tmp/out" | grep -q "on rail rail1 at $2 mm" ||
    fail "$1 is not on rail1 at $2 mm"
  grep "World/Objects/$1/Pose" "$tmp/out" | grep -qE '0\.300, 0\.025 \| 0\.000, -?0\.000, 0\.000' ||
    fail "$1 does not lie flat on the rail"
done
grep -E 'World/Robots/[^/]+/MountedTool' "$tmp/out" | grep -q '""' || fail "a tool is still mounted"

journal=$tmp/work/journal.sqlite
runs=$(sqlite3 "$journal" "SELECT group_concat(state, ' ') FROM runs")
[ "$runs" = "completed" ] || fail "journal runs: $runs"
steps=$(sqlite3 "$journal" "SELECT group_concat(idx || ':' || attempt || ':' || state, ' ') \
  FROM (SELECT * FROM steps WHERE run = 1 ORDER BY idx, attempt)")
[ "$steps" = "1:1:finished 2:1:finished 3:1:finished 4:1:finished 5:1:finished" ] ||
  fail "journal steps: $steps"
echo "ok"
