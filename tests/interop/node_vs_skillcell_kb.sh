#!/usr/bin/env bash
# Interop: node-opcua's client against the knowledge base (`skillcell kb`): kb_query.js calls
# Query, Update and Load on Objects/KnowledgeBase. The KB starts its own Virtuoso in a temporary
# data directory and needs no discovery. Skips (exit 77) without node-opcua, unless
# SKILLCELL_REQUIRE_NODE=1 (CI).
# Usage: node_vs_skillcell_kb.sh PATH/TO/skillcell
set -euo pipefail
skillcell=$1
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=SCRIPTDIR/interop_lib.sh
source "$here/interop_lib.sh"
interop_require_node
interop_temp_dir
mkfifo "$tmp/out"
"$skillcell" kb --port 0 --host 127.0.0.1 --no-discovery --insecure --http-port 0 \
  --data-dir "$tmp/data" --pki-dir "$tmp/pki" >"$tmp/out" 2>"$tmp/kb.log" &
pid=$!
exec 3<"$tmp/out"
url=""
# "SPARQL <url>" first, then "READY <url>"; the first start creates Virtuoso's database.
while read -r -t 120 word value <&3; do
  if [ "$word" = READY ]; then url=$value; break; fi
done
if [ -z "$url" ]; then
  echo "the KB did not become ready:" >&2; cat "$tmp/kb.log" >&2; exit 1
fi
echo "KB ready at $url"
status=0
timeout 90 node "$here/kb_query.js" "$url" || status=$?
if ! kill -0 "$pid" 2>/dev/null; then
  echo "the KB died during the test:" >&2; cat "$tmp/kb.log" >&2; exit 1
fi
[ $status -eq 0 ] || { echo "KB log:" >&2; tail -n 50 "$tmp/kb.log" >&2; }
# A clean stop: exit 0, Virtuoso stopped with it.
kill -TERM "$pid"
wait "$pid" || { echo "the KB did not exit 0 on SIGTERM" >&2; exit 1; }
pid=""
exit $status
