#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Builds the libFuzzer targets (clang 14, ASan+UBSan) and runs each for a bounded time with its
# seed corpus from tests/data/fuzz/<target>/, then prints one line per target (executions,
# exec/s, coverage) and "fuzz: N passed, M failed".
#
# Usage: tests/fuzz/run.sh [SECONDS_PER_TARGET] [TARGET...]     (default 20 s, every target)
# Environment: CODRIVE_FUZZ_BUILD (build dir, default build-fuzz), CXX_FUZZ (clang++-14),
#              JOBS (build parallelism, default 2), FUZZ_MAX_LEN (default 4096),
#              FUZZ_NO_BUILD (1: run what is built, do not build), FUZZ_BUILD_ONLY (1: build, run
#              nothing; exits non-zero when a target failed to build),
#              FUZZ_RUNS (run each target to this many executions instead of for SECONDS),
#              FUZZ_DEADLINE (epoch seconds: a target still running then is stopped and counted
#              as failed, "stopped at the deadline"; no target starts after it),
#              FUZZ_OPT (optimisation of a new build, default -O1; CI runs the targets of its
#              ASan+UBSan build instead, see tests/run-all.sh), FUZZ_EDGES_ONLY (libraries of a
#              new build with edge counters only, no comparison tracing; default codrive_sim,
#              see tests/fuzz/CMakeLists.txt), ASAN_OPTIONS (default below),
#              FUZZ_TIMEOUT (seconds one input may run before libFuzzer calls it a hang, default
#              10; wall time, so a campaign beside other work needs more: bench/fuzz_long.sh).
# The table's executions and cov/ft are libFuzzer's final figures (the "DONE" stats line).
# A target that crashes on its first input has no coverage line: its row shows "-" (set -e must
# not end the script there, or the summary line run-all.sh counts would be missing).
# A crash leaves its input in <build>/fuzz-artifacts/<target>/; copy it to
# tests/data/fuzz/regressions/<name>/ (a seed of every later run) and add a test for the fix.
set -euo pipefail

root=$(cd "$(dirname "$0")/../.." && pwd)
seconds=${1:-20}
shift || true
build=${CODRIVE_FUZZ_BUILD:-$root/build-fuzz}
cxx=${CXX_FUZZ:-clang++-14}
jobs=${JOBS:-2}
max_len=${FUZZ_MAX_LEN:-4096}
runs=${FUZZ_RUNS:-}
deadline=${FUZZ_DEADLINE:-}
unit_timeout=${FUZZ_TIMEOUT:-10}
# ASan's defaults record 30 stack frames at every malloc and free and keep 256 MB of freed memory
# poisoned: with inputs that allocate a lot (YAML trees, simulated slaves) that bookkeeping and
# the page faults of its quarantine took half of fuzz_bus_config's time. Ten frames still show
# where a block was allocated and freed, and 64 MB still holds every block an input frees (the
# largest inputs of four corpora allocated under 2 MB each), so a use after free is caught as
# before.
export ASAN_OPTIONS=${ASAN_OPTIONS:-malloc_context_size=10:quarantine_size_mb=64}

if ! command -v "$cxx" >/dev/null; then
    echo "fuzz: $cxx not found (libFuzzer needs clang)" >&2
    exit 2
fi
if [[ ! -f $build/build.ninja ]]; then
    # lld (package lld-14) links in a fraction of GNU ld's time; without it, the default linker.
    linker=()
    if [[ -x /usr/lib/llvm-14/bin/ld.lld ]]; then
        linker=(-DCMAKE_EXE_LINKER_FLAGS=-fuse-ld=lld)
    fi
    # Unset: the default of tests/fuzz/CMakeLists.txt (codrive_sim), kept in that one place.
    edges_only=()
    if [[ -n ${FUZZ_EDGES_ONLY:-} ]]; then
        edges_only=("-DCODRIVE_FUZZ_EDGES_ONLY=$FUZZ_EDGES_ONLY")
    fi
    cmake -S "$root" -B "$build" -G Ninja -DCMAKE_CXX_COMPILER="$cxx" "${linker[@]}" \
        -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=${FUZZ_OPT:--O1} -g" \
        -DCODRIVE_FUZZ=ON -DCODRIVE_BUILD_TESTS=OFF -DCODRIVE_BUILD_TOOLS=OFF \
        -DCODRIVE_BUILD_BENCH=OFF -DCODRIVE_SANITIZE=address,undefined "${edges_only[@]}" \
        >/dev/null
fi
# Build what builds: one module that does not compile must not hide the other fuzzers' results.
# FUZZ_NO_BUILD=1 runs the binaries already built (a target not built is reported as such).
if [[ -n ${FUZZ_NO_BUILD:-} ]]; then
    :
elif ! ninja -C "$build" -j "$jobs" -k 0 fuzz_all >"$build/fuzz-build.log" 2>&1; then
    echo "fuzz: some targets failed to build (see $build/fuzz-build.log)" >&2
    [[ -z ${FUZZ_BUILD_ONLY:-} ]] || exit 1
fi
[[ -z ${FUZZ_BUILD_ONLY:-} ]] || exit 0

targets=("$@")
if [[ ${#targets[@]} -eq 0 ]]; then
    for src in "$root"/tests/fuzz/fuzz_*.cpp; do
        targets+=("$(basename "$src" .cpp)")
    done
fi

passed=0
failed=0
printf '%-26s %12s %9s %7s %8s %7s  %s\n' target executions exec/s cov ft corpus result
for target in "${targets[@]}"; do
    exe=$build/tests/fuzz/$target
    name=${target#fuzz_}
    if [[ ! -x $exe ]]; then
        printf '%-26s %12s %9s %7s %8s %7s  %s\n' "$target" - - - - - "FAILED (not built)"
        failed=$((failed + 1))
        continue
    fi
    # Work on a copy of the seeds so new inputs never land in the source tree.
    corpus=$build/fuzz-corpus/$name
    artifacts=$build/fuzz-artifacts/$name
    mkdir -p "$corpus" "$artifacts"
    # Every reproducer of a fixed crash (tests/data/fuzz/regressions/<name>/) is a seed too, so
    # each run replays it first: a defect that comes back fails the run at once.
    for seeds in "$root/tests/data/fuzz/$name" "$root/tests/data/fuzz/regressions/$name"; do
        if [[ -d $seeds ]]; then
            cp -n "$seeds"/* "$corpus"/ 2>/dev/null || true
        fi
    done
    log=$build/fuzz-logs/$target.log
    mkdir -p "$(dirname "$log")"
    status=0
    if [[ -n $runs ]]; then
        budget=(-runs="$runs")
        guard=$((7 * 24 * 3600))
    else
        budget=(-max_total_time="$seconds")
        guard=$((seconds + 60)) # in case a single input hangs past libFuzzer's own -timeout
    fi
    if [[ -n $deadline ]]; then
        left=$((deadline - $(date +%s)))
        if [[ $left -le 0 ]]; then
            printf '%-26s %12s %9s %7s %8s %7s  %s\n' "$target" - - - - - "FAILED (not started: deadline)"
            failed=$((failed + 1))
            continue
        fi
        [[ $left -lt $guard ]] && guard=$left
    fi
    timeout --signal=INT "$guard" "$exe" "$corpus" "${budget[@]}" \
        -max_len="$max_len" -timeout="$unit_timeout" -rss_limit_mb=2048 -print_final_stats=1 \
        -artifact_prefix="$artifacts/" >"$log" 2>&1 || status=$?
    execs=$(awk '/stat::number_of_executed_units:/ {v=$2} END {print v+0}' "$log")
    rate=$(awk '/stat::average_exec_per_sec:/ {v=$2} END {print v+0}' "$log")
    # Coverage from libFuzzer's last status line (the "DONE" line of a finished run).
    cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | awk '{print $2}' || true)
    ft=$(grep -o 'ft: [0-9]*' "$log" | tail -1 | awk '{print $2}' || true)
    units=$(find "$corpus/" -type f | wc -l) # the slash: a corpus directory may be a symlink
    if [[ $status -eq 0 ]]; then
        result=ok
        passed=$((passed + 1))
    elif grep -q 'libFuzzer: run interrupted' "$log"; then
        result="FAILED (stopped at the deadline after $execs executions; log $log)"
        failed=$((failed + 1))
    else
        crash=$(grep -o "Test unit written to [^ ]*" "$log" | tail -1 | sed 's/Test unit written to //' || true)
        result="FAILED (exit $status${crash:+, input $crash}; log $log)"
        failed=$((failed + 1))
    fi
    printf '%-26s %12s %9s %7s %8s %7s  %s\n' "$target" "$execs" "$rate" "${cov:--}" "${ft:--}" \
        "$units" "$result"
done
echo "fuzz: $passed passed, $failed failed"
[[ $failed -eq 0 ]]
