#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Installs every Debian 12 package codrive needs to build, test and run its demo (idempotent).
set -euo pipefail

packages=(
    build-essential cmake ninja-build pkg-config git
    libsocketcan-dev libfmt-dev libeigen3-dev libgtest-dev libgmock-dev libbenchmark-dev
    libcli11-dev libexpected-dev libyaml-cpp-dev nlohmann-json3-dev libpugixml-dev zlib1g-dev
    can-utils iproute2 kmod user-mode-linux tshark
    clang-14 clang-format-14 libclang-rt-14-dev lld-14 valgrind python3
    python3-dev pybind11-dev python3-pytest python3-can
    nodejs npm chromium
)
# Sanitizer builds (ASan+UBSan, TSan) and fuzz stage: clang-14, linked with lld (lld-14);
# the fuzz stage compiles with -fsanitize=fuzzer; libFuzzer itself
# (libclang_rt.fuzzer-x86_64.a) and the ASan/UBSan runtimes for clang come from
# libclang-rt-14-dev (dpkg -S libclang_rt.fuzzer-x86_64.a on Debian 12). Leak check: valgrind.
# ESI XML files (devices/*.xml, `codrive esi export`): libpugixml-dev.
# Vector BLF traces (codrive-dump): zlib1g-dev, the containers are zlib streams.
# The Python module (python/, docs/python.md): python3-dev, pybind11-dev; its tests: python3-pytest,
# and python3-can, whose trace writers check codrive-dump's readers (tests/python/test_python_can_traces.py).
# codrive-dump --report: npm (with nodejs) fetches uPlot at build time (tools/dump/report,
# `npm ci` on the committed package-lock.json); the report test loads the page in chromium.

missing=()
for p in "${packages[@]}"; do
    # A Node.js from elsewhere (e.g. NodeSource's nodejs, which bundles npm and conflicts with
    # Debian's npm package) serves as well: only the commands are needed.
    case $p in
    nodejs) command -v node >/dev/null && continue ;;
    npm) command -v npm >/dev/null && continue ;;
    esac
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]} == 0)); then
    exit 0
fi
if [[ $(id -u) -ne 0 ]]; then
    echo "install-deps: missing packages: ${missing[*]} (run as root, or: sudo apt-get install ${missing[*]})" >&2
    exit 1
fi
echo "install-deps: installing ${missing[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
apt-get update -q >/dev/null
apt-get install -y -q --no-install-recommends "${missing[@]}" >/dev/null
