#!/usr/bin/env bash
# Interop: a node-opcua client script against our server.
# Usage: node_script_vs_skillcell.sh PATH/TO/skillcell SCRIPT.js [-- SERVER ARGS... [-- SCRIPT ARGS...]]
# Starts `skillcell server --port 0 --insecure` (with the extra server arguments; SERVER ARGS
# that begin with `device NAME` start that device instead of `server`; the secured
# server has its own driver, node_secure_client_vs_skillcell.sh), learns its port from the READY line, runs the script
# with the server's URL (client.js: browse from Root, read every attribute of every node,
# write + read back, call; subscribe.js: data change after a write, event after
# Demo.FireEvent), and stops the server. The server's PKI (application certificate) goes to the
# temporary directory ($tmp/pki), never under $HOME. Skips (exit 77) when node-opcua is not installed, unless
# SKILLCELL_REQUIRE_NODE=1, as in CI, where that is a failure.
set -euo pipefail
skillcell=$1
script=$2
shift 2
server_args=()
script_args=()
if [ "${1:-}" = -- ]; then
  shift
  while [ $# -gt 0 ] && [ "$1" != -- ]; do server_args+=("$1"); shift; done
  [ "${1:-}" = -- ] && shift
  script_args=("$@")
fi
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=SCRIPTDIR/interop_lib.sh
source "$here/interop_lib.sh"
interop_require_node
interop_temp_dir
mkfifo "$tmp/ready"
command=(server)
if [ "${server_args[0]:-}" = device ]; then
  command=(device "${server_args[1]}")
  server_args=("${server_args[@]:2}")
fi
"$skillcell" "${command[@]}" --port 0 --host 127.0.0.1 --no-discovery --pki-dir "$tmp/pki" --insecure \
  ${server_args[@]+"${server_args[@]}"} >"$tmp/ready" 2>"$tmp/server.log" &
pid=$!
exec 3<"$tmp/ready"
if ! read -r -t 20 word url <&3 || [ "$word" != READY ]; then
  echo "server did not become ready:" >&2; cat "$tmp/server.log" >&2; exit 1
fi
echo "server ready at $url"
status=0
timeout 90 node "$here/$script" "$url" ${script_args[@]+"${script_args[@]}"} || status=$?
if ! kill -0 "$pid" 2>/dev/null; then
  echo "our server died during the test:" >&2; cat "$tmp/server.log" >&2; exit 1
fi
[ $status -eq 0 ] || { echo "server log:" >&2; tail -n 50 "$tmp/server.log" >&2; }
exit $status
