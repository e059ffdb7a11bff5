#!/usr/bin/env bash
# Lint step: formatting and static analysis.
#
#   scripts/lint.sh [TIDY_BUILD_DIR]
#
# (a) clang-format --dry-run --Werror over every tracked *.cpp/*.hpp under src/ tests/ bench/
#     fuzz/ (style from .clang-format); fails on any diff. Fix with the same file list and -i.
# (b) clang-tidy (checks from .clang-tidy) over the translation units under src/ only, using
#     the compile database of TIDY_BUILD_DIR (default: build-lint/), which this script
#     configures without unity batches: a unity build's database names the batches, not the
#     files of src/. tests/, bench/ and fuzz/ are not tidied: with gtest and
#     the benchmark harness they take several times longer, too slow for CI on 2 cores.
#     Fails on any warning.
#
# Environment: CLANG_FORMAT, CLANG_TIDY, RUN_CLANG_TIDY override the tool names;
# LINT_JOBS (default 2) sets the clang-tidy parallelism; LINT_SKIP_TIDY=1 runs (a) only.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)

build_dir=${1:-build-lint}
case "$build_dir" in /*) ;; *) build_dir="$root/$build_dir" ;; esac
jobs=${LINT_JOBS:-2}
clang_format=${CLANG_FORMAT:-clang-format}
clang_tidy=${CLANG_TIDY:-clang-tidy}

status=0
start=$SECONDS

echo "== clang-format ($("$clang_format" --version | head -n1))"
mapfile -d '' cxx_files < <(git ls-files -z -- \
    'src/*.cpp' 'src/*.hpp' 'src/*.c' 'src/*.h' 'tests/*.cpp' 'tests/*.hpp' \
    'bench/*.cpp' 'bench/*.hpp' 'fuzz/*.cpp' 'fuzz/*.hpp' 'examples/*.cpp' 'examples/*.hpp')
if ! "$clang_format" --dry-run --Werror "${cxx_files[@]}"; then
    echo "clang-format: files above need formatting" >&2
    status=1
else
    echo "clang-format: ${#cxx_files[@]} files clean"
fi

if [ "${LINT_SKIP_TIDY:-0}" != 1 ]; then
    echo "== clang-tidy ($("$clang_tidy" --version | grep -m1 -i version)), build dir $build_dir"
    if ! cmake -S "$root" -B "$build_dir" -G Ninja -DSKILLCELL_UNITY_BUILD=OFF >/dev/null; then
        echo "cannot configure $build_dir for clang-tidy" >&2
        exit 2
    fi
    # Asio enables its coroutine support (asio::awaitable, co_spawn) only when it recognises
    # the compiler; with clang 14 parsing libstdc++ 12 headers it does not, so say so.
    extra_args=(-extra-arg=-DASIO_HAS_CO_AWAIT=1 -extra-arg=-DASIO_HAS_STD_COROUTINE=1)
    log=$(mktemp)
    trap 'rm -f "$log"' EXIT
    tidy_status=0
    run_clang_tidy=${RUN_CLANG_TIDY:-$(command -v run-clang-tidy || command -v run-clang-tidy-14 || true)}
    if [ -n "$run_clang_tidy" ]; then
        # The file arguments are regular expressions matched against the database entries.
        "$run_clang_tidy" -quiet -j "$jobs" -p "$build_dir" -clang-tidy-binary "$(command -v "$clang_tidy")" \
            "${extra_args[@]}" "^$root/src/.*\.cpp\$" >"$log" 2>&1 || tidy_status=$?
    else
        python3 -c 'import json, sys
for e in json.load(open(sys.argv[1])):
    f = e["file"]
    if f.startswith(sys.argv[2] + "/src/") and f.endswith(".cpp"):
        print(f)' "$build_dir/compile_commands.json" "$root" | sort -u |
            xargs -r -P "$jobs" -n 1 "$clang_tidy" --quiet -p "$build_dir" "${extra_args[@]}" \
                >"$log" 2>&1 || tidy_status=$?
    fi
    # run-clang-tidy always asks for colour; strip it so that the log reads and greps plainly.
    sed -i 's/\x1b\[[0-9;]*m//g' "$log"
    # Compiler diagnostics that are not promoted to errors would not fail clang-tidy; count
    # every warning and error, whatever its source.
    if [ "$tidy_status" -ne 0 ] || grep -qE '(warning|error): ' "$log"; then
        grep -vE '^([0-9]+ warnings? generated|Suppressed [0-9]+ warnings|Use -header-filter)' "$log" >&2 || true
        echo "clang-tidy: findings above (exit $tidy_status)" >&2
        status=1
    else
        echo "clang-tidy: src/ clean"
    fi
fi

echo "== lint finished in $((SECONDS - start)) s, status $status"
exit "$status"
