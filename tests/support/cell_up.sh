# shellcheck shell=bash
# Sourced by the shell tests that bring a cell up with `skillcell cell up`, in a network
# namespace of the cell's own (tests/unit/cell/cell_up_cli.sh,
# tests/browser/paper_process_test.sh). It gives them:
#  - a skip (exit 77) where no network namespace can be made (not root), unless
#    SKILLCELL_REQUIRE_NETNS=1 (CI), where that fails the test;
#  - $tmp, a directory of their own, and $work, the cell's work directory in it;
#  - a trap that stops the cell whose supervisor's pid the test puts in $supervisor and
#    removes $tmp, even when the test fails;
#  - fail MESSAGE: prints it with the cell's output ($tmp/up*.out, .err) and the last lines of
#    each component's log, and exits 1;
#  - up_with_dashboard SKILLCELL CELL_FILE [ARGS...]: `cell up` in the background, waited for
#    (bounded); sets $page (the dashboard's URL), $netns (the cell's network) and $spki (the
#    pin of the dashboard's key, which the browser trusts as the cell CA's);
#  - down SKILLCELL: `cell down`, and the supervisor must exit 0.
if ! unshare -n true 2>/dev/null; then
  echo "!!! SKIPPED: cannot create a network namespace (not root?) !!!" >&2
  [ "${SKILLCELL_REQUIRE_NETNS:-0}" = 1 ] && exit 1
  exit 77
fi
tmp=$(mktemp -d)
work=$tmp/work
supervisor=
cleanup() {
  # A failed test must not leave its cell behind.
  if [ -n "$supervisor" ] && kill -0 "$supervisor" 2>/dev/null; then
    kill -TERM "$supervisor" 2>/dev/null || true
    timeout 60 tail --pid="$supervisor" -f /dev/null || kill -KILL "$supervisor" || true
  fi
  rm -rf "$tmp"
}
trap cleanup EXIT
fail() {
  echo "FAILED: $*" >&2
  for f in "$tmp"/up*.out "$tmp"/up*.err "$work"/logs/*.log; do
    [ -f "$f" ] && { echo "--- $f"; tail -n 20 "$f"; }
  done
  exit 1
}

up_with_dashboard() {
  local skillcell=$1 cell=$2
  shift 2
  "$skillcell" cell up "$cell" --work-dir "$work" "$@" >"$tmp/up.out" 2>"$tmp/up.err" &
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
}

down() {
  "$1" cell down --work-dir "$work" >/dev/null || fail "cell down"
  local rc=0
  wait "$supervisor" || rc=$?
  supervisor=
  [ "$rc" = 0 ] || fail "cell up exited $rc"
}
