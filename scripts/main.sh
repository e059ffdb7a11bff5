#!/usr/bin/env bash
# The main job, until the demo of a whole work cell exists: installs what is missing,
# builds, starts the demo OPC UA server, browses it with our client, runs node-opcua's
# client against it (browse from Root, read every attribute, write, call), and stops it.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake --preset default >/dev/null
cmake --build --preset default -j "$(nproc)" --target skillcell

tmp=$(mktemp -d)
pid=""
cleanup() {
  [ -n "$pid" ] && kill "$pid" 2>/dev/null && wait "$pid" 2>/dev/null
  rm -rf "$tmp"
}
trap cleanup EXIT
mkfifo "$tmp/ready"
build/src/apps/skillcell server --port "${PORT:-4840}" --host 127.0.0.1 >"$tmp/ready" &
pid=$!
exec 3<"$tmp/ready"
read -r -t 20 word url <&3 && [ "$word" = READY ] || { echo "server did not start" >&2; exit 1; }

echo "== our client browses $url"
build/src/apps/skillcell browse "$url" --values --max-depth 4
echo
echo "== node-opcua's client against our server"
node tests/interop/client.js "$url"
