#!/usr/bin/env bash
# The main job: installs what is missing, builds, and runs `skillcell demo`, the paper's work
# cell with security on, every component a process that finds the others by mDNS inside a
# private network namespace (so it needs root): it clocks how long each component takes to
# be detected, runs the paper's process through the MES with its progress, and prints the
# world state, the MES's journal and the detection times beside the paper's (docs/demo.md).
# Arguments go to `skillcell demo` (e.g. --speed 50 --boot-profile none --keep-running).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh --main
cmake --preset default >/dev/null
cmake --build --preset default -j "$(nproc)" --target skillcell skillcell-component
exec build/src/apps/skillcell demo "$@"
