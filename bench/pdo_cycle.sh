#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Instructions per SYNC cycle of the master PDO engine and of the memcpy floor, via callgrind:
# each variant runs with N and with 0 cycles, and (Ir(N) − Ir(0)) / N is the per-cycle cost.
# Fails when the engine is more than 5 % cheaper than the floor (the floor would be wrong).
# Usage: bench/pdo_cycle.sh [path/to/bench_pdo_cycle] [cycles]
set -euo pipefail
bin=${1:-build-rel/bench/bench_pdo_cycle}
cycles=${2:-20000}
if ! command -v valgrind >/dev/null; then
    echo "valgrind is not installed (apt-get install valgrind)" >&2
    exit 2
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
ir() { # variant cycles → total instructions
    valgrind --tool=callgrind --callgrind-out-file="$tmp/out" "$bin" "$1" "$2" >"$tmp/log" 2>&1
    awk '/^summary:/ {print $2}' "$tmp/out"
}
"$bin" both "$cycles" # wall time and the allocation check, natively
declare -A per_cycle
for v in engine floor; do
    full=$(ir "$v" "$cycles")
    base=$(ir "$v" 0)
    per_cycle[$v]=$(awk -v f="$full" -v b="$base" -v n="$cycles" 'BEGIN { printf "%.0f", (f - b) / n }')
    echo "$v ${per_cycle[$v]} instructions per SYNC cycle (callgrind, $cycles cycles)"
done
# Instruction counts are exact (no spread to report). An engine cheaper than the memcpy floor by
# more than 5 % means the floor does not do the same work: the figure cannot be trusted.
awk -v e="${per_cycle[engine]}" -v f="${per_cycle[floor]}" 'BEGIN {
    printf "engine / floor = %.2f instructions\n", e / f
    if (f / e > 1.05) {
        print "floor check failed: the engine needs fewer instructions than its memcpy floor (more than 5 % fewer), so the floor is not the same work" > "/dev/stderr"
        exit 1
    }
}'
