#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# A session on one virtual CAN bus: starts codrive-sim, waits for its "ready" lines, runs your
# commands against it, stops the simulator. Copy it and edit the two marked parts.
#
# Where the kernel has no SocketCAN, every run-in-vcan.sh call boots a NEW guest with a NEW, empty
# vcan0: a simulator started in one call is gone in the next. Put everything that talks to it in
# one call:
#   bash vcan-scripts/run-in-vcan.sh bash vcan-scripts/examples/session.sh
#   bash vcan-scripts/run-in-vcan.sh bash vcan-scripts/examples/session.sh codrive scan -i vcan0
# With arguments, they are the one command to run; without, the commands below run.
# Tools: from PATH if `codrive` is there (an installed prefix's bin/), else $CODRIVE_BIN, else the
# first of build-release/tools, build/tools, build-ubsan/tools in the repository (not an ASan
# build: it cannot run in the guest, see docs/vcan.md).
set -euo pipefail
repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)

# ---- 1. the simulated bus (docs/cli/codrive-sim.md) -----------------------------------------
iface=${CODRIVE_IFACE:-vcan0}
sim_args=(-i "$iface" --node 1:akd2g --node 2:ds-bvs)
# ---------------------------------------------------------------------------------------------

if [[ -z ${CODRIVE_BIN:-} ]] && command -v codrive >/dev/null; then
    CODRIVE_BIN=$(dirname "$(command -v codrive)")
fi
if [[ -z ${CODRIVE_BIN:-} ]]; then
    for d in build-release build build-ubsan; do
        if [[ -x $repo/$d/tools/codrive ]]; then
            CODRIVE_BIN=$repo/$d/tools
            break
        fi
    done
fi
[[ -x ${CODRIVE_BIN:-}/codrive-sim ]] || {
    echo "session.sh: no codrive-sim found: install codrive (README 'Using the library'), build it" \
        "(build-release/tools/), or set CODRIVE_BIN to the directory holding the tools." >&2
    exit 2
}
export PATH=$CODRIVE_BIN:$PATH

sim_log=$(mktemp)
codrive-sim "${sim_args[@]}" >"$sim_log" 2>&1 &
sim_pid=$!
trap 'kill "$sim_pid" 2>/dev/null || true; wait "$sim_pid" 2>/dev/null || true; rm -f "$sim_log"' EXIT

# One "codrive-sim: ... ready on vcan0" line per simulated node.
nodes=$(grep -o -- '--node' <<<"${sim_args[*]}" | wc -l)
for _ in $(seq 200); do
    (($(grep -c ' ready on ' "$sim_log") >= nodes)) && break
    kill -0 "$sim_pid" 2>/dev/null || break
    sleep 0.05
done
cat "$sim_log"
if (($(grep -c ' ready on ' "$sim_log") < nodes)); then
    echo "session.sh: codrive-sim did not report ready for $nodes node(s) within 10 s" >&2
    exit 1
fi

if (($# > 0)); then
    "$@"
    exit
fi
# ---- 2. your commands (docs/cli/) -----------------------------------------------------------
codrive scan -i "$iface"
# e.g.: codrive sdo read -i "$iface" -n 1 0x1008:0 --type str
#       codrive drive -i "$iface" -n 1 --axis 2 status
# ---------------------------------------------------------------------------------------------
