#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Instructions per SYNC cycle of the master PDO engine and of the memcpy floor, via callgrind:
# each variant runs with N and with 0 cycles, and (Ir(N) − Ir(0)) / N is the per-cycle cost.
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
for v in engine floor; do
    full=$(ir "$v" "$cycles")
    base=$(ir "$v" 0)
    awk -v v="$v" -v f="$full" -v b="$base" -v n="$cycles" \
        'BEGIN { printf "%-7s %.0f instructions per SYNC cycle (callgrind, %d cycles)\n", v, (f - b) / n, n }'
done
