#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# codrive-dump decode speed: full decode (SDO reassembly and PDO decoding on) of a generated
# 1,000,000-frame candump log to /dev/null, next to tshark's CANopen decode of the same trace
# (as pcap written by `codrive-dump -w`), plus peak memory on a 10-million-frame stream.
#
# usage: bench/dump_speed.sh [BUILD_DIR]     (a Release build: -DCMAKE_BUILD_TYPE=Release
#                                             -DCODRIVE_SANITIZE=; default: build-release)
# env:   FRAMES (default 1000000), BIG_FRAMES (default 10000000, 0 skips the memory run)
# Target: >= 5 million frames/s of CPU time on one core, flat memory.
set -euo pipefail

build=${1:-build-release}
frames=${FRAMES:-1000000}
big=${BIG_FRAMES:-10000000}
dump=$build/tools/codrive-dump
gen=$build/tools/codrive-gen-trace
for t in "$dump" "$gen"; do
    [[ -x $t ]] || { echo "dump_speed: $t not built (ninja -C $build codrive-dump codrive-gen-trace)" >&2; exit 2; }
done
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

"$gen" "$frames" >"$tmp/trace.log" 2>"$tmp/gen.txt"
n=$(grep -o '[0-9]*' "$tmp/gen.txt" | head -1)
echo "trace: $n frames, $(du -m "$tmp/trace.log" | cut -f1) MiB candump log"

# Best of three runs (the machine may be shared); CPU time is user + sys of the process.
best_cpu=999999
for _ in 1 2 3; do
    /usr/bin/time -f "%e %U %S %M" -o "$tmp/time.txt" "$dump" -r "$tmp/trace.log" --color never >/dev/null
    read -r wall user sys rss <"$tmp/time.txt"
    cpu=$(awk -v u="$user" -v s="$sys" 'BEGIN { print u + s }')
    if awk -v a="$cpu" -v b="$best_cpu" 'BEGIN { exit !(a < b) }'; then
        best_cpu=$cpu best_wall=$wall best_rss=$rss
    fi
done
rate() { awk -v n="$n" -v t="$1" 'BEGIN { if (t <= 0) t = 0.01; printf "%.2f", n / t / 1e6 }'; }
echo "codrive-dump: $(rate "$best_cpu") M frames/s CPU (${best_cpu} s), $(rate "$best_wall") M frames/s wall (${best_wall} s), peak RSS ${best_rss} KiB   [target >= 5 M frames/s]"

"$dump" -r "$tmp/trace.log" -w "$tmp/trace.pcap"
if command -v tshark >/dev/null; then
    /usr/bin/time -f "%e %U %S %M" -o "$tmp/time.txt" \
        tshark -r "$tmp/trace.pcap" -d can.subdissector,canopen >/dev/null 2>"$tmp/tshark.err" ||
        /usr/bin/time -f "%e %U %S %M" -o "$tmp/time.txt" tshark -r "$tmp/trace.pcap" >/dev/null 2>>"$tmp/tshark.err"
    read -r wall user sys rss <"$tmp/time.txt"
    cpu=$(awk -v u="$user" -v s="$sys" 'BEGIN { print u + s }')
    echo "tshark (one-line CANopen decode of the same trace as pcap): $(rate "$cpu") M frames/s CPU (${cpu} s), $(rate "$wall") M frames/s wall (${wall} s), peak RSS ${rss} KiB"
    if [[ -s $tmp/tshark.err ]]; then sed 's/^/  tshark: /' "$tmp/tshark.err" | head -3; fi
else
    echo "tshark: not installed"
fi

if [[ $big -gt 0 ]]; then
    # Streamed from the generator through stdin: memory must not grow with the trace.
    /usr/bin/time -f "%e %U %S %M" -o "$tmp/time.txt" \
        sh -c "'$gen' $big 2>/dev/null | '$dump' -r - --stats >/dev/null"
    read -r wall user sys rss <"$tmp/time.txt"
    echo "codrive-dump on a $big-frame stream: peak RSS ${rss} KiB (the 1M-frame file: ${best_rss} KiB)"
fi
