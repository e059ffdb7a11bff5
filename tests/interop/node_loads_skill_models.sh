#!/usr/bin/env bash
# Interop: node-opcua loads our companion models (models/Skillcell.*.NodeSet2.xml) and
# instantiates every concrete skill type (load_skill_models.js). Skips (exit 77) when
# node-opcua is not installed, unless SKILLCELL_REQUIRE_NODE=1, as in CI.
# Usage: node_loads_skill_models.sh MODELS_DIR
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=SCRIPTDIR/interop_lib.sh
source "$here/interop_lib.sh"
interop_require_node
exec timeout 120 node "$here/load_skill_models.js" "$1"
