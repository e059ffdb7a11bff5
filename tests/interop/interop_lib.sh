# shellcheck shell=bash
# The preamble every interop driver shares. Source it from a bash script running under
# set -euo pipefail.
#
#   interop_require_node     skips (exit 77) when node or node-opcua is missing; with
#                            SKILLCELL_REQUIRE_NODE=1 (CI) that is a failure (exit 1) instead.
#   interop_temp_dir         creates $tmp, removed at exit, and installs the trap that first
#                            stops the background process whose pid the driver keeps in $pid.
#   interop_start NAME TIMEOUT_S CMD...
#                            starts CMD in the background (stdout read here, stderr to
#                            $tmp/NAME.log) and waits, bounded, for its "READY <url>" line: sets
#                            $url and $last_pid; lines before READY (the KB's "SPARQL <url>") go
#                            to $tmp/NAME.before. A CMD that dies or stays silent: its log, exit 1.

INTEROP_HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)

interop_require_node() {
  if ! command -v node >/dev/null || [ ! -d "$INTEROP_HERE/node_modules/node-opcua" ]; then
    echo "!!! SKIPPED: node or node-opcua missing (run scripts/install-deps.sh) !!!" >&2
    [ "${SKILLCELL_REQUIRE_NODE:-0}" = 1 ] && exit 1
    exit 77
  fi
}

interop_cleanup() {
  if [ -n "${pid:-}" ]; then kill "$pid" 2>/dev/null && wait "$pid" 2>/dev/null; fi
  rm -rf "$tmp"
}

interop_temp_dir() {
  tmp=$(mktemp -d)
  pid=""
  trap interop_cleanup EXIT
}

interop_start() {
  local name=$1 timeout=$2
  shift 2
  mkfifo "$tmp/$name.out"
  "$@" >"$tmp/$name.out" 2>"$tmp/$name.log" &
  # shellcheck disable=SC2034 # for the caller
  last_pid=$!
  local fd word value
  exec {fd}<"$tmp/$name.out"
  url=""
  while read -r -t "$timeout" word value <&"$fd"; do
    if [ "$word" = READY ]; then url=$value; break; fi
    echo "$word $value" >>"$tmp/$name.before"
  done
  exec {fd}<&-
  if [ -z "$url" ]; then
    echo "$name did not start:" >&2
    tail -n 40 "$tmp/$name.log" >&2
    exit 1
  fi
}
