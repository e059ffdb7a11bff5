#!/usr/bin/env bash
# The dashboard in a real browser (Debian's Chromium, driven by playwright-core): a cell of
# two components with skills and the dashboard, all secured by a cell CA and the cell's
# users, in a private network namespace (tests/netns/run_in_private_netns.sh runs this).
# dashboard.test.js logs in, watches the components and their skills appear, stops one
# component and watches it go; SCREENSHOT_DIR (if set) receives the pictures.
# Usage: dashboard_test.sh SKILLCELL_BINARY
set -euo pipefail
skillcell=$1
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=require_browser.sh
source "$here/require_browser.sh"
# shellcheck source=cell.sh
source "$here/cell.sh"

rc=0
DASHBOARD_URL="$url" DASHBOARD_SPKI="$spki" GRIPPER_PID="$gripper" \
  node "$here/dashboard.test.js" || rc=$?
if [ "$rc" != 0 ]; then
  echo "--- dashboard's log" >&2
  tail -40 "$tmp/dashboard.err" >&2
fi
exit "$rc"
