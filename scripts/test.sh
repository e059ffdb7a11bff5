#!/usr/bin/env bash
# The test command of the README and of CI: installs what is missing, builds, and runs
# every test twice: once optimised, once under AddressSanitizer + UndefinedBehaviorSanitizer;
# then runs each fuzz target for a short time.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh

export SKILLCELL_REQUIRE_NODE=1   # interop tests fail (not skip) when node-opcua is missing
export SKILLCELL_REQUIRE_NETNS=1  # and network-namespace tests when namespaces cannot be made
jobs=$(nproc)

echo "== build and test (RelWithDebInfo)"
cmake --preset default >/dev/null
# Formatting is checked on every run; clang-tidy (scripts/lint.sh without LINT_SKIP_TIDY)
# takes too long on 2 cores for every run and is run by developers before they push.
LINT_SKIP_TIDY=1 bash scripts/lint.sh build
cmake --build --preset default -j "$jobs"
ctest --preset default -j "$jobs"

echo "== build and test (ASan + UBSan)"
cmake --preset asan >/dev/null
cmake --build --preset asan -j "$jobs"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
  ctest --preset asan -j "$jobs"

echo "== fuzz (short runs)"
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz -j "$jobs" --target fuzz_message_decoder fuzz_mdns_datagram
for target in build-fuzz/fuzz/fuzz_*; do
  [ -x "$target" ] || continue
  corpus="fuzz/corpus/$(basename "$target")"
  mkdir -p "build-fuzz/corpus-$(basename "$target")"
  log="build-fuzz/$(basename "$target").log"
  if ! "$target" -max_total_time="${SKILLCELL_FUZZ_SECONDS:-30}" -rss_limit_mb=1024 \
      "build-fuzz/corpus-$(basename "$target")" "$corpus" >"$log" 2>&1; then
    tail -n 60 "$log"; echo "fuzz target $(basename "$target") found a failure" >&2; exit 1
  fi
  tail -n 1 "$log"
done
echo "== all tests passed"
