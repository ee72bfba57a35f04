#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Builds and runs every codrive test: unit, virtual-bus and EtherCAT (veth) tests under
# ASan+UBSan on the host; vcan tests (real sockets, real processes) in vcan (natively or in a UML
# guest, where no sanitizer runtime works) on the Release build users ship, with a valgrind leak
# check of a vcan subset; the host threading tests under ThreadSanitizer; the allocation tests and
# the Python module's pytest suites (host, and vcan in the guest) in the same Release build; the
# libFuzzer targets (bounded time) from the ASan+UBSan build. Three builds (ASan+UBSan with the
# fuzz targets, Release, TSan), each building only the targets its stages run: the sanitizer
# builds with clang 14 and lld, the Release build with the default compiler (GCC on Debian), as
# users build it.
# The summary gives per suite: passed, failed, skipped, and the stage's wall time (format: one
# test per C/C++ file, as clang-format leaves it or not). A suite that
# exists but ran no test fails the run, and so does a skipped test that was not asked for.
#   CODRIVE_SKIP_VCAN=1      skip the vcan and leak stages explicitly (reported as skipped)
#   CODRIVE_SKIP_ETHERCAT=1  skip the EtherCAT stage explicitly, and let the TSan and Python suites skip their
#                            veth tests (reported as skipped)
#   CODRIVE_SKIP_FUZZ=1      skip the fuzz stage explicitly (reported as skipped)
#   CODRIVE_FUZZ_SECONDS     seconds per fuzz target (default 10)
#   CODRIVE_JOBS=N           parallel build jobs (default: nproc)
# The last line is "N passed, M failed, K skipped" (CI reads it).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
jobs=${CODRIVE_JOBS:-$(nproc)}
t_start=$(date +%s)

declare -A passed failed skipped seconds note
suites=(format unit tsan release python vcan leak fuzz ethercat install)
stage_order=()
status=0

# stage NAME CMD... : runs CMD, records its wall time under NAME (for the summary).
stage() {
    local name=$1 t0 rc
    shift
    t0=$(date +%s)
    set +e
    "$@"
    rc=$?
    set -e
    seconds[$name]=$(($(date +%s) - t0))
    stage_order+=("$name")
    return $rc
}

stage deps bash .ci/install-deps.sh

# Every C and C++ file git tracks is as clang-format (14, .clang-format) leaves it: a file counts
# as one passed test, or as one failed test with clang-format's complaint printed.
format_stage() {
    local cf log bad n_bad
    local -a files
    cf=$(command -v clang-format-14 || command -v clang-format || true)
    if [[ -z $cf ]]; then
        echo "format: no clang-format (install clang-format-14)"
        failed[format]=1
        return 1
    fi
    mapfile -t files < <(if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
        git ls-files '*.cpp' '*.hpp' '*.c' '*.h'
    else # an unpacked archive: the sources, not the build trees
        find . -mindepth 1 \( -name 'build*' -o -name node_modules -o -name '.*' \) -prune -o \
            -type f \( -name '*.cpp' -o -name '*.hpp' -o -name '*.c' -o -name '*.h' \) -print
    fi)
    log=$(mktemp)
    "$cf" --dry-run --Werror "${files[@]}" >"$log" 2>&1 || true
    # "FILE:LINE:COL: error: code should be clang-formatted [-Wclang-format-violations]"
    bad=$(sed -n 's/^\(.*\):[0-9]*:[0-9]*: error: .*clang-format.*/\1/p' "$log" | sort -u)
    n_bad=0
    [[ -z $bad ]] || n_bad=$(wc -l <<<"$bad")
    if ((n_bad > 0)); then
        head -40 "$log"
        echo "format: not as clang-format leaves them: $(paste -sd' ' <<<"$bad")"
    fi
    rm -f "$log"
    passed[format]=$((${#files[@]} - n_bad))
    failed[format]=$n_bad
    echo "format: ${passed[format]} files as clang-format leaves them, $n_bad not ($cf)"
    ((n_bad == 0))
}
echo "== format: clang-format on every C and C++ file git tracks"
stage format format_stage || status=1

# The sanitizer builds compile with clang 14 and link with lld: at -O0 clang compiles this code in
# about half of GCC's time (docs/reliability.md, "CI time"). The Release build, what users ship,
# keeps the default compiler, so the libraries, tools and Python module meet both compilers'
# warnings (errors); the ASan+UBSan build compiles the Python module for that alone (no test
# loads it: the Python stage runs the Release build's), since clang 14 refused code GCC took (a
# lambda capturing a structured binding). Without clang 14 the sanitizer builds use the default
# compiler too.
# Their debug information is line tables only: sanitizer reports still name file, line and
# inlined frames, and the ASan+UBSan build takes 8 % less CPU time (460 against 500 s).
# The ASan+UBSan build also builds the libFuzzer targets (clang only): its module libraries carry
# libFuzzer's edge counters (CODRIVE_FUZZ_COVERAGE=edges), which do not slow the unit tests
# (unit_sdo 35.5 s against 36.3 s; the full instrumentation, comparisons traced, made it 46.7 s).
# That replaced a fourth build of the libraries for the fuzzers: 127 CPU-seconds fewer.
san_cmake=()
asan_fuzz_cmake=()
asan_fuzz_regex=
if command -v clang++-14 >/dev/null; then
    san_cmake=(-DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_CXX_FLAGS_DEBUG=-gline-tables-only)
    if [[ -x /usr/lib/llvm-14/bin/ld.lld ]]; then
        san_cmake+=(-DCMAKE_EXE_LINKER_FLAGS=-fuse-ld=lld -DCMAKE_SHARED_LINKER_FLAGS=-fuse-ld=lld)
    fi
    if [[ ${CODRIVE_SKIP_FUZZ:-0} != 1 ]]; then
        asan_fuzz_cmake=(-DCODRIVE_FUZZ=ON -DCODRIVE_FUZZ_COVERAGE=edges)
        asan_fuzz_regex='|fuzz_[a-z_]+'
    fi
fi

# configure_build DIR BUILD_TYPE SANITIZE TARGET_REGEX [CMAKE_ARG...]: configures like the README
# (plus CMAKE_ARGs) and builds only the executables whose names match TARGET_REGEX (and what they
# link), with $JOBS jobs if set, else $jobs; it builds what builds (one target that does not
# compile fails the stage but leaves the others' tests to run).
configure_build() {
    local dir=$1 type=$2 sanitize=$3 regex=$4 targets
    shift 4
    cmake -S "$root" -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE="$type" -DCODRIVE_SANITIZE="$sanitize" \
        -DCODRIVE_BUILD_BENCH=OFF "$@" >"$dir.configure.log" 2>&1 || {
        cat "$dir.configure.log"
        return 1
    }
    targets=$(ninja -C "$dir" -t targets all | awk -F: -v re="^($regex)\$" '$1 ~ re {print $1}' |
        sort -u)
    if [[ -z $targets ]]; then
        echo "run-all: no target in $dir matches $regex" >&2
        return 1
    fi
    # shellcheck disable=SC2086 # one word per target
    ninja -C "$dir" -j "${JOBS:-$jobs}" -k 0 $targets
}

# gtest_total TAG LOGFILE: the sum of N over gtest's "[TAG] N test..." summary lines, TAG being
# its padded "  PASSED  ", "  FAILED  " or "  SKIPPED ".
gtest_total() {
    awk -v tag="[$1]" 'substr($0, 1, 12) == tag && substr($0, 13) ~ /^ [0-9]+ test/ {s += $4}
        END {print s + 0}' "$2"
}
# count_gtest SUITE LOGFILE: adds up gtest's PASSED, FAILED and SKIPPED summary lines.
count_gtest() {
    local suite=$1 log=$2
    passed[$suite]=$((${passed[$suite]:-0} + $(gtest_total '  PASSED  ' "$log")))
    failed[$suite]=$((${failed[$suite]:-0} + $(gtest_total '  FAILED  ' "$log")))
    skipped[$suite]=$((${skipped[$suite]:-0} + $(gtest_total '  SKIPPED ' "$log")))
}

# report_gtest SUITE NAME LOG RC: prints a gtest binary's log on failure (its PASSED/SKIPPED
# lines otherwise) and counts it into SUITE; a binary that crashed before its summary counts as
# one failure.
report_gtest() {
    local suite=$1 name=$2 log=$3 rc=$4
    if [[ $rc -ne 0 ]]; then
        cat "$log"
        status=1
    else
        # unit_conformance also prints "conformance: N facts checked per drive, M differ from the
        # manual (K known divergences, U unexpected); device files (EDS, ESI): ..."
        grep -E '^\[  (PASSED  |SKIPPED )\]|^conformance:' "$log" | sed "s|^|$name: |" || true
    fi
    count_gtest "$suite" "$log"
    if [[ $rc -ne 0 ]] && ! grep -qE '^\[  FAILED  \] [0-9]+ test' "$log"; then
        failed[$suite]=$((${failed[$suite]:-0} + 1))
    fi
}

# run_gtest SUITE EXE [ARGS...]: runs one gtest binary on the host (after the command words in
# gtest_prefix, e.g. chrt) and reports it.
gtest_prefix=()
run_gtest() {
    local suite=$1 exe=$2 log rc
    shift 2
    log=$(mktemp)
    set +e
    "${gtest_prefix[@]}" "$exe" "$@" >"$log" 2>&1
    rc=$?
    set -e
    report_gtest "$suite" "$(basename "$exe")" "$log" $rc
    rm -f "$log"
}

# run_gtest_retry SUITE EXE [ARGS...]: run_gtest for the suites that time a cyclic exchange over
# veth (lost frames, late cycles). The tests that failed run again, alone, at once, up to two
# more times; a test counts as passed only if one of those runs passes, every failed run is
# printed in full, and the summary names every test that needed another run. A deterministic
# failure fails three times and fails the run; a crash before gtest's summary is not run again.
# (Why: a 2-vCPU VM of this workplace stalled a 1 ms SCHED_FIFO sleeper by 9 to 26 ms in every
# 10 s, idle or not; such stalls lose cycles whatever the master does. With nothing beside the
# suite, its timed tests failed 0, 1, 0 and 3 times in four runs there, each passing when run
# again: docs/reliability.md, session 22.)
declare -A retried
run_gtest_retry() {
    local suite=$1 exe=$2 log rc names run=1 label
    local -a only=()
    shift 2
    label=$(basename "$exe")
    log=$(mktemp)
    while :; do
        set +e
        "${gtest_prefix[@]}" "$exe" "$@" "${only[@]}" >"$log" 2>&1
        rc=$?
        set -e
        names=$(awk '/^\[  FAILED  \] [0-9]+ tests?, listed below:/ {on = 1; next}
            on && /^\[  FAILED  \] / {sub(/,$/, "", $4); print $4}' "$log" | sort -u)
        if [[ $rc -eq 0 || -z $names || $run -eq 3 ]]; then
            report_gtest "$suite" "$label" "$log" $rc
            rm -f "$log"
            return
        fi
        cat "$log"
        passed[$suite]=$((${passed[$suite]:-0} + $(gtest_total '  PASSED  ' "$log")))
        if ((run == 1)); then
            retried[$suite]="${retried[$suite]:+${retried[$suite]}, }$(paste -sd' ' <<<"$names" |
                sed 's/ /, /g')"
        fi
        run=$((run + 1))
        label="$(basename "$exe") (run $run)"
        echo "$(basename "$exe"): $(wc -l <<<"$names") test(s) failed; run $run of them, alone:"
        only=(--gtest_filter="$(paste -sd: <<<"$names")")
    done
}

# The unit stage runs in the background while the Release build compiles (a test binary needs
# one CPU): each binary's log and exit status go to unit_dir and are counted afterwards.
# gtest_to_dir DIR EXE [ARGS...]: runs one gtest binary (after gtest_prefix) in a background
# stage, its log and exit status into DIR, for report_dir.
gtest_to_dir() {
    local dir=$1 exe=$2
    shift 2
    "${gtest_prefix[@]}" "$exe" "$@" >"$dir/$(basename "$exe").log" 2>&1
    echo $? >"$dir/$(basename "$exe").rc"
}
# report_dir SUITE DIR: reports every binary gtest_to_dir ran into DIR.
report_dir() {
    local suite=$1 dir=$2 log name
    for log in "$dir"/*.log; do
        [[ -f $log ]] || continue
        name=$(basename "$log" .log)
        report_gtest "$suite" "$name" "$log" "$(cat "$dir/$name.rc" 2>/dev/null || echo 1)"
    done
}
unit_dir=$root/build-asan/ci-unit
unit_run() {
    local exe t0
    t0=$(date +%s)
    rm -rf "$unit_dir"
    mkdir -p "$unit_dir"
    for exe in "$root"/build-asan/tests/unit_* "$root"/build-asan/tests/integration_tests; do
        [[ -x $exe ]] || continue
        gtest_to_dir "$unit_dir" "$exe"
    done
    echo $(($(date +%s) - t0)) >"$unit_dir/seconds"
}

# The Release build (what users ship) serves the vcan and leak stages (no sanitizer runtime works
# in the UML guest; valgrind reads optimised code fine), the allocation proofs (the optimiser
# must not be able to remove what they count), the Python module and the install stage: its
# directory is the one tests/install/run.sh configures with the same flags, so the libraries
# compiled here are reused there instead of being compiled again.
release_build=$root/build-install/build
release_stage() {
    run_gtest release "$release_build/tests/allocation_tests"
}

# ThreadSanitizer on the tests where threads meet: the in-process controller and hand-off tests
# (integration_tests) and the controller over veth EtherCAT with its dedicated cyclic thread (its
# object accesses from the loop thread included: DemoScenarioOverEthercat.ObjectAccess*, and
# those a shutdown ends: ObjectAccessAtShutdown).
# TSan cannot run in the UML guest, so the vcan suite has no TSan run. Left out under TSan: the
# allocation count (TSan's runtime owns operator new, so nothing can be counted; it runs in the
# ASan+UBSan EtherCAT stage and in the Release allocation_tests). The fd and thread count of a
# destroyed controller (DestroyedControllerLeavesNoFdsOrThreads...) runs here too: its baseline
# is taken after a throwaway thread has started TSan's own background thread (count_threads()).
# integration_tests under TSan times nothing (its threads are checked for races, not for
# latency), so it runs in the background after the fuzzers, beside the Python and install stages
# (below), at nice 19; its log, exit status and wall time go to tsan_dir. The EtherCAT controller
# tests under TSan run after the EtherCAT stage, alone: they run a cyclic thread over veth.
tsan_dir=$root/build-tsan/ci-tsan
tsan_options="halt_on_error=1 second_deadlock_stack=1 ${TSAN_OPTIONS:-}"
tsan_integration_run() {
    local t0
    local -a gtest_prefix=(env "TSAN_OPTIONS=$tsan_options" nice -n 19)
    t0=$(date +%s)
    rm -rf "$tsan_dir"
    mkdir -p "$tsan_dir"
    gtest_to_dir "$tsan_dir" "$root/build-tsan/tests/integration_tests"
    echo $(($(date +%s) - t0)) >"$tsan_dir/seconds"
}
tsan_stage() {
    report_dir tsan "$tsan_dir"
    tsan_rest_t0=$(date +%s)
    local -a gtest_prefix=(env "TSAN_OPTIONS=$tsan_options")
    run_gtest_retry tsan "$root/build-tsan/tests/ethercat_tests" \
        --gtest_filter='ControllerOverEthercat.*:ControllerRecovery.AnInterfaceThatGoesDown*:DemoScenarioOverEthercat.ObjectAccess*:Threading/ObjectAccessAtShutdown.*:-*EcatDemoProgram*:*AllocatesNothing*'
}

echo "== build: ASan+UBSan (unit, virtual-bus and EtherCAT tests, the tools they start, fuzz targets, the Python module)"
stage build-asan configure_build "$root/build-asan" Debug "address,undefined" \
    "unit_[a-z_]+|integration_tests|ethercat_tests|codrive(-[a-z_-]+)?|codrive_python$asan_fuzz_regex" \
    "${san_cmake[@]}" "${asan_fuzz_cmake[@]}" || status=1
echo "== unit tests (ASan+UBSan) started in the background, beside the Release build"
unit_run &
unit_pid=$!

echo "== build: Release (vcan and leak stages, allocation tests, Python module, install)"
# All jobs, beside the unit tests: the build outlasts them (with one job fewer it ran alone on
# one CPU for minutes after the unit stage ended).
mkdir -p "$root/build-install"
stage build-release configure_build "$release_build" Release "" \
    'vcan_tests|allocation_tests|codrive_python|codrive(-[a-z_-]+)?' || status=1
echo "== unit tests (ASan+UBSan)"
wait "$unit_pid" || true
seconds[unit]=$(cat "$unit_dir/seconds" 2>/dev/null || echo 0)
stage_order+=(unit)
report_dir unit "$unit_dir"

# Beside the guest of the vcan and leak stages, which takes one CPU: the TSan build with one job
# (two jobs beside the guest, even at nice 19, slowed its stages by a third: 10m46s instead of
# 7m48s), then the fuzzers (one process at a time). When the guest ends a build under way goes on
# with every job, beside the Python and install stages; the timed EtherCAT tests come last.
bg_dir=$root/build-ci-beside
fuzz_log=$bg_dir/fuzz.log
guest_done=$bg_dir/guest-done
rm -rf "$bg_dir"
mkdir -p "$bg_dir"
# beside_build DIR LOG CMD...: runs CMD, a build of DIR by `ninja -C DIR` that takes its job count
# from $JOBS, into LOG: with one job while the guest runs, with all jobs after it. A build still
# under way when the guest ends is stopped (ninja stops its compilers and keeps what it finished)
# and started again with all jobs; the stopped attempt's log is kept as LOG.stopped.
beside_build() {
    local dir=$1 log=$2 pid
    shift 2
    if [[ ! -e $guest_done ]]; then
        JOBS=1 "$@" >"$log" 2>&1 &
        pid=$!
        while kill -0 "$pid" 2>/dev/null && [[ ! -e $guest_done ]]; do
            sleep 1
        done
        if ! kill -0 "$pid" 2>/dev/null; then
            wait "$pid"
            return
        fi
        # (A configure step has no ninja yet: try until the attempt is over.)
        while kill -0 "$pid" 2>/dev/null; do
            pkill -TERM -f "^ninja -C $dir " || true
            sleep 1
        done
        wait "$pid" || true
        mv "$log" "$log.stopped"
    fi
    JOBS=$jobs "$@" >"$log" 2>&1
}
beside_guest() {
    local t0
    renice -n 10 -p "$BASHPID" >/dev/null
    t0=$(date +%s)
    set +e
    beside_build "$root/build-tsan" "$bg_dir/build-tsan.log" configure_build "$root/build-tsan" \
        Debug thread 'integration_tests|ethercat_tests|codrive-ecat-sim' "${san_cmake[@]}"
    echo $? >"$bg_dir/build-tsan.rc"
    echo $(($(date +%s) - t0)) >"$bg_dir/build-tsan.seconds"
    [[ ${CODRIVE_SKIP_FUZZ:-0} == 1 ]] || fuzz_run
    tsan_integration_run
}
# The fuzz targets of the ASan+UBSan build (-O0, edge counters): the 10 s runs are a check of each
# target over its corpus, not a campaign (bench/fuzz_long.sh builds its own, at -O1 with libFuzzer's
# full instrumentation). A target that did not build is reported by the run ("not built").
fuzz_run() {
    local t0
    t0=$(date +%s)
    CODRIVE_FUZZ_BUILD=$root/build-asan FUZZ_NO_BUILD=1 \
        bash tests/fuzz/run.sh "${CODRIVE_FUZZ_SECONDS:-10}" >"$fuzz_log" 2>&1
    echo $? >"$bg_dir/fuzz.rc"
    echo $(($(date +%s) - t0)) >"$bg_dir/fuzz-run.seconds"
}
echo "== beside the guest (logs: $bg_dir): TSan build, then the fuzzers"
beside_guest &
beside_pid=$!

vcan_stage() {
    local log rc
    log=$(mktemp)
    set +e
    bash vcan-scripts/run-in-vcan.sh -v --timeout 2400 "$release_build/tests/vcan_tests" 2>&1 | tee "$log"
    rc=${PIPESTATUS[0]}
    set -e
    [[ $rc -eq 0 ]] || status=1
    count_gtest vcan "$log"
    # A guest that timed out or crashed before gtest's summary is one failure, not a pass.
    if [[ $rc -ne 0 ]] && ! grep -qE '^\[  FAILED  \] [0-9]+ test' "$log"; then
        failed[vcan]=$((${failed[vcan]:-0} + 1))
    fi
    rm -f "$log"
}

leak_stage() {
    local log rc
    log=$(mktemp)
    set +e
    bash vcan-scripts/run-in-vcan.sh --timeout 900 bash tests/vcan/leak_check.sh \
        "$release_build" 2>&1 | tee "$log"
    rc=${PIPESTATUS[0]}
    set -e
    [[ $rc -eq 0 ]] || status=1
    # Failed: memory errors, and processes that failed their own run (a test, a tool's exit
    # status) even with clean memory; those are not counted as passed.
    passed[leak]=$(awk '/^leak-check: [0-9]+ processes clean/ {print $2 - $8}' "$log")
    failed[leak]=$(awk '/^leak-check: [0-9]+ processes clean/ {print $5 + $8}' "$log")
    [[ -n ${passed[leak]} ]] || failed[leak]=1
    rm -f "$log"
}

if [[ ${CODRIVE_SKIP_VCAN:-0} == 1 ]]; then
    echo "== vcan tests: SKIPPED (CODRIVE_SKIP_VCAN=1)"
    note[vcan]="skipped on request"
    note[leak]="skipped on request"
else
    echo "== vcan tests (real SocketCAN)"
    stage vcan vcan_stage
    echo "== leak check: valgrind memcheck on a vcan subset and the tools it starts (guest)"
    stage leak leak_stage
fi

touch "$guest_done"
echo "== the guest ended: what is left of the TSan build goes on with $jobs jobs, then the fuzzers and the TSan integration tests run, beside the Python and install stages"

# The Python module under pytest: the host suites (in-process VirtualNetwork, EDS files, traces),
# then the vcan suites in a guest (codrive-sim processes on real SocketCAN). The module and the
# tools the tests start come from the Release build, which the install stage builds anyway (the
# package ships that module): a second, sanitized build of the pybind11 code would cost minutes.
# count_pytest SUITE LOG: adds up pytest's last line ("3 failed, 40 passed, 1 skipped in 2.1s";
# errors count as failures).
count_pytest() {
    local suite=$1 log=$2 line p f s
    line=$(grep -E '^=*[ ]*[0-9]+ (passed|failed|skipped|error|errors)' "$log" | tail -1 || true)
    read -r p f s < <(awk '{
        for (i = 2; i <= NF; i++) {
            w = $i; gsub(/[,=]/, "", w)
            if (w == "passed") p += $(i - 1)
            if (w == "failed" || w == "error" || w == "errors") f += $(i - 1)
            if (w == "skipped") s += $(i - 1)
        }
    } END { print p + 0, f + 0, s + 0 }' <<<"$line")
    passed[$suite]=$((${passed[$suite]:-0} + p))
    failed[$suite]=$((${failed[$suite]:-0} + f))
    skipped[$suite]=$((${skipped[$suite]:-0} + s))
    [[ -n $line ]] || failed[$suite]=$((${failed[$suite]:-0} + 1)) # pytest did not get to run
}
python_stage() {
    local log rc
    log=$(mktemp)
    local env=(env CODRIVE_PYTHON_DIR="$release_build/python" CODRIVE_BUILD_DIR="$release_build")
    set +e
    "${env[@]}" /usr/bin/python3 -m pytest -p no:cacheprovider -q \
        --ignore="$root/tests/python/vcan" "$root/tests/python" >"$log" 2>&1
    rc=$?
    set -e
    [[ $rc -eq 0 ]] || { cat "$log"; status=1; }
    tail -1 "$log" | sed 's/^/python (host): /'
    count_pytest python "$log"
    if [[ ${CODRIVE_SKIP_VCAN:-0} != 1 ]]; then
        set +e
        "${env[@]}" bash vcan-scripts/run-in-vcan.sh --ifaces 2 --timeout 300 \
            /usr/bin/python3 -m pytest -p no:cacheprovider -q "$root/tests/python/vcan" >"$log" 2>&1
        rc=$?
        set -e
        [[ $rc -eq 0 ]] || { cat "$log"; status=1; }
        tail -1 "$log" | sed 's/^/python (vcan): /'
        count_pytest python "$log"
    fi
    rm -f "$log"
}
echo "== Python module (pytest: host, then vcan in a guest; Release build)"
stage python python_stage

install_stage() {
    local log rc
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
}
echo "== install: find_package(codrive) and pkg-config consumers of an installed tree"
stage install install_stage

echo "== waiting for the builds beside the guest, the fuzzers and the TSan integration tests"
t_wait=$(date +%s)
wait "$beside_pid" || true
echo "(waited $(($(date +%s) - t_wait)) s after the install stage)"
echo "== build: ThreadSanitizer (controller, hand-off and EtherCAT controller tests), beside the guest"
seconds[build-tsan]=$(cat "$bg_dir/build-tsan.seconds" 2>/dev/null || echo 0)
stage_order+=(build-tsan)
if [[ $(cat "$bg_dir/build-tsan.rc" 2>/dev/null || echo 1) -ne 0 ]]; then
    cat "$bg_dir/build-tsan.log"
    status=1
else
    tail -1 "$bg_dir/build-tsan.log"
fi

if [[ ${CODRIVE_SKIP_FUZZ:-0} == 1 ]]; then
    note[fuzz]="skipped on request"
else
    echo "== fuzz (libFuzzer, clang 14, ASan+UBSan build; ${CODRIVE_FUZZ_SECONDS:-10} s per target)"
    seconds[fuzz]=$(cat "$bg_dir/fuzz-run.seconds" 2>/dev/null || echo 0)
    stage_order+=(fuzz)
    cat "$fuzz_log" 2>/dev/null || true
    [[ $(cat "$bg_dir/fuzz.rc" 2>/dev/null || echo 1) -eq 0 ]] || status=1
    passed[fuzz]=$(awk '/^fuzz: [0-9]+ passed/ {print $2}' "$fuzz_log" 2>/dev/null || true)
    failed[fuzz]=$(awk '/^fuzz: [0-9]+ passed/ {print $4}' "$fuzz_log" 2>/dev/null || true)
    if [[ -z ${passed[fuzz]} ]]; then
        failed[fuzz]=1 # the stage did not get as far as running the targets
    fi
fi

# The timed EtherCAT suite counts lost frames and late cycles: nothing runs beside it. It runs at
# SCHED_FIFO where the system allows it (root or CAP_SYS_NICE). (Side by side with two jobs of a
# build, at SCHED_FIFO too, the FoE test at a 1 ms cycle lost 65 of 988 cycles. With
# integration_tests under TSan beside it at nice 19, as until session 22, six of its 67 tests
# lost too many cycles on a 2-vCPU VM that stalls; alone, on the same machine, up to three in a
# run, each passing when run again: run_gtest_retry.)
ethercat_stage() {
    local -a gtest_prefix=()
    if chrt -f 10 true 2>/dev/null; then
        gtest_prefix=(chrt -f 10)
    fi
    run_gtest_retry ethercat "$root/build-asan/tests/ethercat_tests"
}
if [[ ${CODRIVE_SKIP_ETHERCAT:-0} == 1 ]]; then
    echo "== EtherCAT tests: SKIPPED (CODRIVE_SKIP_ETHERCAT=1)"
    note[ethercat]="skipped on request"
else
    echo "== EtherCAT tests (veth; nothing beside them)"
    stage ethercat ethercat_stage
fi

echo "== ThreadSanitizer tests (host)"
stage tsan tsan_stage
# The stage's time: the integration run's own (beside the EtherCAT stage) plus the rest's.
seconds[tsan]=$(($(date +%s) - tsan_rest_t0 + $(cat "$tsan_dir/seconds" 2>/dev/null || echo 0)))

echo "== allocation tests (Release)"
stage release release_stage

# Skips that were asked for: the vcan guard honours CODRIVE_SKIP_VCAN, the veth guard
# CODRIVE_SKIP_ETHERCAT (in the EtherCAT, TSan and Python suites: the Python EtherCAT tests
# need veth). Any other skip is an error.
skip_allowed() { # suite
    case $1 in
    vcan) [[ ${CODRIVE_SKIP_VCAN:-0} == 1 ]] ;;
    ethercat | tsan | python) [[ ${CODRIVE_SKIP_ETHERCAT:-0} == 1 ]] ;;
    *) false ;;
    esac
}

fmt_time() { printf '%dm%02ds' $(($1 / 60)) $(($1 % 60)); }

echo
echo "== summary"
total_passed=0
total_failed=0
total_skipped=0
for suite in "${suites[@]}"; do
    p=${passed[$suite]:-0}
    f=${failed[$suite]:-0}
    s=${skipped[$suite]:-0}
    total_passed=$((total_passed + p))
    total_failed=$((total_failed + f))
    total_skipped=$((total_skipped + s))
    n=${note[$suite]:-}
    if [[ -z $n ]]; then
        if ((p + f + s == 0)); then
            n="ERROR: the suite ran no test"
            status=1
        elif ((s > 0)) && ! skip_allowed "$suite"; then
            n="ERROR: $s test(s) skipped that no CODRIVE_SKIP_* asked to skip"
            status=1
        elif ((s > 0)); then
            n="skips requested"
        fi
    fi
    if [[ -n ${retried[$suite]:-} ]]; then
        n="${n:+$n; }failed, then ran again: ${retried[$suite]}"
    fi
    t=""
    [[ -n ${seconds[$suite]:-} ]] && t=$(fmt_time "${seconds[$suite]}")
    printf '%-9s %5d passed, %d failed, %d skipped  %8s%s\n' "$suite:" "$p" "$f" "$s" "$t" \
        "${n:+  ($n)}"
done
line="stage times:"
for name in "${stage_order[@]}"; do
    line+=" $name $(fmt_time "${seconds[$name]}"),"
done
echo "$line total $(fmt_time $(($(date +%s) - t_start))) (build-tsan, one job until the guest ends, then the fuzzers, then tsan's integration tests, beside vcan, leak, python and install)"
if ((total_failed > 0)); then
    status=1
fi
echo "${total_passed} passed, ${total_failed} failed, ${total_skipped} skipped"
exit $status
