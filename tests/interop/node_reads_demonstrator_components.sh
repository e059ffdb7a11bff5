#!/usr/bin/env bash
# Interop: node-opcua browses and reads every node (client.js --strict) of the demonstrators'
# new parts: the world model with a DIN rail and terminal blocks (on no rail yet: an empty
# Rail and a NaN RailPosition), a fuse slot and a fuse, and the pick-and-place component with
# its PlaceTerminalBlock and InsertFuse skills (from the CompositeSkills companion model).
# Usage: node_reads_demonstrator_components.sh PATH/TO/skillcell
# Skips (77) without node-opcua unless SKILLCELL_REQUIRE_NODE=1.
set -euo pipefail
skillcell=$1
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=SCRIPTDIR/interop_lib.sh
source "$here/interop_lib.sh"
interop_require_node
interop_temp_dir
common=(--port 0 --host 127.0.0.1 --no-discovery --insecure)

interop_start world 20 "$skillcell" device world "${common[@]}" --pki-dir "$tmp/pki-world" \
  --rail 'rail1:0.2@0.3,0.3,0.0075' \
  --terminal-block 'tb1:0.0052,0.045,0.035@0.45,0,0.0175' \
  --terminal-block 'tb2:0.0052,0.045,0.035@0.48,0,0.0175' \
  --fuse-slot 'F1@0.5,0.2,0.05' --fuse 'fuse1:0.0191,0.0051,0.0185@0.3,0.1,0.00925'
pid=$last_pid
world=$url
echo "world ready at $world"
timeout 90 node "$here/client.js" "$world" --strict --no-demo || {
  tail -n 40 "$tmp/world.log" >&2
  exit 1
}

interop_start pickplace 20 "$skillcell" device pickplace "${common[@]}" \
  --pki-dir "$tmp/pki-pickplace" --world "$world"
pickplace=$last_pid
echo "pick-and-place ready at $url"
status=0
timeout 90 node "$here/client.js" "$url" --strict --no-demo || status=$?
kill "$pickplace" 2>/dev/null && wait "$pickplace" 2>/dev/null || true
[ $status -eq 0 ] || { tail -n 40 "$tmp/pickplace.log" >&2; exit 1; }
echo ok
