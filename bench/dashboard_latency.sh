#!/usr/bin/env bash
# Benchmark: the time from a skill's transition on its server to its appearance in the
# dashboard's page (the DOM of headless Chromium), p50 and p99. Goal (issue 24): p50 at most
# 100 ms. The cell is tests/browser/cell.sh's, in a private network namespace; the runs are
# the Operator's Starts of a gripper's skill from the page. Both ends read the same clock
# (one machine): the transition's time is the server's event Time, the appearance is
# Date.now() in a MutationObserver of the page.
# Usage: bench/dashboard_latency.sh SKILLCELL_BINARY [RUNS]   (root: it makes a namespace)
set -euo pipefail
if [ "${1:-}" != "--inside" ]; then
  exec "$(dirname "$0")/../tests/netns/run_in_private_netns.sh" "$0" --inside "$@"
fi
shift
skillcell=$1
runs=${2:-50}
here=$(cd "$(dirname "$0")/../tests/browser" && pwd)
if [ ! -d "$here/node_modules/playwright-core" ] || [ ! -x /usr/bin/chromium ]; then
  echo "dashboard_latency: needs /usr/bin/chromium and tests/browser's npm ci" >&2
  exit 2
fi
# shellcheck source=../tests/browser/cell.sh
source "$here/cell.sh"
DASHBOARD_URL="$url" DASHBOARD_SPKI="$spki" RUNS="$runs" \
  NODE_PATH="$here/node_modules" node "$(dirname "$0")/dashboard_latency.js"
