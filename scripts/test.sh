#!/usr/bin/env bash
# The test command of the README and of CI: installs what is missing, builds, and runs
# every test once, under AddressSanitizer + UndefinedBehaviorSanitizer, the chaos suite's
# kills and restarts included; then runs each fuzz target for a short time. At
# the end (also when a phase fails) it prints how long each phase took, and after each test
# phase its slowest tests (docs/development.md has the figures and how to read them).
set -euo pipefail
cd "$(dirname "$0")/.."

export SKILLCELL_REQUIRE_NODE=1   # interop tests fail (not skip) when node-opcua is missing
export SKILLCELL_REQUIRE_NETNS=1  # and network-namespace tests when namespaces cannot be made
jobs=$(nproc)

phases=()
seconds=()
phase_start=$SECONDS
phase_name=""
begin() {  # begin NAME: ends the phase before, starts the next
  finish
  phase_name=$1
  phase_start=$SECONDS
  echo "== $1"
}
finish() {
  if [ -n "$phase_name" ]; then
    phases+=("$phase_name")
    seconds+=($((SECONDS - phase_start)))
    phase_name=""
  fi
}
report() {
  local status=$?
  [ -n "$phase_name" ] && phases+=("$phase_name (failed)") && seconds+=($((SECONDS - phase_start)))
  echo
  echo "== time per phase"
  printf '%-34s %8s\n' phase seconds
  local total=0
  for i in "${!phases[@]}"; do
    printf '%-34s %8d\n' "${phases[$i]}" "${seconds[$i]}"
    total=$((total + seconds[i]))
  done
  printf '%-34s %8d\n' total "$total"
  exit "$status"
}
trap report EXIT

# The slowest tests of a build directory's last run (CTest keeps each test's time there).
slowest() {
  local cost="$1/Testing/Temporary/CTestCostData.txt"
  [ -f "$cost" ] || return 0
  echo "-- slowest tests, seconds:"
  # No `head`: under pipefail, a reader that stops early fails the pipeline (SIGPIPE).
  awk '/^---/ { exit } NF >= 3 { printf "%8.1f  %s\n", $3, $1 }' "$cost" | sort -rn |
    awk 'NR <= 12'
}

begin install
bash scripts/install-deps.sh

begin "format check"
# Formatting is checked on every run; clang-tidy (scripts/lint.sh without LINT_SKIP_TIDY)
# takes too long on 2 cores for every run and is run by developers before they push.
LINT_SKIP_TIDY=1 bash scripts/lint.sh

# The machine's two cores are busy through the test phase, so each test runs once, in the
# stricter build: running the suite optimised too took 14 minutes and found nothing the
# sanitizer run did not. The chaos trials ran on an optimised build of their own until that
# build's 10 minutes (of a fresh clone's 50 on a slow machine) were more than the trials cost
# under the sanitizers (docs/development.md); the optimised build is what `scripts/main.sh`
# makes, and what developers build with GCC before they push.
begin "build (ASan + UBSan)"
cmake --preset asan >/dev/null
cmake --build --preset asan -j "$jobs"

begin "test (ASan + UBSan)"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
  ctest --preset asan -j "$jobs"
slowest build-asan

begin "fuzz build"
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz -j "$jobs" --target fuzz_message_decoder fuzz_mdns_datagram fuzz_http_endpoint \
  fuzz_session_services

begin "fuzz (short runs)"
# The targets run side by side (each is one process on one core; three runs one after the other
# left a core idle for 90 s), each for SKILLCELL_FUZZ_SECONDS of wall time.
fuzz_pids=()
fuzz_names=()
for target in build-fuzz/fuzz/fuzz_*; do
  [ -x "$target" ] || continue
  name=$(basename "$target")
  mkdir -p "build-fuzz/corpus-$name"
  "$target" -max_total_time="${SKILLCELL_FUZZ_SECONDS:-60}" -rss_limit_mb=1024 \
    "build-fuzz/corpus-$name" "fuzz/corpus/$name" >"build-fuzz/$name.log" 2>&1 &
  fuzz_pids+=($!)
  fuzz_names+=("$name")
done
fuzz_failed=0
for i in "${!fuzz_pids[@]}"; do
  log="build-fuzz/${fuzz_names[$i]}.log"
  if wait "${fuzz_pids[$i]}"; then
    echo "${fuzz_names[$i]}: $(tail -n 1 "$log")"
  else
    tail -n 60 "$log"
    echo "fuzz target ${fuzz_names[$i]} found a failure" >&2
    fuzz_failed=1
  fi
done
[ $fuzz_failed = 0 ] || exit 1
finish
echo "== all tests passed"
