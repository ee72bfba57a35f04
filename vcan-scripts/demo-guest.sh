#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The demo itself, run where vcan exists: codrive processes talking over vcan0.
set -euo pipefail
build=${1:?usage: demo-guest.sh BUILD_DIR}
codrive=$build/tools/codrive
pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; }
trap cleanup EXIT

step() { printf '\n\033[1m== %s\033[0m\n' "$*"; }

step "interface"
"$codrive" bus info -i vcan0

step "two codrive processes exchange 10,000 numbered frames on vcan0 (none may be lost)"
out=$(mktemp)
"$codrive" bus sink -i vcan0 --count 10000 >"$out" 2>&1 &
pids+=($!)
for _ in $(seq 100); do grep -q ready "$out" && break; sleep 0.05; done
"$codrive" bus stream -i vcan0 --count 10000
wait "${pids[-1]}"
cat "$out"

if [[ -x $build/tools/codrive ]] && "$codrive" sdo --help >/dev/null 2>&1; then
    step "SDO: codrive sdo serve (node 5) and codrive sdo read/write in another process"
    "$codrive" sdo serve -i vcan0 -n 5 >"$out" 2>&1 &
    pids+=($!)
    sleep 0.3
    "$codrive" sdo read -i vcan0 -n 5 0x1008:0 --type str
    "$codrive" sdo read -i vcan0 -n 5 0x1018:1 --type u32
fi

step "demo finished"
