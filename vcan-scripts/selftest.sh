#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Self-test of the vcan harness: exit status and arguments propagate; frames, error frames and tc shaping work on vcan.
set -euo pipefail

here=$(cd -- "$(dirname -- "${BASH_SOURCE[0]}")" && pwd -P)
failures=0

ok() { echo "selftest: [ok]   $*"; }
bad() { echo "selftest: [FAIL] $*"; failures=$((failures + 1)); }
skip() { echo "selftest: [skip] $*"; }

# Wait until a CAN_RAW receiver is registered on $2 in /proc/net/can/$1 (so no frame is sent
# before candump listens).
wait_rx() {
    local list=/proc/net/can/$1 dev=$2 i
    if [[ ! -r $list ]]; then
        sleep 1
        return 0
    fi
    for ((i = 0; i < 100; i++)); do
        grep -Eq "^ +$dev +[0-9A-Fa-f]" "$list" && return 0
        sleep 0.1
    done
    return 1
}

inner() {
    local tmp i pid rc out
    tmp=$(mktemp -d "${TMPDIR:-/tmp}/vcan-selftest.XXXXXX")
    trap 'rm -rf -- "$tmp"' RETURN

    local missing=()
    for ((i = 0; i < 4; i++)); do
        [[ -e /sys/class/net/vcan$i ]] || missing+=("vcan$i")
    done
    if ((${#missing[@]} == 0)); then
        ok "vcan0..vcan3 exist (CODRIVE_VCAN=${CODRIVE_VCAN:-unset}, kernel $(uname -r), $(nproc) CPU)"
    else
        bad "missing interfaces: ${missing[*]}"
    fi

    # 1. Three data frames from cansend reach candump.
    candump -n 3 vcan0 >"$tmp/data" 2>&1 &
    pid=$!
    wait_rx rcvlist_all vcan0 || bad "candump did not start listening on vcan0"
    for i in 1 2 3; do
        cansend vcan0 123#11223344
    done
    rc=0
    timeout 10 tail --pid="$pid" -f /dev/null || rc=$?
    kill "$pid" 2>/dev/null || true
    wait "$pid" 2>/dev/null || true
    out=$(grep -Ec 'vcan0 +123 +\[4\] +11 22 33 44' "$tmp/data" || true)
    if [[ $out == 3 && $rc == 0 ]]; then
        ok "candump saw the 3 frames cansend sent (123#11223344)"
    else
        bad "candump saw $out of 3 frames; its output:"
        sed 's/^/    /' "$tmp/data"
    fi

    # 2. An error frame (CAN_ERR_FLAG | CAN_ERR_BUSOFF = 0x20000040) written by a raw socket
    #    reaches a receiver that enabled CAN_RAW_ERR_FILTER (filter 0~0: no data frames).
    candump -e -n 1 vcan0,0~0,#FFFFFFFF >"$tmp/err" 2>&1 &
    pid=$!
    wait_rx rcvlist_err vcan0 || bad "candump -e did not start listening on vcan0"
    cansend vcan0 123#55 # data frame: must be filtered out
    cansend vcan0 20000040#0000000000000000
    rc=0
    timeout 10 tail --pid="$pid" -f /dev/null || rc=$?
    kill "$pid" 2>/dev/null || true
    wait "$pid" 2>/dev/null || true
    if [[ $rc == 0 ]] && grep -q ERRORFRAME "$tmp/err" && grep -q bus-off "$tmp/err"; then
        ok "candump -e saw the injected bus-off error frame (cansend vcan0 20000040#0000000000000000)"
    else
        bad "candump -e did not report the injected error frame; its output:"
        sed 's/^/    /' "$tmp/err"
    fi

    # 3. A token-bucket qdisc on a vcan makes a flooding sender get ENOBUFS.
    if ! command -v tc >/dev/null || ! command -v cangen >/dev/null; then
        skip "tc or cangen missing; tbf/ENOBUFS check not run"
    elif ! out=$(tc qdisc add dev vcan3 root tbf rate 100kbit burst 1600 limit 3000 2>&1); then
        bad "tc qdisc add dev vcan3 root tbf rate 100kbit burst 1600 limit 3000: $out"
    else
        out=$(timeout 10 cangen vcan3 -g 0 -I 123 -L 8 -D i -n 5000 2>&1 || true)
        if grep -q 'No buffer space available' <<<"$out"; then
            ok "tbf qdisc on vcan3 (rate 100kbit burst 1600 limit 3000): flooding cangen got ENOBUFS"
        else
            bad "flooding cangen through tbf did not get ENOBUFS: $out"
        fi
        tc qdisc del dev vcan3 root || bad "tc qdisc del dev vcan3 root failed"
    fi

    ((failures == 0))
}

if [[ ${1:-} == --inner ]]; then
    inner
    exit
fi

# Outer part: on the host. Options are passed to run-in-vcan.sh (e.g. --mode uml).
run=("$here/run-in-vcan.sh" "$@")

rc=0
"${run[@]}" sh -c 'exit 7' || rc=$?
if [[ $rc == 7 ]]; then ok "exit status propagates (sh -c 'exit 7' -> 7)"; else bad "sh -c 'exit 7' gave $rc, not 7"; fi

# shellcheck disable=SC2016 # a literal $HOME must come back unexpanded
out=$("${run[@]}" printf '<%s>' 'a b' "it's" 'say "hi"' '$HOME' '' </dev/null 2>&1) || true
expect="<a b><it's><say \"hi\"><\$HOME><>"
if [[ $out == "$expect" ]]; then ok "arguments and output with spaces and quotes propagate"; else bad "argument round trip: got '$out', want '$expect'"; fi

rc=0
"${run[@]}" "$here/selftest.sh" --inner </dev/null || rc=$?
((rc == 0)) || failures=$((failures + 1))

if ((failures == 0)); then
    echo "selftest: PASS"
    exit 0
fi
echo "selftest: FAIL"
exit 1
