#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Builds and runs every codrive test: unit and virtual-bus tests under ASan+UBSan on the host,
# vcan tests (real sockets, real processes) under UBSan in vcan (natively or in a UML guest),
# EtherCAT tests on veth, the libFuzzer targets (clang 14, bounded time, built and run while the
# one-CPU vcan guest runs) and a valgrind leak check of a vcan subset in the guest. Prints how
# many tests of each suite ran; fails if a suite that exists ran none.
#   CODRIVE_SKIP_VCAN=1   skip the vcan suite explicitly (it is reported as skipped)
#   CODRIVE_SKIP_FUZZ=1   skip the fuzz stage explicitly (reported as skipped)
#   CODRIVE_FUZZ_SECONDS  seconds per fuzz target (default 10)
#   CODRIVE_JOBS=N        parallel build jobs (default: nproc)
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
jobs=${CODRIVE_JOBS:-$(nproc)}

bash .ci/install-deps.sh

configure_build() { # dir sanitize
    local dir=$1 sanitize=$2
    cmake -S "$root" -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=Debug -DCODRIVE_SANITIZE="$sanitize" \
        -DCODRIVE_BUILD_BENCH=OFF >"$dir.configure.log" 2>&1 || {
        cat "$dir.configure.log"
        exit 1
    }
    ninja -C "$dir" -j "$jobs"
}

declare -A passed failed
total_passed=0
total_failed=0

# run_suite NAME CMD... : runs gtest binaries, adds up "[  PASSED  ] N" and "N FAILED TEST".
count_gtest() { # label logfile
    local label=$1 log=$2 p f
    p=$(awk '/^\[  PASSED  \] [0-9]+ test/ {s += $4} END {print s + 0}' "$log")
    f=$(awk '/^\[  FAILED  \] [0-9]+ test/ {s += $4} END {print s + 0}' "$log")
    passed[$label]=$(( ${passed[$label]:-0} + p ))
    failed[$label]=$(( ${failed[$label]:-0} + f ))
}

status=0
echo "== build: ASan+UBSan (unit and virtual-bus tests)"
configure_build "$root/build-asan" "address,undefined"
echo "== unit tests (ASan+UBSan)"
for exe in "$root"/build-asan/tests/unit_* "$root"/build-asan/tests/integration_tests; do
    [[ -x $exe ]] || continue
    log=$(mktemp)
    set +e
    "$exe" >"$log" 2>&1
    rc=$?
    set -e
    if [[ $rc -ne 0 ]]; then
        cat "$log"
        status=1
    else
        # unit_conformance also prints "conformance: N facts checked per drive, M failed".
        grep -E '^\[  PASSED  \]|^conformance:' "$log" | sed "s|^|$(basename "$exe"): |" || true
    fi
    count_gtest unit "$log"
    rm -f "$log"
done

echo "== build: UBSan (vcan and EtherCAT tests; ASan cannot run in a UML guest)"
configure_build "$root/build-ubsan" "undefined"

# Fuzz stage in the background: the UML guest of the vcan stage uses one CPU, the clang build and
# the fuzzers use the others. Its log is printed after the vcan stage.
fuzz_log=$root/build-fuzz.ci.log
fuzz_pid=
if [[ ${CODRIVE_SKIP_FUZZ:-0} == 1 ]]; then
    fuzz_skipped=1
else
    fuzz_skipped=0
    echo "== fuzz stage started in the background (log: $fuzz_log)"
    fuzz_jobs=$((jobs > 1 ? jobs - 1 : 1))
    CODRIVE_FUZZ_BUILD=$root/build-fuzz JOBS=$fuzz_jobs \
        bash tests/fuzz/run.sh "${CODRIVE_FUZZ_SECONDS:-10}" >"$fuzz_log" 2>&1 &
    fuzz_pid=$!
fi

if [[ ${CODRIVE_SKIP_VCAN:-0} == 1 ]]; then
    echo "== vcan tests: SKIPPED (CODRIVE_SKIP_VCAN=1)"
    vcan_skipped=1
else
    vcan_skipped=0
    echo "== vcan tests (real SocketCAN)"
    log=$(mktemp)
    set +e
    bash vcan-scripts/run-in-vcan.sh -v "$root/build-ubsan/tests/vcan_tests" 2>&1 | tee "$log"
    rc=${PIPESTATUS[0]}
    set -e
    [[ $rc -eq 0 ]] || status=1
    count_gtest vcan "$log"
    rm -f "$log"

    echo "== leak check: valgrind memcheck on a vcan subset and the tools it starts (guest)"
    log=$(mktemp)
    set +e
    bash vcan-scripts/run-in-vcan.sh --timeout 900 bash tests/vcan/leak_check.sh \
        "$root/build-ubsan" 2>&1 | tee "$log"
    rc=${PIPESTATUS[0]}
    set -e
    [[ $rc -eq 0 ]] || status=1
    # Failed: memory errors, and processes that failed their own run (a test, a tool's exit
    # status) even with clean memory; those are not counted as passed.
    passed[leak]=$(awk '/^leak-check: [0-9]+ processes clean/ {print $2 - $8}' "$log")
    failed[leak]=$(awk '/^leak-check: [0-9]+ processes clean/ {print $5 + $8}' "$log")
    [[ -n ${passed[leak]} ]] || failed[leak]=1
    rm -f "$log"
fi

if [[ -n $fuzz_pid ]]; then
    echo "== fuzz (libFuzzer, clang 14, ASan+UBSan; ${CODRIVE_FUZZ_SECONDS:-10} s per target)"
    set +e
    wait "$fuzz_pid"
    rc=$?
    set -e
    cat "$fuzz_log"
    [[ $rc -eq 0 ]] || status=1
    passed[fuzz]=$(awk '/^fuzz: [0-9]+ passed/ {print $2}' "$fuzz_log")
    failed[fuzz]=$(awk '/^fuzz: [0-9]+ passed/ {print $4}' "$fuzz_log")
    if [[ -z ${passed[fuzz]} ]]; then
        failed[fuzz]=1 # the stage did not get as far as running the targets
    fi
fi

if [[ -x $root/build-ubsan/tests/ethercat_tests ]]; then
    echo "== EtherCAT tests (veth)"
    log=$(mktemp)
    set +e
    "$root/build-ubsan/tests/ethercat_tests" 2>&1 | tee "$log"
    rc=${PIPESTATUS[0]}
    set -e
    [[ $rc -eq 0 ]] || status=1
    count_gtest ethercat "$log"
    rm -f "$log"
    ethercat_expected=1
else
    ethercat_expected=0
fi

echo "== install: find_package(codrive) and pkg-config consumers of an installed tree"
log=$(mktemp)
set +e
bash tests/install/run.sh "$root/build-install" 2>&1 | tee "$log"
rc=${PIPESTATUS[0]}
set -e
[[ $rc -eq 0 ]] || status=1
passed[install]=$(awk '/^install: [0-9]+ passed/ {print $2}' "$log")
failed[install]=$(awk '/^install: [0-9]+ passed/ {print $4}' "$log")
[[ -n ${passed[install]} ]] || failed[install]=1
rm -f "$log"

echo
echo "== summary"
for suite in unit vcan leak fuzz ethercat install; do
    p=${passed[$suite]:-0}
    f=${failed[$suite]:-0}
    total_passed=$((total_passed + p))
    total_failed=$((total_failed + f))
    note=""
    if [[ ($suite == vcan || $suite == leak) && $vcan_skipped == 1 ]]; then
        note=" (skipped on request)"
    elif [[ $suite == fuzz && $fuzz_skipped == 1 ]]; then
        note=" (skipped on request)"
    elif [[ $suite == ethercat && $ethercat_expected == 0 ]]; then
        note=" (no EtherCAT suite built yet)"
    elif ((p + f == 0)); then
        note=" (ERROR: the suite ran no test)"
        status=1
    fi
    printf '%-9s %5d passed, %d failed%s\n' "$suite:" "$p" "$f" "$note"
done
if ((total_failed > 0)); then
    status=1
fi
echo "${total_passed} passed, ${total_failed} failed"
exit $status
