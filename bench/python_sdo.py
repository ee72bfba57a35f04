#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""SDO expedited round trips from Python, next to the C++ blocking client and a raw-socket floor.

Usage (vcan0..vcan3 must exist, e.g. through the User-Mode-Linux guest):
    bash vcan-scripts/run-in-vcan.sh /usr/bin/python3 bench/python_sdo.py --build build-bench

The servers, the C++ client and the floor run in bench_python_sdo_peer (a C++ program this
script starts); Python's client runs here. Every figure has a vcan interface of its own, so no
socket ever queues another figure's frames:
    vcan0  floor: write() + blocking read() on raw sockets against a raw echo server
    vcan1  C++: sdo::BlockingSdo (what `codrive sdo` and this module use), its own process
    vcan2  Python: codrive.Bus("vcan2").sdo(100).read(0x1018, 0, "u32")
    vcan3  python-canopen's node.sdo.upload(0x1018, 0), only if `import canopen` works
All against the same codrive SDO server code (one process per interface). The figures are taken
in interleaved slices (floor, C++, Python, [python-canopen], floor, ...) so a load change hits
them alike; each ratio is the median of the per-round ratios, printed with the rounds' extremes.

Exit status: 0 when every floor held and Python reached 0.8x the C++ client; 1 when a figure beat
its floor by more than 5 % (the floor is then wrong), Python fell below 0.8x the C++ client, or a
transfer failed; 2 when the bench could not start.
"""
import argparse
import os
import statistics
import subprocess
import sys
import time

FLOOR_TOLERANCE = 1.05  # the same rule as bench/floor_check.hpp
PYTHON_TARGET = 0.8  # Python's round trips / the C++ client's (issue 18)
NODE = 100
CLOCK_EVERY = 64  # round trips between clock reads, as in the C++ loops


def spread(values, digits=2):
    v = sorted(values)
    return (f"{statistics.median(v):.{digits}f} (min {v[0]:.{digits}f}, max {v[-1]:.{digits}f}, "
            f"{len(v)} rounds)")


def python_round_trips(read, seconds):
    """Round trips per second of read() for `seconds`, the clock read every CLOCK_EVERY calls."""
    done = 0
    t0 = time.perf_counter()
    while time.perf_counter() - t0 < seconds:
        for _ in range(CLOCK_EVERY):
            read()
        done += CLOCK_EVERY
    return done / (time.perf_counter() - t0)


class Peer:
    """bench_python_sdo_peer: servers, the C++ client and the floor, figures on request."""

    def __init__(self, exe, floor_if, cpp_if, server_ifs):
        self.proc = subprocess.Popen([exe, floor_if, cpp_if, *server_ifs], stdin=subprocess.PIPE,
                                     stdout=subprocess.PIPE, text=True)
        line = self.proc.stdout.readline()
        if not line.startswith("ready"):
            self.proc.wait()
            raise RuntimeError(f"{exe} did not start its servers (exit {self.proc.returncode})")

    def figure(self, what, seconds):
        self.proc.stdin.write(f"{what} {seconds}\n")
        self.proc.stdin.flush()
        return float(self.proc.stdout.readline())

    def close(self):
        self.proc.stdin.close()
        self.proc.wait(timeout=10)


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default=os.path.join(here, "..", "build-bench"),
                    help="the build directory (Release, CODRIVE_BUILD_BENCH=ON)")
    ap.add_argument("--seconds", type=float, default=6.0, help="total seconds per figure")
    ap.add_argument("--slice", type=float, default=0.25, help="seconds per interleaved slice")
    ap.add_argument("--ifaces", nargs=4, default=["vcan0", "vcan1", "vcan2", "vcan3"],
                    metavar=("FLOOR", "CPP", "PYTHON", "CANOPEN"))
    args = ap.parse_args()
    build = os.path.abspath(args.build)
    sys.path.insert(0, os.path.join(build, "python"))
    try:
        import codrive
    except ImportError as e:
        print(f"python_sdo: cannot import codrive from {build}/python: {e}", file=sys.stderr)
        return 2
    try:
        import canopen  # optional: a comparison, not a floor
    except ImportError:
        canopen = None
    floor_if, cpp_if, py_if, co_if = args.ifaces
    peer_exe = os.path.join(build, "bench", "bench_python_sdo_peer")
    servers = [py_if] + ([co_if] if canopen else [])
    try:
        peer = Peer(peer_exe, floor_if, cpp_if, servers)
    except (OSError, RuntimeError) as e:
        print(f"python_sdo: {e}", file=sys.stderr)
        return 2

    bus = codrive.Bus(py_if)
    sdo = bus.sdo(NODE)
    py_read = lambda: sdo.read(0x1018, 0, "u32")  # noqa: E731
    co_read = None
    if canopen:
        network = canopen.Network()
        network.connect(interface="socketcan", channel=co_if)
        node = network.add_node(NODE, canopen.ObjectDictionary())
        co_read = lambda: node.sdo.upload(0x1018, 0)  # noqa: E731

    print(f"SDO expedited round trips, codrive {codrive.__version__}, "
          f"{args.slice} s slices for {args.seconds} s per figure")
    rows = {"floor": [], "cpp": [], "python": [], "canopen": []}
    rounds = max(1, round(args.seconds / args.slice))
    try:
        for _ in range(rounds):
            rows["floor"].append(peer.figure("floor", args.slice))
            rows["cpp"].append(peer.figure("cpp", args.slice))
            rows["python"].append(python_round_trips(py_read, args.slice))
            if co_read:
                rows["canopen"].append(python_round_trips(co_read, args.slice))
    except codrive.Error as e:
        print(f"python_sdo: a Python transfer failed: {e}", file=sys.stderr)
        return 1
    finally:
        peer.close()
        if canopen:
            network.disconnect()
    if min(rows["floor"] + rows["cpp"]) <= 0:
        print("python_sdo: a C++ transfer failed (see above)", file=sys.stderr)
        return 1

    def ratios(a, b):
        return [x / y for x, y in zip(rows[a], rows[b])]

    ok = True
    print(f"  {'floor: raw request/response (' + floor_if + ')':<44} "
          f"{spread(rows['floor'], 0)} round trips/s")
    for key, name in (("cpp", f"C++ blocking client ({cpp_if})"),
                      ("python", f"Python codrive.Bus ({py_if})")):
        r = ratios(key, "floor")
        print(f"  {name:<44} {statistics.median(rows[key]):8.0f} round trips/s, "
              f"ratio to floor {spread(r)}")
        if statistics.median(r) > FLOOR_TOLERANCE:
            print(f"python_sdo: {name} beats the floor by more than "
                  f"{FLOOR_TOLERANCE - 1:.0%}: the floor is wrong")
            ok = False
    py_cpp = ratios("python", "cpp")
    print(f"  Python / C++ client: {spread(py_cpp)}, target >= {PYTHON_TARGET}")
    if statistics.median(py_cpp) < PYTHON_TARGET:
        print(f"python_sdo: Python reaches {statistics.median(py_cpp):.2f}x the C++ client, "
              f"below the {PYTHON_TARGET}x target")
        ok = False
    if co_read:
        print(f"  {'python-canopen (' + co_if + ')':<44} "
              f"{statistics.median(rows['canopen']):8.0f} round trips/s, ratio to floor "
              f"{spread(ratios('canopen', 'floor'))}")
        print(f"  codrive Python / python-canopen: {spread(ratios('python', 'canopen'))} "
              "(a comparison, not a floor)")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
