#!/usr/bin/env bash
# A host whose link comes back asks the network again at once (RFC 6762, 5.2 and 13), instead
# of waiting for its next query, which the backoff may have put far away.
#   h1: a robot, `skillcell server --noop-skill ...`: announces, never queries
#   h2: a detector, `skillcell server --detect` with --mdns-query-period 3600: its queries go
#       out at 0, 1, 3, 7, 15, 31 ... s after it starts
# h2's link goes down 7.5 s after h2 started (after its query at 7 s), for 12.5 s: longer than
# the robot's records live (TTL 10 s), so h2 forgets it. Then the robot must be detected again
# within 1.5 s of the link coming up: before h2's next query by the backoff (at 15 s after the
# link went down... 31 s after its start), and before the robot would send its records again
# for their TTL (every 8 s or so). Only the link change explains it: h2 asks again at once.
# Usage: mdns_link_change.sh SKILLCELL_BINARY
# Needs root; otherwise exit 77 (exit 1 if SKILLCELL_REQUIRE_NETNS=1).
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=lib.sh
. "$here/lib.sh"

BIN=${1:?usage: mdns_link_change.sh SKILLCELL_BINARY}
[ -x "$BIN" ] || { echo "FAIL: $BIN is not an executable"; exit 1; }
BIN=$(realpath -- "$BIN")
T_START=$(now_ms)
say() { local t=$(($(now_ms) - T_START)); printf '[%d.%03ds] %s\n' $((t / 1000)) $((t % 1000)) "$*"; }
fail() { netns_fail "$*"; }

netns_trap
netns_setup_or_skip 2

start_in h1 robot "$BIN" server --port 4840 --application-uri urn:test:robot --mdns-ttl 10 \
  --mdns-query-period 3600 --pki-dir "$NETNS_DIR/pki-robot" --insecure \
  --noop-skill CartesianLinearMoveSkillType=Move
wait_for_line "$NETNS_DIR/robot.out" '^READY ' 15 >/dev/null || fail "the robot did not print READY"
h2_started=$(now_ms)
start_in h2 detector "$BIN" server --port 4840 --application-uri urn:test:detector --mdns-ttl 10 \
  --mdns-query-period 3600 --pki-dir "$NETNS_DIR/pki-detector" --insecure --detect
added='^SKILL ADDED CartesianLinearMoveSkillType urn:test:robot '
wait_for_line "$NETNS_DIR/detector.out" "$added" 15 >/dev/null ||
  fail "h2 did not detect the robot"
say "ok: h2 detects the robot"

# After h2's query at 7 s (sleeping until a moment on h2's clock is the point of this test).
sleep "$(awk -v ms=$((h2_started + 7500 - $(now_ms))) 'BEGIN { print (ms > 0 ? ms / 1000 : 0) }')"
from=$(($(line_count "$NETNS_DIR/detector.out") + 1))
link_down h2 || fail "link_down h2"
say "h2's link down"
wait_for_line "$NETNS_DIR/detector.out" '^SKILL REMOVED CartesianLinearMoveSkillType urn:test:robot ' \
  14 "$from" >/dev/null || fail "the robot's skill was not removed with h2's link down"
sleep "$(awk -v ms=$((h2_started + 20000 - $(now_ms))) 'BEGIN { print (ms > 0 ? ms / 1000 : 0) }')"
say "ok: the robot is gone from h2"
from=$(($(line_count "$NETNS_DIR/detector.out") + 1))
up_at=$(now_ms)
link_up h2 || fail "link_up h2"
[ $((up_at - h2_started)) -lt 28000 ] || fail "the link came up too late to tell the link change from the backoff"
wait_for_line_until "$NETNS_DIR/detector.out" "$added" $((up_at + 1500)) "$from" >/dev/null ||
  fail "h2 did not detect the robot within 1.5 s of its link coming up (its next query by the backoff is at 31 s)"
say "ok: h2 detects the robot again $(($(now_ms) - up_at)) ms after its link came up"
grep -q 'link .* up again' "$NETNS_DIR/detector.err" || fail "h2's log does not say why it asked again"

for p in robot detector; do stop_gracefully "$p"; done
say "PASS"
