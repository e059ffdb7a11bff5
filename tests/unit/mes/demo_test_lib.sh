# Shared by the demo's end-to-end tests (demo_test.sh, demo_din_rail_test.sh,
# demo_fuse_box_test.sh): source it after `set -euo pipefail`.
#   demo_require_netns   exits 77 (skipped) without the right to make a network namespace,
#                        or 1 when SKILLCELL_REQUIRE_NETNS=1 (as in CI);
#   tmp                  a fresh directory, removed on exit (demo_on_exit adds to that);
#   fail MESSAGE         prints it, the demo's output ($tmp/out) and its components' logs
#                        ($tmp/work/logs), and exits 1.
demo_require_netns() {
  if ! unshare -n true 2>/dev/null; then
    echo "!!! SKIPPED: cannot create a network namespace (not root?) !!!" >&2
    [ "${SKILLCELL_REQUIRE_NETNS:-0}" = 1 ] && exit 1
    exit 77
  fi
}
tmp=$(mktemp -d)
demo_on_exit=
trap 'eval "$demo_on_exit"; rm -rf "$tmp"' EXIT
fail() {
  echo "FAILED: $*" >&2
  echo "--- the demo's output (last 40 lines)"
  tail -n 40 "$tmp/out"
  for log in "$tmp"/work/logs/*.log; do
    [ -f "$log" ] && { echo "--- $log"; tail -n 15 "$log"; }
  done
  exit 1
}
