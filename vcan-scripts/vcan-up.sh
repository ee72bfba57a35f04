#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Load the vcan driver and create/bring up vcan0..vcan{N-1} (native kernel or User-Mode-Linux guest).
set -euo pipefail

usage() {
    echo "usage: vcan-up.sh [N]   (create and bring up vcan0..vcan{N-1}; default N=4)" >&2
}

die() {
    echo "vcan-up: $*" >&2
    exit 1
}

n=4
case $# in
    0) ;;
    1)
        case $1 in
            -h | --help) usage; exit 0 ;;
        esac
        n=$1
        ;;
    *) usage; exit 2 ;;
esac
if ! [[ $n =~ ^[0-9]+$ ]] || ((n < 1 || n > 64)); then
    usage
    die "N must be an integer from 1 to 64, got '$n'."
fi

export PATH="$PATH:/usr/local/sbin:/usr/sbin:/sbin"

iface_up() { # true if the interface exists and is administratively up
    local flags
    [[ -r /sys/class/net/$1/flags ]] || return 1
    flags=$(<"/sys/class/net/$1/flags")
    (((flags & 0x1) != 0))
}

all_up() {
    local i
    for ((i = 0; i < n; i++)); do
        iface_up "vcan$i" || return 1
    done
}

# Fast path: nothing to do (also works without root).
if all_up; then
    exit 0
fi

command -v ip >/dev/null 2>&1 || die "the 'ip' command is missing (apt-get install iproute2)."

module_loaded() { [[ -d /sys/module/${1//-/_} ]]; }

# Inside a User-Mode-Linux guest the modules live in /usr/lib/uml/modules/<release>, where plain
# modprobe does not look. 'modprobe -d ROOT' looks in ROOT/lib/modules/<release>, so point a
# temporary ROOT there (this resolves dependencies from the shipped modules.dep).
uml_modprobe() {
    local release moddir root rc=0
    release=$(uname -r)
    moddir=/usr/lib/uml/modules/$release
    [[ -d $moddir ]] || return 1
    root=$(mktemp -d "${TMPDIR:-/tmp}/vcan-up-modroot.XXXXXX") || return 1
    mkdir -p "$root/lib/modules"
    ln -s "$moddir" "$root/lib/modules/$release"
    modprobe -d "$root" "$@" 2>/dev/null || rc=$?
    rm -rf -- "$root"
    return "$rc"
}

# Last resort inside UML: plain insmod in dependency order.
uml_insmod() {
    local moddir m f
    moddir=/usr/lib/uml/modules/$(uname -r)
    [[ -d $moddir ]] || return 1
    command -v insmod >/dev/null 2>&1 || return 1
    for m in can can-raw can-bcm can-dev vcan; do
        module_loaded "$m" && continue
        f=$(find "$moddir/kernel" -name "$m.ko*" -print -quit)
        [[ -n $f ]] || continue
        insmod "$f" 2>/dev/null || true
    done
    module_loaded vcan
}

load_modules() {
    # Required: vcan (its dependency can-dev comes along). Wanted: the CAN protocols, and a few
    # qdiscs so tests can shape a vcan's transmit queue with tc. Missing optional ones are fine.
    local optional=(can can_raw can_bcm can_gw vxcan sch_tbf sch_prio sch_netem sch_htb)
    if command -v modprobe >/dev/null 2>&1 && modprobe -q vcan 2>/dev/null; then
        modprobe -q -a "${optional[@]}" 2>/dev/null || true
        return 0
    elif command -v modprobe >/dev/null 2>&1 && uml_modprobe -q vcan; then
        uml_modprobe -q -a "${optional[@]}" || true
        return 0
    else
        uml_insmod || true
    fi
}

need_root_hint() {
    if [[ $(id -u) -ne 0 ]]; then
        echo " Creating network interfaces needs root (or CAP_NET_ADMIN); try sudo, or run the tests through run-in-vcan.sh, which boots a User-Mode-Linux guest."
    fi
}

module_loaded vcan || load_modules

# One 'ip -batch' for all interfaces: each process start is slow inside User-Mode-Linux.
batch=
for ((i = 0; i < n; i++)); do
    dev=vcan$i
    [[ -e /sys/class/net/$dev ]] || batch+="link add dev $dev type vcan"$'\n'
    iface_up "$dev" || batch+="link set dev $dev up"$'\n'
done
if [[ -n $batch ]] && ! err=$(printf '%s' "$batch" | ip -batch - 2>&1); then
    all_up && exit 0 # somebody else created them meanwhile
    err=$(printf '%s' "$err" | grep -v '^Command failed' | head -n 1)
    err=${err:-ip failed}
    if [[ ! -e /sys/class/net/vcan0 ]]; then
        die "cannot create vcan0: ${err%.}. This kernel has no usable vcan driver (modprobe vcan failed or is not permitted).$(need_root_hint)"
    fi
    die "cannot create or bring up vcan0..vcan$((n - 1)): ${err%.}.$(need_root_hint)"
fi
all_up || die "vcan0..vcan$((n - 1)) are not all up after setup.$(need_root_hint)"
exit 0
