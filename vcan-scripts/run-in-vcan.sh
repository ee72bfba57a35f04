#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Run a command where vcan0..vcanN-1 exist: natively if the kernel has vcan, else in a User-Mode-Linux guest.
set -euo pipefail

prog=run-in-vcan
here=$(cd -- "$(dirname -- "${BASH_SOURCE[0]}")" && pwd -P)

usage() {
    cat <<'USAGE'
usage: run-in-vcan.sh [options] [--] CMD [ARGS...]

Runs CMD where the interfaces vcan0..vcan{N-1} exist and are up, and exits with CMD's exit status.
Natively (kernel with vcan, root): creates the interfaces with vcan-up.sh and runs CMD directly.
Otherwise: boots a User-Mode-Linux guest whose root is the host filesystem, runs CMD there as
root in the same working directory with the same environment, and relays its stdout/stderr.

options:
  --ifaces N       number of vcan interfaces (default 4)
  --mem SIZE       guest memory, e.g. 512M, 1G (default 1G; UML only)
  --timeout SEC    kill the guest after SEC seconds (default 1200; natively only if given)
  --mode MODE      auto (default), native or uml  (env: CODRIVE_VCAN_MODE)
  --keep           keep the guest's work directory (console log, init trace)
  -v, --verbose    report the mode and the guest's boot time on stderr
  -h, --help       this text

CMD sees CODRIVE_VCAN=native or CODRIVE_VCAN=uml. In the guest CMD's stdin is /dev/null.
Environment: CODRIVE_VCAN_MODE, CODRIVE_VCAN_KEEP=1, CODRIVE_VCAN_VERBOSE=1 (as the options);
CODRIVE_UML (linux.uml binary), CODRIVE_UML_TMPDIR (where UML keeps its RAM file; default
/dev/shm if it has room, else /var/tmp), CODRIVE_VCAN_WORKDIR (parent of the work directory;
default $TMPDIR or /var/tmp).
Exit status: CMD's; 125 if the guest failed to report one (crash, timeout); 2 on usage errors or
when neither native vcan nor User-Mode-Linux is available.
USAGE
}

die2() {
    echo "$prog: $*" >&2
    exit 2
}

verbose=${CODRIVE_VCAN_VERBOSE:-0}
[[ $verbose == 1 || $verbose == true || $verbose == yes ]] && verbose=1 || verbose=0
note() { if ((verbose)); then echo "$prog: $*" >&2; fi; }

ifaces=4
mem=1G
timeout_s=
mode=${CODRIVE_VCAN_MODE:-auto}
keep=${CODRIVE_VCAN_KEEP:-0}
[[ $keep == 1 || $keep == true || $keep == yes ]] && keep=1 || keep=0

need_arg() { [[ $# -ge 2 ]] || die2 "option $1 needs a value (see --help)."; }

while [[ $# -gt 0 ]]; do
    case $1 in
        --ifaces) need_arg "$@"; ifaces=$2; shift 2 ;;
        --ifaces=*) ifaces=${1#*=}; shift ;;
        --mem) need_arg "$@"; mem=$2; shift 2 ;;
        --mem=*) mem=${1#*=}; shift ;;
        --timeout) need_arg "$@"; timeout_s=$2; shift 2 ;;
        --timeout=*) timeout_s=${1#*=}; shift ;;
        --mode) need_arg "$@"; mode=$2; shift 2 ;;
        --mode=*) mode=${1#*=}; shift ;;
        --keep) keep=1; shift ;;
        -v | --verbose) verbose=1; shift ;;
        -h | --help) usage; exit 0 ;;
        --) shift; break ;;
        -*) die2 "unknown option '$1' (see --help)." ;;
        *) break ;;
    esac
done
[[ $# -ge 1 ]] || { usage >&2; exit 2; }
cmd=("$@")

if ! [[ $ifaces =~ ^[0-9]+$ ]] || ((ifaces < 1 || ifaces > 64)); then
    die2 "--ifaces must be 1..64, got '$ifaces'."
fi
[[ $mem =~ ^([0-9]+)([KkMmGg]?)$ ]] || die2 "--mem must look like 512M or 1G, got '$mem'."
case ${BASH_REMATCH[2]} in
    K | k) mem_kib=${BASH_REMATCH[1]} ;;
    M | m) mem_kib=$((BASH_REMATCH[1] * 1024)) ;;
    G | g) mem_kib=$((BASH_REMATCH[1] * 1024 * 1024)) ;;
    *) mem_kib=$((BASH_REMATCH[1] / 1024)) ;;
esac
((mem_kib >= 64 * 1024)) || die2 "--mem must be at least 64M, got '$mem'."
if [[ -n $timeout_s ]]; then
    if ! [[ $timeout_s =~ ^[0-9]+$ ]] || ((timeout_s < 1)); then
        die2 "--timeout must be a positive number of seconds, got '$timeout_s'."
    fi
fi
case $mode in auto | native | uml) ;; *) die2 "--mode must be auto, native or uml, got '$mode'." ;; esac

# ---------------------------------------------------------------------------------------------
# Native: the running kernel has vcan (an ordinary Linux machine, or already inside the guest).
# ---------------------------------------------------------------------------------------------
run_native() {
    export CODRIVE_VCAN=native
    command -v -- "${cmd[0]}" >/dev/null || { echo "$prog: ${cmd[0]}: command not found" >&2; exit 127; }
    note "vcan available natively; running CMD directly."
    if [[ -n $timeout_s ]]; then
        exec timeout -k 10 "$timeout_s" "${cmd[@]}"
    fi
    exec "${cmd[@]}"
}

native_err=
if [[ $mode != uml ]]; then
    if native_err=$("$here/vcan-up.sh" "$ifaces" 2>&1); then
        run_native
    fi
    native_err=${native_err#vcan-up: }
    if [[ $mode == native ]]; then
        die2 "native vcan requested but unavailable: ${native_err:-vcan-up.sh failed}"
    fi
fi

# ---------------------------------------------------------------------------------------------
# User-Mode-Linux guest.
# ---------------------------------------------------------------------------------------------
syspath="$PATH:/usr/local/sbin:/usr/sbin:/sbin"
find_tool() { PATH=$syspath command -v "$1" 2>/dev/null || true; }

uml_bin=${CODRIVE_UML:-$(find_tool linux.uml)}
modprobe_bin=$(find_tool modprobe)
missing=()
[[ -n $uml_bin && -x $uml_bin ]] || missing+=("linux.uml (package user-mode-linux)")
compgen -G '/usr/lib/uml/modules/*/kernel/drivers/net/can/vcan.ko*' >/dev/null ||
    missing+=("the UML vcan module /usr/lib/uml/modules/<version>/kernel/drivers/net/can/vcan.ko (package user-mode-linux)")
[[ -n $modprobe_bin ]] || missing+=("modprobe (package kmod)")
[[ -n $(find_tool ip) ]] || missing+=("ip (package iproute2)")
[[ -n $(find_tool timeout) ]] || missing+=("timeout (package coreutils)")
if ((${#missing[@]})); then
    {
        printf '%s: no vcan in this kernel' "$prog"
        [[ -n $native_err ]] && printf ' (%s)' "$native_err"
        printf ' and no usable User-Mode-Linux; missing: '
        (IFS=';'; printf '%s' "${missing[*]}" | sed 's/;/, /g')
        printf '.\nInstall them with: apt-get install user-mode-linux kmod iproute2\n'
    } >&2
    exit 2
fi

# Paths the guest does not share with the host: it mounts its own /proc, /sys and /dev.
shadowed() { [[ $1 == /proc || $1 == /proc/* || $1 == /sys || $1 == /sys/* || $1 == /dev || $1 == /dev/* ]]; }

cwd=$(pwd -P)
shadowed "$cwd" && die2 "the working directory $cwd is not visible inside the UML guest (it has its own /dev, /proc, /sys); cd elsewhere."
shadowed "$here" && die2 "the scripts in $here are not visible inside the UML guest; copy them elsewhere."

# Work directory on the host filesystem, shared with the guest through hostfs.
base=${CODRIVE_VCAN_WORKDIR:-${TMPDIR:-/var/tmp}}
{ [[ -d $base && -w $base ]] && ! shadowed "$(cd "$base" && pwd -P)"; } || base=/var/tmp
[[ -d $base && -w $base ]] || base=/tmp
work=$(mktemp -d "$base/run-in-vcan.XXXXXX") || die2 "cannot create a work directory under $base."
work=$(cd "$work" && pwd -P)

# UML keeps its RAM in a file in TMPDIR (default /dev/shm). A too-small tmpfs there (e.g. Docker's
# 64 MiB /dev/shm) makes the guest die with SIGBUS, so pick a place with room for all of it.
avail_kib() { df -Pk -- "$1" 2>/dev/null | awk 'NR == 2 { print $4 }'; }
uml_tmp=${CODRIVE_UML_TMPDIR:-}
if [[ -z $uml_tmp ]]; then
    for d in /dev/shm /var/tmp "$work"; do
        a=$(avail_kib "$d")
        if [[ -d $d && -w $d && -n $a ]] && ((a > mem_kib + 64 * 1024)); then
            uml_tmp=$d
            break
        fi
    done
    [[ -n $uml_tmp ]] || { uml_tmp=$work; echo "$prog: warning: less than $mem free in /dev/shm and /var/tmp; the guest may crash (lower --mem or set CODRIVE_UML_TMPDIR)." >&2; }
fi

guest_pid=
# shellcheck disable=SC2317 # invoked by the EXIT trap
cleanup() {
    local rc=$?
    if [[ -n $guest_pid ]] && kill -0 "$guest_pid" 2>/dev/null; then
        kill -TERM "$guest_pid" 2>/dev/null || true
        wait "$guest_pid" 2>/dev/null || true
    fi
    if ((keep)); then
        rm -f -- "$work/env.sh" # the caller's environment may hold secrets
        echo "$prog: guest work directory kept: $work" >&2
    else
        rm -rf -- "$work"
    fi
    return "$rc"
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM
trap 'exit 129' HUP

# Are our stdout and stderr the same file (terminal, one log, 2>&1 pipe)? Then let the guest write
# both into one file so their interleaving is kept.
fd_id() { stat -L -c '%d:%i' "/proc/$$/fd/$1" 2>/dev/null || echo "fd$1"; }
merged=0
[[ $(fd_id 1) == "$(fd_id 2)" ]] && merged=1
out=$work/stdout
err=$work/stderr
((merged)) && err=$out
: >"$out"
: >"$err"

# The caller's environment, minus what belongs to this shell or must not be copied.
{
    while IFS= read -r name; do
        case $name in
            PWD | OLDPWD | SHLVL | _ | SHELLOPTS | BASHOPTS | UID | EUID | PPID | GROUPS | \
                LINES | COLUMNS | CODRIVE_VCAN | TMOUT) continue ;;
        esac
        [[ -v $name ]] || continue
        printf 'export %s=%q\n' "$name" "${!name}"
    done < <(compgen -e)
    echo 'export CODRIVE_VCAN=uml'
} >"$work/env.sh"

# The command, as a bash array, so arguments survive unchanged.
{
    printf 'CMD=('
    printf ' %q' "${cmd[@]}"
    printf ' )\n'
} >"$work/cmd.sh"

# Kernel module autoloading in the guest (tc qdiscs, CAN protocols): point modprobe at the UML
# modules, which live in /usr/lib/uml/modules/<release> instead of /lib/modules/<release>.
mkdir -p "$work/modroot/lib/modules" "$work/uml"
cat >"$work/modprobe" <<EOF
#!/bin/sh
exec $(printf %q "$modprobe_bin") -d $(printf %q "$work/modroot") "\$@"
EOF
chmod +x "$work/modprobe"

# The guest's init (PID 1).
cat >"$work/init" <<EOF
#!/bin/bash
# Generated by run-in-vcan.sh: PID 1 of the User-Mode-Linux guest.
W=$(printf %q "$work")
OUT=$(printf %q "$out")
ERR=$(printf %q "$err")
SCRIPTS=$(printf %q "$here")
CWD=$(printf %q "$cwd")
IFACES=$ifaces
MERGED=$merged
EOF
cat >>"$work/init" <<'EOF'
export PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin
export HOME=/root
exec </dev/null >>"$W/init.log" 2>&1
date +%s.%N >"$W/t_init"
PS4='+ ${EPOCHREALTIME} '
set -x

finish() {
    echo "$1" >"$W/status.tmp" && mv -f "$W/status.tmp" "$W/status"
    sync
    halt -f
    poweroff -f
    echo o >/proc/sysrq-trigger
    sleep 10
}

mount -t proc proc /proc
mount -t sysfs sysfs /sys
[ -c /dev/null ] || mount -t devtmpfs devtmpfs /dev
mkdir -p /dev/shm /dev/pts
mount -t tmpfs -o mode=1777,nosuid,nodev tmpfs /dev/shm
mount -t devpts -o gid=5,mode=620,ptmxmode=666 devpts /dev/pts
[ -e /dev/fd ] || ln -s /proc/self/fd /dev/fd
[ -e /dev/stdin ] || ln -s /proc/self/fd/0 /dev/stdin
[ -e /dev/stdout ] || ln -s /proc/self/fd/1 /dev/stdout
[ -e /dev/stderr ] || ln -s /proc/self/fd/2 /dev/stderr
hostname codrive-uml || true
ip link set lo up

# Let the kernel (tc, socket()) load modules from the UML module tree, and load the ones tests
# use up front (one modprobe: every process start costs tens of ms in the guest).
ln -s "/usr/lib/uml/modules/$(uname -r)" "$W/modroot/lib/modules/$(uname -r)"
echo "$W/modprobe" >/proc/sys/kernel/modprobe
"$W/modprobe" -q -a vcan can can_raw can_bcm can_gw vxcan sch_tbf sch_prio sch_netem sch_htb || true

if [ "$MERGED" = 1 ]; then
    "$SCRIPTS/vcan-up.sh" "$IFACES" >>"$OUT" 2>&1
else
    "$SCRIPTS/vcan-up.sh" "$IFACES" >>"$OUT" 2>>"$ERR"
fi || {
    echo "run-in-vcan: setting up vcan0..vcan$((IFACES - 1)) in the UML guest failed." >>"$ERR"
    finish 125
}

check_cmd() {
    command -v -- "${CMD[0]}" >/dev/null && return 0
    echo "run-in-vcan: ${CMD[0]}: command not found" >&2
    exit 127
}

cd -- "$CWD" || { echo "run-in-vcan: cannot cd to $CWD in the UML guest." >>"$ERR"; finish 125; }
date +%s.%N >"$W/t_cmd"
set +x
if [ "$MERGED" = 1 ]; then
    (source "$W/env.sh" && source "$W/cmd.sh" && check_cmd && exec "${CMD[@]}") </dev/null >>"$OUT" 2>&1
else
    (source "$W/env.sh" && source "$W/cmd.sh" && check_cmd && exec "${CMD[@]}") </dev/null >>"$OUT" 2>>"$ERR"
fi
status=$?
PS4='+ ${EPOCHREALTIME} '
set -x
date +%s.%N >"$W/t_end"
finish "$status"
EOF
chmod +x "$work/init"

# Debian 12's UML (kernel 6.1) keeps 2696 bytes of FPU state per guest thread; on a host whose
# XSAVE area is larger (AMX: 11008 bytes) every restore fails and the guest's init dies at once.
# The preloaded shim completes those requests to the host's size (see uml-xstate-shim.c); where
# UML already fits it passes everything through.
preload=()
cc_bin=$(find_tool cc)
[[ -n $cc_bin ]] || cc_bin=$(find_tool gcc)
if [[ -n $cc_bin ]] &&
    "$cc_bin" -std=c11 -O2 -shared -fPIC -o "$work/uml-xstate-shim.so" "$here/uml-xstate-shim.c" -ldl \
        >"$work/shim-build.log" 2>&1; then
    preload=(env "LD_PRELOAD=$work/uml-xstate-shim.so")
else
    echo "$prog: warning: could not build $here/uml-xstate-shim.c with ${cc_bin:-a C compiler (none found; package gcc)}; on a host CPU with AMX the guest will die at start." >&2
    if [[ -s $work/shim-build.log ]]; then sed -n '1,5s/^/  | /p' "$work/shim-build.log" >&2; fi
fi

tmo=${timeout_s:-1200}
note "no native vcan (${native_err:-mode=uml}); booting User-Mode-Linux ($uml_bin, mem=$mem, RAM file in $uml_tmp, timeout ${tmo}s)."

t_start=$(date +%s.%N)
# con0=null,fd:1: console output to the log, no input; everything works with no terminal.
TMPDIR=$uml_tmp timeout -k 10 "$tmo" "${preload[@]}" "$uml_bin" \
    mem="$mem" rootfstype=hostfs rw init="$work/init" uml_dir="$work/uml" \
    con=null con0=null,fd:1 ssl=null </dev/null >"$work/console.log" 2>&1 &
guest_pid=$!

# Relay the guest's output live; tail exits after the guest process is gone and the file drained.
tail -q -n +1 -s 0.2 -f --pid="$guest_pid" -- "$out" 2>/dev/null &
tail_out=$!
tail_err=
if ((!merged)); then
    tail -q -n +1 -s 0.2 -f --pid="$guest_pid" -- "$err" >&2 2>/dev/null &
    tail_err=$!
fi

uml_rc=0
wait "$guest_pid" 2>/dev/null || uml_rc=$?
# timeout(1) leads its own process group; end guest processes a crashed kernel left behind.
kill -KILL -- "-$guest_pid" 2>/dev/null || true
guest_pid=
wait "$tail_out" || true
[[ -z $tail_err ]] || wait "$tail_err" || true
t_stop=$(date +%s.%N)

if [[ -f $work/t_init ]]; then
    note "$(awk -v a="$t_start" -v b="$(<"$work/t_init")" -v c="$t_stop" \
        'BEGIN { printf "guest booted in %.2f s; total %.2f s", b - a, c - a }')"
fi

status=
[[ -f $work/status ]] && status=$(<"$work/status")
if [[ $status =~ ^[0-9]+$ ]]; then
    exit "$status"
fi

keep=1
{
    if ((uml_rc == 124 || uml_rc == 137)); then
        echo "$prog: the User-Mode-Linux guest timed out after ${tmo}s and was killed; CMD reported no exit status."
    else
        echo "$prog: the User-Mode-Linux guest ended (linux.uml exit code $uml_rc) without reporting CMD's exit status (crash or early halt)."
    fi
    echo "$prog: last lines of the guest console:"
    tail -n 25 "$work/console.log" 2>/dev/null | sed 's/^/  | /'
    if [[ -s $work/init.log ]]; then
        echo "$prog: last lines of the guest init trace:"
        tail -n 10 "$work/init.log" | sed 's/^/  | /'
    fi
} >&2
exit 125
