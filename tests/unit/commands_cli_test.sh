#!/usr/bin/env bash
# `skillcell` itself: every subcommand is listed by --help and reachable, with or without the
# global --log-level before it (only the subcommand named on the command line is built, so
# that a component's start does not build all of them: src/apps/main.cpp).
#   skillcell --help                              -> 0, every subcommand listed
#   skillcell, or an unknown subcommand           -> 2 (an unknown one named, with ours)
#   skillcell-component kb                        -> 2, its commands and where kb is
#   skillcell-component device [KIND] --help      -> 0, every kind; KIND's options
#   ... device robotiq --world-certificate MISSING -> 2, the option and the file named
#   skillcell [--log-level L] SUBCOMMAND --help   -> 0, that subcommand's own options
# Usage: commands_cli_test.sh PATH/TO/skillcell
set -euo pipefail
skillcell=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAILED: $*" >&2; exit 1; }

run() {  # run WANT ARGS...: skillcell ARGS (bounded), output in $tmp/out, exit code checked
  local want=$1; shift
  local rc=0
  timeout 30 "$skillcell" "$@" >"$tmp/out" 2>&1 || rc=$?
  [ "$rc" = "$want" ] || { cat "$tmp/out" >&2; fail "skillcell $*: exit $rc, expected $want"; }
}
expect() { grep -qE -- "$1" "$tmp/out" || { cat "$tmp/out" >&2; fail "missing in output: $1"; }; }

commands=(server browse lds discover skill check detect pki user nodeset2owl kb mes run demo
  cell process dashboard orders device)
run 0 --help
for c in "${commands[@]}"; do expect "^  $c( |$)"; done
run 2
expect "A subcommand is required"
run 2 no-such-command
expect "^skillcell: no command 'no-such-command'; it has: server, browse, lds"
run 0 server --help
expect "--noop-skill"
run 0 --log-level warn server --help
expect "--noop-skill"
run 0 --log-level=error lds --help
expect "--port"
run 0 --log-level debug device --help
expect "world"
run 2 --log-level nonsense server --help
# skillcell-component (beside skillcell): its three, and where the others are.
component=$(dirname "$skillcell")/skillcell-component
if [ -x "$component" ]; then
  rc=0
  timeout 30 "$component" kb >"$tmp/out" 2>&1 || rc=$?
  [ "$rc" = 2 ] || { cat "$tmp/out" >&2; fail "skillcell-component kb: exit $rc, expected 2"; }
  expect "^skillcell-component: no command 'kb'; it has: server, lds, device; the other commands are skillcell's"
  rc=0
  timeout 30 "$component" --log-level warn device --help >"$tmp/out" 2>&1 || rc=$?
  [ "$rc" = 0 ] || fail "skillcell-component device --help: exit $rc"
  for kind in world ur5 iiwa robotiq ag95 schmalz toolchanger pickplace; do expect "^  $kind "; done
  # Only the kind named is built: its options are there.
  rc=0
  timeout 30 "$component" device ur5 --help >"$tmp/out" 2>&1 || rc=$?
  [ "$rc" = 0 ] || fail "skillcell-component device ur5 --help: exit $rc"
  expect "--base"
  # A world certificate that is not there: refused before anything starts.
  rc=0
  timeout 30 "$component" device robotiq --world opc.tcp://127.0.0.1:1 \
    --world-certificate "$tmp/no-such.der" --port 0 >"$tmp/out" 2>&1 || rc=$?
  [ "$rc" = 2 ] || { cat "$tmp/out" >&2; fail "a missing --world-certificate: exit $rc, expected 2"; }
  expect "^--world-certificate: File does not exist: $tmp/no-such.der"
  ! grep -q '^READY' "$tmp/out" || fail "a missing --world-certificate started anyway"
fi
echo "every subcommand listed and reachable"
