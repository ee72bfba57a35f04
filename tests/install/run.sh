#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Installs codrive into a non-default prefix exactly as README.md says and checks what a user does
# with it: README's CMake and pkg-config consumers (lines extracted from README.md), the same for
# codrive::sim, every docs ```cpp snippet, every documented command line, the per-command pages in
# docs/cli/ against --help, --version, the vcan session template, and the .deb (as root).
# Prints "install: N passed, M failed". Usage: run.sh [WORK_DIR] (default build-install/).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
work=${1:-$root/build-install}
mkdir -p "$work"
work=$(cd "$work" && pwd)
jobs=${CODRIVE_JOBS:-$(nproc)}
# A prefix nobody searches by default: the README's /opt/codrive under the work directory.
prefix=$work/xyz/opt/codrive
passed=0
failed=0
pass() { echo "install: ok: $*"; passed=$((passed + 1)); }
fail() { echo "install: FAILED: $*"; failed=$((failed + 1)); }

# block FILE SECTION LANG N: the N-th (1-based) ```LANG block under the "## SECTION" header.
block() {
    awk -v section="## $2" -v lang="$3" -v want="$4" '
        /^## / { inside = ($0 == section) }
        inside && /^```/ && !open { open = 1; n += ($0 == "```" lang); take = ($0 == "```" lang && n == want); next }
        open && /^```/ { open = 0; take = 0; next }
        take { print }' "$1"
}
readme_install=$(block "$root/README.md" "Using the library" sh 1)
readme_cmake=$(block "$root/README.md" "Using the library" cmake 1)
readme_cmake_build=$(block "$root/README.md" "Using the library" sh 2)
readme_pkgconfig=$(block "$root/README.md" "Using the library" sh 3)
sim_link=$(block "$root/docs/codrive-sim.md" "Library use" cmake 1)
readme_python=$(block "$root/README.md" "Python" sh 1)
for v in readme_install readme_cmake readme_cmake_build readme_pkgconfig sim_link readme_python; do
    [[ -n ${!v} ]] || { echo "install: FAILED: README.md / docs/codrive-sim.md lost the block $v"; exit 1; }
done
# The README's commands with its example prefix and build directory replaced by ours.
readme_cmd() { sed -e "s#/opt/codrive#$prefix#g" -e "s#build-release#$work/build#g"; }

# 1. Build and install with the README's own commands (Release, tools included).
rm -rf "$work/xyz"
if (cd "$root" && CMAKE_BUILD_PARALLEL_LEVEL=$jobs bash -euo pipefail -c "$(readme_cmd <<<"$readme_install")") \
    >"$work/install.log" 2>&1; then
    pass "README install commands (cmake --install --prefix $prefix)"
else
    tail -20 "$work/install.log"
    fail "README install commands"
    echo "install: $passed passed, $failed failed"
    exit 1
fi

# consumer NAME MAIN CMAKE_TEXT BUILD_TEXT: a project with README's files, built and run.
consumer() {
    local dir=$work/consumers/$1
    rm -rf "$dir"
    mkdir -p "$dir"
    cp "$root/tests/install/consumer/$2" "$dir/main.cpp"
    [[ -n $3 ]] && printf '%s\n' "$3" >"$dir/CMakeLists.txt"
    (cd "$dir" && env -u PKG_CONFIG_PATH bash -euo pipefail -c "$(readme_cmd <<<"$4")") >"$dir.log" 2>&1
}
if consumer cmake main.cpp "$readme_cmake" "$readme_cmake_build"; then
    pass "README find_package(codrive) consumer builds from $prefix and runs"
else
    tail -15 "$work/consumers/cmake.log"
    fail "README find_package(codrive) consumer"
fi
if consumer pkg-config main.cpp "" "$readme_pkgconfig"; then
    pass "README pkg-config consumer builds from $prefix and runs"
else
    tail -15 "$work/consumers/pkg-config.log"
    fail "README pkg-config consumer"
fi
# codrive::sim: README's CMakeLists with docs/codrive-sim.md's link line, and pkg-config codrive-sim.
sim_cmake=$(printf '%s\n' "$readme_cmake" | grep -v '^target_link_libraries'; printf '%s\n' "$sim_link" | sed 's/ *#.*//')
if consumer sim-cmake sim_main.cpp "$sim_cmake" "$readme_cmake_build"; then
    pass "codrive::sim consumer (docs/codrive-sim.md) builds and runs"
else
    tail -15 "$work/consumers/sim-cmake.log"
    fail "codrive::sim consumer"
fi
if consumer sim-pkg-config sim_main.cpp "" "${readme_pkgconfig//--libs codrive)/--libs codrive-sim)}"; then
    pass "pkg-config codrive-sim consumer builds and runs"
else
    tail -15 "$work/consumers/sim-pkg-config.log"
    fail "pkg-config codrive-sim consumer"
fi
# The pkg-config file follows the prefix: moved elsewhere, it still points at its own tree.
mv "$work/xyz" "$work/moved"
moved_inc=$(PKG_CONFIG_PATH=$work/moved/opt/codrive/lib/pkgconfig pkg-config --variable=includedir codrive)
mv "$work/moved" "$work/xyz"
if [[ $(cd "$moved_inc" 2>/dev/null && pwd) == "$work/moved/opt/codrive/include" ]] ||
    [[ $(realpath -m "$moved_inc") == "$work/moved/opt/codrive/include" ]]; then
    pass "codrive.pc is relocatable (includedir follows the tree: $moved_inc)"
else
    fail "codrive.pc includedir is $moved_inc after moving the tree, not under it"
fi

# The Python package: README's two lines against the installed tree (Debian's python3).
version=$(awk -F'[ )]' '/^project\(codrive VERSION/ {print $3}' "$root/CMakeLists.txt")
if out=$(cd "$work" && bash -euo pipefail -c "$(readme_cmd <<<"$readme_python")" 2>&1) &&
    [[ $out == "$version" ]]; then
    pass "README Python lines: import codrive from $prefix prints $out"
else
    printf '%s\n' "$out" | tail -5
    fail "README Python lines printed '$out', not $version"
fi

# --version on every tool.
for tool in codrive codrive-dump codrive-sim codrive-ecat-sim; do
    if out=$("$prefix/bin/$tool" --version 2>&1) && [[ $out =~ ^$tool\ [0-9]+\.[0-9]+\.[0-9]+$ ]]; then
        pass "$tool --version prints '$out'"
    else
        fail "$tool --version printed '$out'"
    fi
done

# Docs are code: snippets, command lines and per-command pages (one ok/FAILED line each).
docs_check() {
    local out rc=0
    out=$(/usr/bin/python3 "$root/tests/install/check_docs.py" "$@" 2>&1) || rc=$?
    while IFS= read -r line; do
        case $line in
            ok:*) pass "${line#ok: }" ;;
            FAILED:*) fail "${line#FAILED: }" ;;
            *) echo "    $line" ;;
        esac
    done <<<"$out"
    if ((rc != 0)) && ! grep -q '^FAILED' <<<"$out"; then fail "check_docs.py $1 exited $rc"; fi
}
docs_check snippets --prefix "$prefix" --work "$work/snippets"
docs_check commands --bin "$prefix/bin"
docs_check pages --bin "$prefix/bin"

# The vcan session template (docs/vcan.md) in a guest, with the installed tools.
if out=$(PATH=$prefix/bin:$PATH bash "$root/vcan-scripts/run-in-vcan.sh" --ifaces 1 --timeout 300 \
    bash "$root/vcan-scripts/examples/session.sh" 2>&1) &&
    grep -Eq '^ +1 +[a-z-]+ +0x00020192 ' <<<"$out" && grep -q ' found$' <<<"$out"; then
    pass "vcan-scripts/examples/session.sh in a guest: codrive-sim ready, codrive scan found node 1"
else
    printf '%s\n' "$out" | tail -15
    fail "vcan-scripts/examples/session.sh"
fi

# The .deb: build it, install it with dpkg (as root) and build README's consumer against /usr.
# (-B: no __pycache__ left in /usr/lib/python3/dist-packages/codrive after dpkg -r.)
if [[ $(id -u) -eq 0 ]]; then
    rm -f "$work/build"/codrive_*.deb
    if (cd "$work/build" && cpack -G DEB >/dev/null) && deb=$(ls "$work/build"/codrive_*.deb) &&
        dpkg -i "$deb" >/dev/null &&
        consumer deb main.cpp "$readme_cmake" "cmake -S . -B build && cmake --build build && ./build/app" &&
        py_out=$(cd / && env -u PYTHONPATH /usr/bin/python3 -B -c "import codrive; print(codrive.__version__)") &&
        [[ $py_out == "$version" ]] &&
        dpkg -r codrive >/dev/null; then
        pass ".deb package ($(basename "$deb")) installed with dpkg, README consumer OK, import codrive OK"
    else
        dpkg -r codrive >/dev/null 2>&1 || true
        fail ".deb package"
    fi
fi
echo "install: $passed passed, $failed failed"
((failed == 0))
