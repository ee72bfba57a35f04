#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Regenerates devices/*.eds and devices/*.xml from codrive's built-in profiles (the one truth):
#   devices/regenerate.sh [BUILD_DIR]     (default build-ubsan; needs its `codrive` tool built)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build-ubsan}
codrive=$build/tools/codrive
if [[ ! -x $codrive ]]; then
    echo "regenerate.sh: $codrive not found; build it first: ninja -C $build codrive" >&2
    exit 1
fi
# The same list as codrive::devices::device_files() (tools/devices/src/eds_export.cpp).
for profile in akd2g ds-bvs fio; do
    "$codrive" eds export --profile "$profile" -o "$root/devices/$profile.eds"
    "$codrive" esi export --profile "$profile" -o "$root/devices/$profile.xml"
done
echo "regenerate.sh: wrote $root/devices/{akd2g,ds-bvs,fio}.{eds,xml}"
