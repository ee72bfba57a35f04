#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The CAN demo's scenario over EtherCAT: a veth pair (slave end in its own network namespace),
# codrive-ecat-sim with the demo's drives (an AKD2G with two axes, a DS-BVS) on one end, the same
# program as the CAN demo, codrive-demo (examples/demo.cpp), on the other with the bus file
# demo-ecat.yml, which differs from demo-bus.yml only in its transport section: boot, enable,
# homing, a coordinated jerk-limited CSP move, CSV, an injected fault diagnosed and reset, safe
# shutdown. Needs root (veth and network namespaces).
#   vcan-scripts/demo-ecat.sh                  install, build (build-release), run
#   vcan-scripts/demo-ecat.sh --build-dir DIR  run with an existing build (CI)
#   ... [--build-dir DIR] --fault-node 0       further arguments go to codrive-demo
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
build=""
if [[ "${1:-}" == "--build-dir" ]]; then
    build=$2
    shift 2
else
    bash .ci/install-deps.sh
    build=$root/build-release
    cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
        -DCODRIVE_BUILD_TESTS=OFF -DCODRIVE_BUILD_BENCH=OFF >/dev/null
    ninja -C "$build" -j "${CODRIVE_JOBS:-$(nproc)}" codrive-ecat-sim codrive-demo
fi
if [[ $(id -u) -ne 0 ]]; then
    echo "demo-ecat.sh: creating a veth pair needs root (run with sudo)" >&2
    exit 1
fi
ns=codrive-demo-$$
master_if=ecm-demo
slave_if=ecs-demo
bus_file=$root/vcan-scripts/demo-ecat.yml
sim_pid=""
cleanup() {
    [[ -n "$sim_pid" ]] && kill "$sim_pid" 2>/dev/null && wait "$sim_pid" 2>/dev/null || true
    ip link del "$master_if" 2>/dev/null || true
    ip netns del "$ns" 2>/dev/null || true
}
trap cleanup EXIT
# A name clash with an earlier, interrupted run: remove the stale pair first.
ip link del "$master_if" 2>/dev/null || true
ip netns add "$ns"
ip link add "$master_if" type veth peer name "$slave_if"
ip link set "$slave_if" netns "$ns"
ip link set "$master_if" up
ip netns exec "$ns" ip link set "$slave_if" up
echo "== veth pair $master_if (controller) <-> $slave_if (simulated AKD2G + DS-BVS, netns $ns)"
log=$(mktemp)
ip netns exec "$ns" "$build/tools/codrive-ecat-sim" --ethercat "$slave_if" --slave akd2g --slave ds-bvs >"$log" 2>&1 &
sim_pid=$!
for _ in $(seq 100); do
    grep -q ready "$log" && break
    sleep 0.1
done
cat "$log"
"$build/examples/codrive-demo" "$bus_file" "$@"
