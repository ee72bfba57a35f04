# SPDX-License-Identifier: Apache-2.0
"""Ctrl-C in a Python script waiting on an SDO transfer over real SocketCAN: KeyboardInterrupt
at once, and the node is sent SDO abort 0x08000000 (run inside the vcan guest)."""
import os
import signal
import socket
import struct
import subprocess
import sys
import time

import codrive

NODE = 90  # no other vcan test uses it

SCRIPT = """
import sys, time
import codrive
bus = codrive.Bus("vcan0")
print("reading", flush=True)
t0 = time.monotonic()
try:
    bus.sdo({node}).read(0x2001, 0, mode="segmented", timeout=5.0)
except KeyboardInterrupt:
    print("KeyboardInterrupt after %.3f s" % (time.monotonic() - t0), flush=True)
    sys.exit(7)
print("the read ended without the interrupt", flush=True)
"""


def requests_socket():
    """A raw CAN socket that sees the master's requests to NODE (600h + node)."""
    s = socket.socket(socket.AF_CAN, socket.SOCK_RAW, socket.CAN_RAW)
    s.setsockopt(socket.SOL_CAN_RAW, socket.CAN_RAW_FILTER,
                 struct.pack("=II", 0x600 + NODE, 0x7FF))
    s.bind(("vcan0",))
    s.settimeout(0.05)
    return s


def frames(s, at_most=1000):
    """Up to `at_most` frames waiting on `s` (until 50 ms pass without one): their data bytes."""
    out = []
    while len(out) < at_most:
        try:
            raw = s.recv(16)
        except socket.timeout:
            break
        _, length = struct.unpack("=IB3x", raw[:8])
        out.append(raw[8:8 + length])
    return out


def test_ctrl_c_raises_keyboard_interrupt_and_aborts_the_transfer_on_the_node(build_dir):
    server = subprocess.Popen([str(build_dir / "tools/codrive"), "sdo", "serve", "-i", "vcan0",
                               "-n", str(NODE)], stdout=subprocess.PIPE, text=True)
    try:
        assert "ready" in server.stdout.readline()
        # 1 MiB in the server's domain: a segmented upload of it takes 150,000 round trips.
        t0 = time.monotonic()
        codrive.Bus("vcan0").sdo(NODE).write(0x2001, 0, bytes(range(256)) * 4096, mode="block")
        print(f"1 MiB block download: {time.monotonic() - t0:.2f} s")
        watch = requests_socket()
        # The child imports the same codrive as this test.
        env = dict(os.environ,
                   PYTHONPATH=os.path.dirname(os.path.dirname(os.path.abspath(codrive.__file__))))
        child = subprocess.Popen([sys.executable, "-c", SCRIPT.format(node=NODE)], env=env,
                                 stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        assert child.stdout.readline().strip() == "reading"
        # Under way: a hundred segment requests went to the node.
        seen = []
        deadline = time.monotonic() + 20
        while len(seen) < 100 and time.monotonic() < deadline:
            seen += frames(watch)
        assert len(seen) >= 100, f"only {len(seen)} requests"
        assert not any(f[0] == 0x80 for f in seen)
        t_signal = time.monotonic()
        child.send_signal(signal.SIGINT)
        out, err = child.communicate(timeout=5)
        took = time.monotonic() - t_signal
        assert child.returncode == 7, (out, err)
        assert "KeyboardInterrupt after" in out
        assert took < 1.5, f"{took:.2f} s from SIGINT to exit"
        print(f"{took:.3f} s from SIGINT to exit; {out.strip()}")
        after = frames(watch, at_most=10**6)
        aborts = [f for f in after if f[0] == 0x80]
        assert len(aborts) == 1, after[-3:]
        # Abort of 2001h:00 with 0x08000000 (general error, CiA 301).
        assert aborts[0] == bytes([0x80, 0x01, 0x20, 0x00, 0x00, 0x00, 0x00, 0x08])
        assert after[-1] == aborts[0]  # nothing after the abort
        # The server is idle again: the next request is answered.
        assert codrive.Bus("vcan0").sdo(NODE).read(0x1008, 0, "str") == "codrive sdo serve"
    finally:
        server.send_signal(signal.SIGTERM)
        server.wait(timeout=5)
