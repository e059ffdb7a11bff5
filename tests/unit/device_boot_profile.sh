#!/usr/bin/env bash
# The microcontroller boot profile of the gripper adapters (`--boot-profile tinyua`): the
# stages of the paper's TinyUA board run in order before the server listens (READY), at
# least as long as the paper measured (Robotiq 8.4 s); SIGTERM during the boot stops the
# process at once with status 0; without a profile there are no boot stages.
# Usage: device_boot_profile.sh PATH/TO/skillcell
set -euo pipefail
skillcell=${1:?usage: $0 PATH/TO/skillcell}
tmp=$(mktemp -d)
pid=""
cleanup() {
  [ -n "$pid" ] && kill -KILL "$pid" 2>/dev/null
  rm -rf "$tmp"
}
trap cleanup EXIT
fail() { echo "FAIL: $*" >&2; for f in "$tmp"/*.log; do echo "--- $f" >&2; cat "$f" >&2; done; exit 1; }

common=(--port 0 --host 127.0.0.1 --no-discovery --insecure)

# Waits (bounded) until FILE has a line matching REGEX.
wait_line() {
  local file=$1 regex=$2 seconds=$3 deadline=$((SECONDS + $3))
  until grep -qE "$regex" "$file" 2>/dev/null; do
    kill -0 "$pid" 2>/dev/null || fail "the process exited before '$regex'"
    [ $SECONDS -lt $deadline ] || fail "no '$regex' within $seconds s"
    sleep 0.05
  done
}

# 1. The whole boot, in order, and not faster than the board.
start_ns=$(date +%s%N)
"$skillcell" device robotiq "${common[@]}" --pki-dir "$tmp/pki-r" --boot-profile tinyua \
  >"$tmp/robotiq.out" 2>"$tmp/robotiq.log" &
pid=$!
wait_line "$tmp/robotiq.out" '^READY ' 30
elapsed_ms=$((($(date +%s%N) - start_ns) / 1000000))
stages=$(grep -oE 'boot: [^(]+' "$tmp/robotiq.log" | sed 's/ *$//' | paste -sd '|')
[ "$stages" = "boot: boot loader|boot: Wi-Fi join|boot: NTP time|boot: OPC UA application start" ] ||
  fail "boot stages: $stages"
[ "$elapsed_ms" -ge 8400 ] || fail "READY after $elapsed_ms ms, before the 8400 ms of the profile"
echo "robotiq with tinyua: READY after $elapsed_ms ms ($stages)"
kill -TERM "$pid"; wait "$pid" || fail "robotiq exited with $? after SIGTERM"
pid=""

# 2. The Schmalz board also initialises IO-Link; a SIGTERM in the Wi-Fi stage stops it.
"$skillcell" device schmalz "${common[@]}" --pki-dir "$tmp/pki-s" --boot-profile tinyua \
  >"$tmp/schmalz.out" 2>"$tmp/schmalz.log" &
pid=$!
wait_line "$tmp/schmalz.log" 'boot profile: 9600 ms' 10
wait_line "$tmp/schmalz.log" 'boot: Wi-Fi join' 10
kill -TERM "$pid"
rc=0
timeout 3 tail --pid="$pid" -f /dev/null || fail "schmalz did not stop within 3 s of SIGTERM in its boot"
wait "$pid" || rc=$?
pid=""
[ "$rc" = 0 ] || fail "schmalz exited with $rc after SIGTERM during its boot"
grep -q '^READY' "$tmp/schmalz.out" && fail "schmalz printed READY although stopped during its boot"
grep -q 'signal 15 during boot (Wi-Fi join)' "$tmp/schmalz.log" || fail "no log of the stop"
echo "schmalz with tinyua: stopped during 'Wi-Fi join', status 0"

# 3. The fast path: no profile, no boot stages.
"$skillcell" device robotiq "${common[@]}" --pki-dir "$tmp/pki-f" \
  >"$tmp/fast.out" 2>"$tmp/fast.log" &
pid=$!
wait_line "$tmp/fast.out" '^READY ' 20
grep -q 'boot:' "$tmp/fast.log" && fail "boot stages without a profile"
kill -TERM "$pid"; wait "$pid" || fail "robotiq (fast) exited with $?"
pid=""
echo "PASS"
