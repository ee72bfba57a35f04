#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The README's main job: install what is needed, build codrive, bring vcan up (natively or in a
# User-Mode-Linux guest) and run the demo there.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
bash .ci/install-deps.sh
cmake -S "$root" -B "$root/build-release" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DCODRIVE_BUILD_TESTS=OFF -DCODRIVE_BUILD_BENCH=OFF >/dev/null
ninja -C "$root/build-release" -j "${CODRIVE_JOBS:-$(nproc)}"
exec bash vcan-scripts/run-in-vcan.sh -v bash vcan-scripts/demo-guest.sh "$root/build-release"
