#!/usr/bin/env bash
# Runs a command in a private network namespace whose only interface is a multicast-capable
# loopback, so that mDNS traffic never leaves the test. Needs root (CI runs as root);
# without it the test is skipped (exit 77), unless SKILLCELL_REQUIRE_NETNS=1, as in CI.
# Usage: run_in_private_netns.sh COMMAND [ARGS...]
set -euo pipefail
if ! unshare -n true 2>/dev/null; then
  echo "!!! SKIPPED: cannot create a network namespace (not root?) !!!" >&2
  [ "${SKILLCELL_REQUIRE_NETNS:-0}" = 1 ] && exit 1
  exit 77
fi
exec unshare -n -- bash -c '
  set -e
  ip link set lo up
  ip link set lo multicast on
  ip route add 224.0.0.0/4 dev lo
  exec "$@"' run_in_private_netns "$@"
