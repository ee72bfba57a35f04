#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The demo itself, run where vcan exists: simulated drives (an AKD2G with two axes and a
# DS-BVS) in one process, the controller demo in another, talking CANopen over vcan0.
set -euo pipefail
build=${1:?usage: demo-guest.sh BUILD_DIR}
here=$(cd "$(dirname "$0")" && pwd)
sim_log=$(mktemp)
pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; }
trap cleanup EXIT

printf '\n\033[1m== simulated drives on vcan0: node 1 AKD2G (2 axes), node 2 DS-BVS\033[0m\n'
"$build/tools/codrive-sim" -i vcan0 --node 1:akd2g --node 2:ds-bvs >"$sim_log" 2>&1 &
pids+=($!)
for _ in $(seq 100); do
    [[ $(grep -c ready "$sim_log") -ge 2 ]] && break
    sleep 0.05
done
cat "$sim_log"

printf '\n\033[1m== codrive scan: who is on the bus\033[0m\n'
"$build/tools/codrive" scan -i vcan0

status=0
"$build/examples/codrive-demo" "$here/demo-bus.yml" || status=$?
exit $status
