#!/usr/bin/env bash
# `skillcell cell check`: exit 0 and the cell's parts for the paper's cell; exit 1 and every
# problem as FILE:LINE:COLUMN on stderr for a wrong one, with nothing on stdout; exit 2
# without a file.
# Usage: cell_check_cli.sh PATH/TO/skillcell SOURCE_DIR
set -euo pipefail
skillcell=$1
src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

"$skillcell" cell check "$src/examples/cells/paper.toml" >"$tmp/out" 2>"$tmp/err" ||
  fail "the paper's cell: exit $?; $(cat "$tmp/err")"
grep -q '^cell paper ' "$tmp/out" || fail "no 'cell paper' line: $(cat "$tmp/out")"
grep -q 'tool *parallel *in dockP, adapter robotiq-2f85, pin 1.00-1.50 V' "$tmp/out" ||
  fail "the parallel tool is not listed as the file has it: $(cat "$tmp/out")"

bad=$src/tests/data/cells/several_problems.toml
rc=0
"$skillcell" cell check "$bad" >"$tmp/out" 2>"$tmp/err" || rc=$?
[ "$rc" = 1 ] || fail "a wrong file: exit $rc, expected 1"
[ ! -s "$tmp/out" ] || fail "a wrong file printed on stdout: $(cat "$tmp/out")"
grep -q "^$bad:7:12: 'mdns-ttl' in \[network\]" "$tmp/err" || fail "no 7:12 problem: $(cat "$tmp/err")"
grep -q "^$bad:12:9: robot 'ur5': model 'ur6'" "$tmp/err" || fail "no 12:9 problem: $(cat "$tmp/err")"
grep -q '^3 problems; nothing would start$' "$tmp/err" || fail "no count: $(cat "$tmp/err")"

rc=0
"$skillcell" cell check >/dev/null 2>&1 || rc=$?
[ "$rc" = 2 ] || fail "no file: exit $rc, expected 2 (usage)"
echo OK
