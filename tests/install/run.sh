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
    -DCODRIVE_BUILD_BENCH=OFF -DCODRIVE_BUILD_TOOLS=ON -DCMAKE_INSTALL_PREFIX="$prefix" >/dev/null
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
# The .deb: build it, install it with dpkg (as root) and build the consumer against /usr.
if [[ $(id -u) -eq 0 ]]; then
    rm -f "$work/build"/codrive_*.deb
    if (cd "$work/build" && cpack -G DEB >/dev/null) && deb=$(ls "$work/build"/codrive_*.deb) &&
        dpkg -i "$deb" >/dev/null &&
        cmake -S "$root/tests/install/consumer" -B "$work/deb-consumer" -G Ninja >/dev/null &&
        ninja -C "$work/deb-consumer" >/dev/null && "$work/deb-consumer/consumer" &&
        dpkg -r codrive >/dev/null; then
        echo "install: .deb package ($(basename "$deb")) installed with dpkg, consumer OK"
        passed=$((passed + 1))
    else
        echo "install: .deb package FAILED"
        failed=$((failed + 1))
    fi
fi
echo "install: $passed passed, $failed failed"
((failed == 0))
