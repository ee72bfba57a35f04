#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# codrive-dump decode speed: full decode (SDO reassembly and PDO decoding on) of a generated
# 1,000,000-frame candump log to /dev/null, next to tshark's CANopen decode of the same trace
# (as pcap written by `codrive-dump -w`), plus peak memory on a 10-million-frame stream.
# Both decoders run RUNS times, interleaved (codrive, tshark, codrive, ...); each reports the
# median CPU time (user + sys) with its minimum and maximum. tshark must accept the CANopen
# dissector option and actually decode CANopen, or the script fails: a tshark that only dissects
# raw CAN frames is no comparison.
#
# usage: bench/dump_speed.sh [BUILD_DIR]     (a Release build: -DCMAKE_BUILD_TYPE=Release
#                                             -DCODRIVE_SANITIZE=; default: build-release)
# env:   FRAMES (default 1000000), BIG_FRAMES (default 10000000, 0 skips the memory run),
#        RUNS (default 5)
# Target: >= 5 million frames/s of CPU time on one core, flat memory.
set -euo pipefail

build=${1:-build-release}
frames=${FRAMES:-1000000}
big=${BIG_FRAMES:-10000000}
runs=${RUNS:-5}
dump=$build/tools/codrive-dump
gen=$build/tools/codrive-gen-trace
for t in "$dump" "$gen"; do
    [[ -x $t ]] || { echo "dump_speed: $t not built (ninja -C $build codrive-dump codrive-gen-trace)" >&2; exit 2; }
done
command -v tshark >/dev/null || { echo "dump_speed: tshark is not installed, so there is no comparison (apt-get install tshark)" >&2; exit 2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

"$gen" "$frames" >"$tmp/trace.log" 2>"$tmp/gen.txt"
n=$(grep -o '[0-9]*' "$tmp/gen.txt" | head -1)
echo "trace: $n frames, $(du -m "$tmp/trace.log" | cut -f1) MiB candump log; $runs interleaved runs per decoder"
"$dump" -r "$tmp/trace.log" -w "$tmp/trace.pcap"

# The dissector option must be accepted and must produce CANopen lines.
tshark_args=(-r "$tmp/trace.pcap" -d can.subdissector,canopen)
if ! tshark "${tshark_args[@]}" -c 200 >"$tmp/probe.txt" 2>"$tmp/probe.err"; then
    echo "dump_speed: tshark refused the CANopen dissector option (-d can.subdissector,canopen): $(head -1 "$tmp/probe.err")" >&2
    exit 1
fi
if ! grep -q CANopen "$tmp/probe.txt"; then
    echo "dump_speed: tshark ran but decoded no CANopen in the first 200 frames, so its time would not be a CANopen decode" >&2
    exit 1
fi

# timed NAME CMD...: one run; appends "cpu wall rss" to $tmp/NAME.
timed() {
    local name=$1
    shift
    /usr/bin/time -f "%e %U %S %M" -o "$tmp/time.txt" "$@" >/dev/null 2>"$tmp/err.txt" || {
        echo "dump_speed: $name failed: $(head -1 "$tmp/err.txt")" >&2
        exit 1
    }
    read -r wall user sys rss <"$tmp/time.txt"
    echo "$(awk -v u="$user" -v s="$sys" 'BEGIN { print u + s }') $wall $rss" >>"$tmp/$name"
}
for _ in $(seq "$runs"); do
    timed codrive "$dump" -r "$tmp/trace.log" --color never
    timed tshark tshark "${tshark_args[@]}"
done

# summary NAME LABEL: median CPU time with min and max, as frames/s; median wall; max RSS.
summary() {
    sort -n "$tmp/$1" | awk -v n="$n" -v label="$2" '
        { cpu[NR] = $1; wall[NR] = $2; if ($3 > rss) rss = $3 }
        END {
            m = int((NR + 1) / 2)
            c = cpu[m] > 0 ? cpu[m] : 0.01
            lo = cpu[NR] > 0 ? cpu[NR] : 0.01; hi = cpu[1] > 0 ? cpu[1] : 0.01
            printf "%s: %.2f M frames/s CPU (median of %d; min %.2f, max %.2f), median CPU %.2f s, peak RSS %d KiB\n",
                label, n / c / 1e6, NR, n / lo / 1e6, n / hi / 1e6, c, rss
            print n / c > "/dev/stderr"
        }' 2>"$tmp/$1.rate"
}
summary codrive "codrive-dump (full decode)"
summary tshark "tshark (one-line CANopen decode of the same trace as pcap)"
echo "  [target for codrive-dump: >= 5 M frames/s]"

if [[ $big -gt 0 ]]; then
    # Streamed from the generator through stdin: memory must not grow with the trace.
    /usr/bin/time -f "%e %U %S %M" -o "$tmp/time.txt" \
        sh -c "'$gen' $big 2>/dev/null | '$dump' -r - --stats >/dev/null"
    read -r wall user sys rss <"$tmp/time.txt"
    echo "codrive-dump on a $big-frame stream: peak RSS ${rss} KiB"
fi
