#!/usr/bin/env bash
# `skillcell mes` and `skillcell run` given bad input: each exits with its code and says why.
#   run without a process, or with an MES nobody serves       -> 2
#   mes with a --kb that is not an http:// URL                -> 2
#   mes with a journal that cannot be opened                  -> 1, naming the file
#   demo with a boot profile, run count or speed it does not know -> 2, naming the option
# Usage: mes_cli_test.sh PATH/TO/skillcell
set -euo pipefail
skillcell=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAILED: $*" >&2; exit 1; }

# Runs skillcell ARGS (bounded), keeps stdout+stderr in $tmp/out and checks the exit code.
run() {
  local want=$1; shift
  local rc=0
  timeout 30 "$skillcell" "$@" >"$tmp/out" 2>&1 || rc=$?
  echo "--- skillcell $* (exit $rc)"; tail -n 3 "$tmp/out"
  [ "$rc" = "$want" ] || fail "skillcell $*: exit $rc, expected $want"
}
expect() { grep -qF -- "$1" "$tmp/out" || fail "missing in output: $1"; }

run 2 run
run 2 run http://skillcell.dev/demo#pickAndPlaceTwoBoxes --mes opc.tcp://127.0.0.1:1 --insecure
expect "cannot connect to the MES at opc.tcp://127.0.0.1:1"
common=(--port 0 --host 127.0.0.1 --no-discovery --insecure --pki-dir "$tmp/pki")
run 2 mes "${common[@]}" --kb ftp://127.0.0.1/sparql --journal "$tmp/journal.sqlite"
expect "--kb ftp://127.0.0.1/sparql"
printf 'not a database, but long enough to look like a header of one.........\n' >"$tmp/bad.sqlite"
run 1 mes "${common[@]}" --kb http://127.0.0.1:1/sparql --journal "$tmp/bad.sqlite"
expect "$tmp/bad.sqlite"
# demo: options out of range are refused before anything starts.
run 2 demo --boot-profile fast
expect "--boot-profile"
run 2 demo --runs 0
expect "--runs"
run 2 demo --speed 0
expect "--speed"
echo "ok"
