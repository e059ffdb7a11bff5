# shellcheck shell=bash
# Sourced by the browser tests' scripts (needs $here, their directory): a skip (exit 77)
# without playwright-core (tests/browser: npm ci) or Debian's Chromium, unless
# SKILLCELL_REQUIRE_NODE=1 (CI), where that fails the test.
if [ ! -d "$here/node_modules/playwright-core" ] || [ ! -x /usr/bin/chromium ]; then
  echo "!!! SKIPPED: playwright-core (tests/browser: npm ci) or /usr/bin/chromium missing !!!" >&2
  [ "${SKILLCELL_REQUIRE_NODE:-0}" = 1 ] && exit 1
  exit 77
fi
