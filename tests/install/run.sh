#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Installs codrive into a scratch prefix and builds two consumers against it: one with
# find_package(codrive), one with pkg-config. Prints "install: N passed, M failed".
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
work=${1:-$root/build-install}
jobs=${CODRIVE_JOBS:-$(nproc)}
prefix=$work/prefix
passed=0
failed=0
cmake -S "$root" -B "$work/build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCODRIVE_BUILD_TESTS=OFF \
    -DCODRIVE_BUILD_BENCH=OFF -DCODRIVE_BUILD_TOOLS=OFF -DCMAKE_INSTALL_PREFIX="$prefix" >/dev/null
ninja -C "$work/build" -j "$jobs" >/dev/null
rm -rf "$prefix"
cmake --install "$work/build" >/dev/null

if cmake -S "$root/tests/install/consumer" -B "$work/consumer" -G Ninja \
    -DCMAKE_PREFIX_PATH="$prefix" >/dev/null && ninja -C "$work/consumer" >/dev/null &&
    "$work/consumer/consumer"; then
    echo "install: find_package(codrive) consumer OK"
    passed=$((passed + 1))
else
    echo "install: find_package(codrive) consumer FAILED"
    failed=$((failed + 1))
fi

if PKG_CONFIG_PATH="$prefix/lib/pkgconfig" g++ -std=c++20 -o "$work/pc-consumer" \
    "$root/tests/install/consumer/main.cpp" \
    $(PKG_CONFIG_PATH="$prefix/lib/pkgconfig" pkg-config --cflags --libs codrive) &&
    "$work/pc-consumer"; then
    echo "install: pkg-config consumer OK"
    passed=$((passed + 1))
else
    echo "install: pkg-config consumer FAILED"
    failed=$((failed + 1))
fi
echo "install: $passed passed, $failed failed"
((failed == 0))
