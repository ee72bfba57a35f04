# SPDX-License-Identifier: Apache-2.0
"""Simulated drives: in-process on a VirtualNetwork (VirtualDrive), or codrive-sim processes on a
real CAN interface (can())."""
import os
import shutil
import signal
import subprocess
import threading
import time
from typing import Dict, List, Mapping, Optional, Sequence

from ._native import Bus, Error
from ._native import sim as _sim

VirtualDrive = _sim.VirtualDrive


def _find_codrive_sim(executable: Optional[str]) -> str:
    candidates = [executable, os.environ.get("CODRIVE_SIM"), shutil.which("codrive-sim"),
                  # A build tree: build/python/codrive/ next to build/tools/codrive-sim.
                  os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools",
                               "codrive-sim")]
    for c in candidates:
        if c and os.access(c, os.X_OK):
            return os.path.normpath(c)
    raise Error("codrive-sim not found: give executable=, set CODRIVE_SIM or put it on PATH")


class CanSimulation:
    """A running ``codrive-sim`` process; made by :func:`can`, used as a context manager."""

    def __init__(self, interface: str, nodes: Mapping[int, str], heartbeat_ms: int = 0,
                 faults: Sequence[str] = (), executable: Optional[str] = None,
                 timeout: float = 10.0, extra_args: Sequence[str] = ()):
        self.interface = interface
        self.nodes: Dict[int, str] = dict(nodes)
        if not self.nodes:
            raise ValueError("codrive.sim.can: give at least one node, e.g. {1: 'akd2g'}")
        argv = [_find_codrive_sim(executable), "-i", interface]
        for node, profile in sorted(self.nodes.items()):
            argv += ["--node", f"{int(node)}:{profile}"]
        if heartbeat_ms:
            argv += ["--heartbeat", str(int(heartbeat_ms))]
        for f in faults:
            argv += ["--fault", f]
        argv += list(extra_args)
        self.argv = argv
        self._timeout = timeout
        self._lines: List[str] = []
        self._cond = threading.Condition()
        self._bus: Optional[Bus] = None
        self._proc: Optional[subprocess.Popen] = None
        self.returncode: Optional[int] = None

    @property
    def output(self) -> List[str]:
        """What codrive-sim printed so far (stdout and stderr, one string per line)."""
        with self._cond:
            return list(self._lines)

    def start(self) -> "CanSimulation":
        """Starts the process and waits until every node reported ``ready``."""
        self._proc = subprocess.Popen(self.argv, stdin=subprocess.DEVNULL,
                                      stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                      text=True, bufsize=1)
        threading.Thread(target=self._drain, daemon=True).start()
        want = {f"node {n} " for n in self.nodes}
        deadline = time.monotonic() + self._timeout
        with self._cond:
            while True:
                ready = {w for w in want for line in self._lines
                         if line.startswith("codrive-sim: " + w) and
                         line.endswith(f"ready on {self.interface}")}
                if ready == want:
                    return self
                left = deadline - time.monotonic()
                if self._proc.poll() is not None or left <= 0:
                    break
                self._cond.wait(min(left, 0.1))
        self.stop()
        raise Error(f"codrive-sim on {self.interface} did not get ready "
                    f"(exit status {self.returncode}): " + " | ".join(self._lines[-5:]))

    def _drain(self) -> None:
        assert self._proc is not None and self._proc.stdout is not None
        for line in self._proc.stdout:
            with self._cond:
                self._lines.append(line.rstrip("\n"))
                self._cond.notify_all()

    @property
    def bus(self) -> Bus:
        """A codrive.Bus on the simulation's interface (opened on first use)."""
        if self._bus is None:
            self._bus = Bus(self.interface)
        return self._bus

    def inject_fault(self, node: int, fault: str, axis: int = 1) -> None:
        """Injects `fault` ('sto', 'overcurrent', 'following-error', 'heartbeat', 'reset') on
        `axis` of `node` through the simulator's control object (SDO, docs/codrive-sim.md)."""
        self.bus.sdo(node).write(_sim.CONTROL_OBJECT + axis - 1, _sim.control_subindex(fault),
                                 1, "u8")

    def stop(self) -> int:
        """Stops the process (SIGTERM, then SIGKILL after 5 s); returns its exit status."""
        self._bus = None
        if self._proc is not None and self._proc.poll() is None:
            self._proc.send_signal(signal.SIGTERM)
            try:
                self._proc.wait(timeout=5)
            except subprocess.TimeoutExpired:
                self._proc.kill()
                self._proc.wait()
        if self._proc is not None:
            self.returncode = self._proc.returncode
        return self.returncode if self.returncode is not None else 0

    def __enter__(self) -> "CanSimulation":
        return self.start() if self._proc is None else self

    def __exit__(self, *exc) -> None:
        self.stop()


def can(interface: str, nodes: Mapping[int, str], heartbeat_ms: int = 0,
        faults: Sequence[str] = (), executable: Optional[str] = None,
        timeout: float = 10.0) -> CanSimulation:
    """Simulated drives on a CAN interface: ``with codrive.sim.can("vcan0", {1: "akd2g",
    2: "ds-bvs"}) as sim:`` runs ``codrive-sim -i vcan0 --node 1:akd2g --node 2:ds-bvs`` until
    the block ends. heartbeat_ms: producer heartbeat of every node; faults: ``--fault`` specs
    such as "1.2:sto@2s". The process is found as `executable`, $CODRIVE_SIM, on PATH or in the
    build tree."""
    return CanSimulation(interface, nodes, heartbeat_ms, faults, executable, timeout)


__all__ = ["CanSimulation", "VirtualDrive", "can"]
