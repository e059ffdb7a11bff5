#!/usr/bin/env bash
# Interop: node-opcua loads our companion models (models/Skillcell.*.NodeSet2.xml) and
# instantiates every concrete skill type (load_skill_models.js). Skips (exit 77) when
# node-opcua is not installed, unless SKILLCELL_REQUIRE_NODE=1, as in CI.
# Usage: node_loads_skill_models.sh MODELS_DIR
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
if ! command -v node >/dev/null || [ ! -d "$here/node_modules/node-opcua" ]; then
  echo "!!! SKIPPED: node or node-opcua missing (run scripts/install-deps.sh) !!!" >&2
  [ "${SKILLCELL_REQUIRE_NODE:-0}" = 1 ] && exit 1
  exit 77
fi
exec timeout 120 node "$here/load_skill_models.js" "$1"
