#!/usr/bin/env bash
# `skillcell process check`: the paper's process and the one docs/processes.md teaches are
# clean (exit 0, their steps listed); a file
# with a misspelt parameter gives FILE:LINE and the parameters the type has (exit 1); several
# files are all checked; a missing file or an unreachable KB is exit 2.
# Usage: process_check_cli.sh PATH/TO/skillcell SOURCE_DIR
set -euo pipefail
skillcell=$1
src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

# The paper's process names the docks of the paper's cell: alone, those are problems.
rc=0
"$skillcell" process check "$src/models/owl/demo-process.ttl" >/dev/null 2>"$tmp/err" || rc=$?
[ "$rc" = 1 ] || fail "the paper's process without its cell: exit $rc, expected 1"
grep -q "demo-process.ttl:58: step step1, parameter ToolPosition: proc:derivedFrom dockP" \
  "$tmp/err" || fail "no problem for the cell's dock: $(cat "$tmp/err")"
"$skillcell" process check --cell "$src/examples/cells/paper.toml" \
  "$src/models/owl/demo-process.ttl" >"$tmp/out" 2>"$tmp/err" ||
  fail "the paper's process: exit $?; $(cat "$tmp/err")"
grep -q 'pickAndPlaceTwoBoxes>, 5 steps, clean' "$tmp/out" || fail "not clean: $(cat "$tmp/out")"
grep -qE '^  2 PickAndPlaceSkillType MoveSkillControllerEndpoint ObjectId PlacePosition ToolSkillControllerEndpoint$' \
  "$tmp/out" || fail "step 2 not listed: $(cat "$tmp/out")"

# The process that docs/processes.md teaches, its Turtle blocks put together, is clean.
awk '/^```turtle$/ {on=1; next} /^```$/ {on=0} on' "$src/docs/processes.md" >"$tmp/doc.ttl"
"$skillcell" process check "$tmp/doc.ttl" >"$tmp/out" 2>"$tmp/err" ||
  fail "the process of docs/processes.md: $(cat "$tmp/err")"
grep -q 'myProcess>, 2 steps, clean' "$tmp/out" || fail "docs/processes.md: $(cat "$tmp/out")"

bad=$src/tests/data/processes/unknown_parameter.ttl
rc=0
"$skillcell" process check "$bad" "$src/tests/data/processes/cycle.ttl" >"$tmp/out" \
  2>"$tmp/err" || rc=$?
[ "$rc" = 1 ] || fail "bad files: exit $rc, expected 1"
grep -q "^$bad:18: step s1, parameter PlacePositon: the ParameterSet of PickAndPlaceSkillType has no such parameter; it has .*PlacePosition" \
  "$tmp/err" || fail "no FILE:LINE problem: $(cat "$tmp/err")"
grep -q "cycle.ttl:14: process p: proc:next makes a cycle" "$tmp/err" ||
  fail "the second file was not checked: $(cat "$tmp/err")"

rc=0
"$skillcell" process check "$tmp/none.ttl" >/dev/null 2>&1 || rc=$?
[ "$rc" = 2 ] || fail "a missing file: exit $rc, expected 2"
# Nothing listens on port 9 of the loopback (discard): the KB cannot be reached.
rc=0
"$skillcell" process check --kb http://127.0.0.1:9/sparql "$bad" >/dev/null 2>"$tmp/err" || rc=$?
[ "$rc" = 2 ] || fail "an unreachable KB: exit $rc, expected 2"
grep -q 'the skill models' "$tmp/err" || fail "no reason: $(cat "$tmp/err")"
echo OK
