#!/usr/bin/env bash
# `skillcell mes` and `skillcell run` given bad input: each exits with its code and says why.
#   run without a process, or with an MES nobody serves       -> 2
#   mes with a --kb that is not an http:// URL                -> 2
#   dashboard with such a --kb: 2, before its page is served
#   mes with a journal that cannot be opened                  -> 1, naming the file
#   demo with a boot profile, run count or speed it does not know -> 2, naming the option
#   orders: an order whose process cannot be read stops with the reason (run: 1); show gives
#   it; cancel of an ended or unknown order is refused (1); a second MES on the same journal
#   stands by and refuses orders (2) until the first ends, then takes over
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
# dashboard: a --kb that is not a SPARQL URL is refused before the page is served.
run 2 dashboard "${common[@]}" --kb ftp://127.0.0.1/sparql
expect "--kb ftp://127.0.0.1/sparql"
grep -q '^DASHBOARD ' "$tmp/out" && fail "the dashboard served its page before refusing --kb"
# demo: options out of range are refused before anything starts.
run 2 demo --boot-profile fast
expect "--boot-profile"
run 2 demo --runs 0
expect "--runs"
run 2 demo --speed 0
expect "--speed"

# Orders, on an MES whose knowledge base nobody serves: each order stops, saying why.
mes_url() {  # the URL of the MES whose output is $1, once it is READY (bounded: 20 s)
  for _ in $(seq 200); do
    url=$(sed -n 's/^READY //p' "$1" | head -n 1)
    [ -n "$url" ] && { echo "$url"; return 0; }
    sleep 0.1  # a bounded poll of the MES's output file
  done
  return 1
}
journal="$tmp/orders.sqlite"
"$skillcell" mes "${common[@]}" --kb http://127.0.0.1:1/sparql --journal "$journal" \
  >"$tmp/mes1.out" 2>&1 &
mes1=$!
trap 'kill $mes1 ${mes2:-} 2>/dev/null || true; rm -rf "$tmp"' EXIT
url=$(mes_url "$tmp/mes1.out") || fail "the MES did not start: $(cat "$tmp/mes1.out")"
run 1 run http://example.org/p --mes "$url" --insecure --timeout 20
expect "ORDER 1"
expect "OUTCOME Failed (cannot read the process http://example.org/p"
run 0 orders show 1 --mes "$url" --insecure
expect "order 1: stopped - cannot read the process"
run 0 orders --mes "$url" --insecure
expect "stopped"
run 1 orders cancel 99 --mes "$url" --insecure
expect "no order 99"
run 0 orders cancel 1 --mes "$url" --insecure
run 1 orders cancel 1 --mes "$url" --insecure
expect "has ended already"
run 2 orders show 99 --mes "$url" --insecure
# A second MES on the journal stands by: it serves, and refuses orders.
"$skillcell" mes "${common[@]}" --kb http://127.0.0.1:1/sparql --journal "$journal" \
  >"$tmp/mes2.out" 2>&1 &
mes2=$!
url2=$(mes_url "$tmp/mes2.out") || fail "the standby MES did not start: $(cat "$tmp/mes2.out")"
grep -q "stands by" "$tmp/mes2.out" || fail "the second MES does not say it stands by"
run 2 run http://example.org/p --mes "$url2" --insecure --no-wait
expect "the MES refused the order: the MES stands by"
# The first ends: the second takes the journal over and accepts orders.
kill $mes1; wait $mes1 || true
for _ in $(seq 100); do
  grep -q "the journal is ours now" "$tmp/mes2.out" && break
  sleep 0.1  # a bounded poll of the standby's output file
done
grep -q "the journal is ours now" "$tmp/mes2.out" || fail "the standby never took over"
run 0 run http://example.org/p --mes "$url2" --insecure --no-wait
expect "ORDER 2"
kill $mes2; wait $mes2 || true
echo "ok"
