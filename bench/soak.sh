#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Soak on vcan: starts codrive-sim with 4 drives (2 AKD2G, 2 DS-BVS, one axis each) and runs
# bench_soak against them in CSP. Needs vcan0; on a host without SocketCAN run it in the guest:
#   vcan-scripts/run-in-vcan.sh --timeout 3600 bench/soak.sh BUILD_DIR [CYCLES] [SYNC_PERIOD_US]
# BUILD_DIR needs CODRIVE_BUILD_BENCH=ON and no ASan (e.g. build-rel); defaults 1000000 cycles at
# 2000 us; SOAK_NODES="1:akd2g,2:akd2g,3:akd2g,4:akd2g" picks the drives
# (ID:PROFILE[:MODE], MODE csp or csv). Exit status: bench_soak's (0 = no PDO lost, heap/fds/threads flat),
# or 1 if codrive-sim reports frames dropped on its socket.
set -euo pipefail
build=${1:?usage: soak.sh BUILD_DIR [CYCLES] [SYNC_PERIOD_US]}
cycles=${2:-1000000}
period=${3:-2000}
nodes=${SOAK_NODES:-1:akd2g,2:akd2g,3:akd2g,4:akd2g}
sim_args=()
IFS=, read -ra items <<<"$nodes"
for item in "${items[@]}"; do
    IFS=: read -r id profile _ <<<"$item"
    sim_args+=(--node "$id:$profile:1")
done
sim_bin=$build/sim/codrive-sim
[[ -x $sim_bin ]] || sim_bin=$build/tools/codrive-sim
soak_bin=$build/bench/bench_soak
for b in "$sim_bin" "$soak_bin"; do
    [[ -x $b ]] || { echo "soak: $b not built" >&2; exit 2; }
done
log=$(mktemp)
"$sim_bin" -i vcan0 "${sim_args[@]}" >"$log" 2>&1 &
sim=$!
trap 'kill "$sim" 2>/dev/null || true; wait "$sim" 2>/dev/null || true; rm -f "$log"' EXIT
for _ in $(seq 100); do
    [[ $(grep -c "ready on" "$log") -ge ${#items[@]} ]] && break
    sleep 0.1
done
echo "soak: $(date -u +%FT%TZ) start, $(nproc) CPU(s), ${CODRIVE_VCAN:-native} vcan"
status=0
"$soak_bin" "$cycles" "$period" vcan0 "$nodes" || status=$?
echo "soak: $(date -u +%FT%TZ) end"
if ! kill -0 "$sim" 2>/dev/null; then
    echo "soak: codrive-sim died during the run:" >&2
    cat "$log" >&2
    status=1
else
    kill -TERM "$sim"
    wait "$sim" || true
    # codrive-sim sets a 4 MiB SO_RCVBUF and reports what the kernel still dropped on its socket.
    grep -E "dropped by the kernel" "$log" | sed 's/^/soak: /' || true
    if grep -qE "dropped by the kernel \(" "$log"; then
        echo "soak: FAILED: the simulator's socket overflowed (see above)" >&2
        status=1
    fi
fi
exit $status
