#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Leak check of the vcan paths with valgrind memcheck (works in the UML guest; ASan does not):
#  1. vcan_tests in-process tests under valgrind: SocketCanBus kernel filters and error frames.
#  2. codrive-sim under valgrind serving three drives while, each under valgrind too, the codrive
#     CLI scans the bus and reads and writes objects by SDO, and the soak master
#     (SoakVcanMaster.DISABLED_Run: Controller, master, SDO, PDO, SYNC, EventLoop) boots the
#     drives and runs two AKD2G in CSP for 2,000 SYNC cycles at 4 ms; then the simulator is
#     stopped with SIGTERM so it exits normally and valgrind can take its leak summary. Only
#     leaks and memory errors count here: under valgrind PDO timing is not checked.
# Needs vcan0: run it with vcan-scripts/run-in-vcan.sh tests/vcan/leak_check.sh BUILD_DIR.
# Prints one line per process, then "leak-check: N processes clean, M with errors, K failed their
# run" (K: memory-clean or not, the process exited non-zero, e.g. its test failed); exits
# non-zero if a process leaked (definitely/indirectly lost), had a memcheck error, exited
# without a leak summary, or a test failed.
set -euo pipefail
build=${1:?usage: leak_check.sh BUILD_DIR}
filter=${2:-'VcanBus.KernelFiltersPassOnlyMatchingIds:VcanBus.InjectedErrorFramesBecomeBusStateEvents'}
command -v valgrind >/dev/null || { echo "leak-check: valgrind is not installed" >&2; exit 2; }
out=$(mktemp -d)
sim_pid=
cleanup() {
    [[ -z $sim_pid ]] || kill -KILL "$sim_pid" 2>/dev/null || true
    rm -rf "$out"
}
trap cleanup EXIT
start=$(date +%s)
status=0
vg=(valgrind --tool=memcheck --leak-check=full --show-leak-kinds=definite,indirect
    --errors-for-leak-kinds=definite,indirect --error-exitcode=99)
n=0
failed_runs=0
# vcan_tests replaces the global operator new/delete (the allocation counter,
# codrive/testing/counting_new.hpp, malloc/free underneath). In an optimised build valgrind
# pairs some of those calls with its own new/delete tracking and reports "Mismatched free() /
# delete" for blocks that are allocated and freed by the same replacement; only that report is
# turned off for the test binary (leaks and invalid accesses still fail), never for the tools.
vg_extra=()
checked() { # name cmd... : runs cmd under valgrind, its log as vg.<n>.log, its time as time.<n>
    n=$((n + 1))
    local log=$out/vg.$n.log t0=$SECONDS
    "${vg[@]}" "${vg_extra[@]}" --log-file="$log" "$@" >"$out/out.$n.log" 2>&1 || {
        echo "leak-check: '$*' exited with $?" >&2
        tail -20 "$out/out.$n.log" >&2
        status=1
        failed_runs=$((failed_runs + 1))
    }
    echo $((SECONDS - t0)) >"$out/time.$n"
}

# 1. In-process vcan tests.
vg_extra=(--show-mismatched-frees=no)
checked "$build/tests/vcan_tests" --gtest_filter="$filter"
vg_extra=()
grep -hE '^\[( +OK|  FAILED) ' "$out/out.1.log" || true

# 2. The simulator and the CLI.
tools=$build/tools
if [[ -x $tools/codrive-sim ]]; then
    sim_t0=$SECONDS
    "${vg[@]}" --log-file="$out/vg.sim.log" "$tools/codrive-sim" -i vcan0 --node 1:akd2g:1 \
        --node 2:akd2g:1 --node 3:ds-bvs >"$out/sim.out" 2>&1 &
    sim_pid=$!
    for _ in $(seq 300); do
        [[ $(grep -c "ready on" "$out/sim.out") -ge 3 ]] && break
        sleep 0.1
    done
    if [[ -x $tools/codrive ]]; then
        checked "$tools/codrive" scan -i vcan0 --timeout 2000
        checked "$tools/codrive" sdo read -i vcan0 -n 1 0x1018:1 --timeout 2000
        checked "$tools/codrive" sdo read -i vcan0 -n 3 0x1008:0 --timeout 2000
        checked "$tools/codrive" sdo write -i vcan0 -n 3 0x6007:0 3 --type i16 --timeout 2000
    else
        echo "leak-check: $tools/codrive not built; the CLI is not checked" >&2
        status=1
    fi
    # Both the master and the simulator run under valgrind (20-50 times slower): give boot-up
    # SDO requests 5 s and each enable 20 s (2 s failed in CI: stuck in SWITCHED ON).
    vg_extra=(--show-mismatched-frees=no)
    CODRIVE_SOAK_NODES=1:akd2g,2:akd2g,3:ds-bvs:off CODRIVE_SOAK_CYCLES=2000 \
        CODRIVE_SOAK_PERIOD_US=4000 CODRIVE_SOAK_SDO_TIMEOUT_MS=5000 \
        CODRIVE_SOAK_ENABLE_TIMEOUT_MS=20000 checked "$build/tests/vcan_tests" \
        --gtest_also_run_disabled_tests --gtest_filter=SoakVcanMaster.DISABLED_Run
    vg_extra=()
    grep -E '^soak: [0-9]+ SYNC|^soak: heap' "$out/out.$n.log" || true
    kill -TERM "$sim_pid"
    wait "$sim_pid" || { echo "leak-check: codrive-sim exited with $?" >&2; status=1; }
    echo $((SECONDS - sim_t0)) >"$out/time.sim"
    sim_pid=
else
    echo "leak-check: $tools/codrive-sim not built" >&2
    status=1
fi

clean=0
bad=0
for log in "$out"/vg.*.log; do
    cmd=$(awk -F'Command: ' '/Command: / {print $2; exit}' "$log")
    short=$(echo "$cmd" | awk '{n=split($1, p, "/"); $1=p[n]; print substr($0, 1, 70)}')
    if ! grep -q "HEAP SUMMARY" "$log"; then
        printf 'leak-check: %-70s no leak summary (killed?)\n' "$short"
        bad=$((bad + 1))
        continue
    fi
    errors=$(awk '/ERROR SUMMARY:/ {v=$4} END {print v+0}' "$log")
    definite=$(awk '/definitely lost:/ {gsub(",", "", $4); v=$4} END {print v+0}' "$log")
    indirect=$(awk '/indirectly lost:/ {gsub(",", "", $4); v=$4} END {print v+0}' "$log")
    allocs=$(awk '/total heap usage:/ {gsub(",", "", $5); v=$5} END {print v+0}' "$log")
    tag=${log##*/vg.}
    secs=$(cat "$out/time.${tag%.log}" 2>/dev/null || echo "?")
    printf 'leak-check: %-70s allocs %9d  definitely lost %d B  indirectly lost %d B  errors %d  %s s\n' \
        "$short" "$allocs" "$definite" "$indirect" "$errors" "$secs"
    if ((errors > 0 || definite > 0 || indirect > 0)); then
        bad=$((bad + 1))
        echo "---- $log" >&2
        grep -E '^==[0-9]+== ' "$log" | head -80 >&2
    else
        clean=$((clean + 1))
    fi
done
echo "leak-check: $clean processes clean, $bad with errors, $failed_runs failed their run" \
    "($(($(date +%s) - start)) s)"
((bad == 0 && status == 0 && clean > 0))
