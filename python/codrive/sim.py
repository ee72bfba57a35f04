# SPDX-License-Identifier: Apache-2.0
"""Simulated drives: in-process on a VirtualNetwork (VirtualDrive), codrive-sim processes on a
real CAN interface (can()), or codrive-ecat-sim on an Ethernet interface (ethercat(), with veth()
for a pair of virtual Ethernet ends)."""
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


def _find_tool(name: str, env: str, executable: Optional[str]) -> str:
    candidates = [executable, os.environ.get(env), shutil.which(name),
                  # A build tree: build/python/codrive/ next to build/tools/<name>.
                  os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools",
                               name)]
    for c in candidates:
        if c and os.access(c, os.X_OK):
            return os.path.normpath(c)
    raise Error(f"{name} not found: give executable=, set {env} or put it on PATH")


def _find_codrive_sim(executable: Optional[str]) -> str:
    return _find_tool("codrive-sim", "CODRIVE_SIM", executable)


class _Process:
    """A child process whose output lines are collected by a thread."""

    def __init__(self, argv: Sequence[str]):
        self.argv = list(argv)
        self.lines: List[str] = []
        self.cond = threading.Condition()
        self.proc = subprocess.Popen(self.argv, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                                     stderr=subprocess.STDOUT, text=True, bufsize=1)
        threading.Thread(target=self._drain, daemon=True).start()

    def _drain(self) -> None:
        assert self.proc.stdout is not None
        for line in self.proc.stdout:
            with self.cond:
                self.lines.append(line.rstrip("\n"))
                self.cond.notify_all()

    def output(self) -> List[str]:
        with self.cond:
            return list(self.lines)

    def wait_for(self, ready, timeout: float) -> bool:
        """Waits until ready(lines) is true; False if the process ended or time ran out."""
        deadline = time.monotonic() + timeout
        with self.cond:
            while not ready(self.lines):
                left = deadline - time.monotonic()
                if self.proc.poll() is not None or left <= 0:
                    return False
                self.cond.wait(min(left, 0.1))
            return True

    def stop(self) -> int:
        """SIGTERM, then SIGKILL after 5 s; the exit status."""
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
            try:
                self.proc.wait(timeout=5)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        return self.proc.returncode


class _Simulation:
    """A simulator process for a ``with`` block: started by start(), which waits for its ready
    line(s), stopped by stop(); what it printed is in `output`."""

    _program = ""

    def __init__(self, interface: str, argv: List[str], timeout: float):
        self.interface = interface
        self.argv = argv
        self._timeout = timeout
        self._proc: Optional[_Process] = None
        self.returncode: Optional[int] = None

    @property
    def output(self) -> List[str]:
        """What the simulator printed so far (stdout and stderr, one string per line)."""
        return self._proc.output() if self._proc is not None else []

    def _ready(self, lines: List[str]) -> bool:
        raise NotImplementedError

    def start(self):
        """Starts the process and waits until it reported ``ready``."""
        self._proc = _Process(self.argv)
        if self._proc.wait_for(self._ready, self._timeout):
            return self
        self.stop()
        raise Error(f"{self._program} on {self.interface} did not get ready "
                    f"(exit status {self.returncode}): " + " | ".join(self.output[-5:]))

    def stop(self) -> int:
        """Stops the process (SIGTERM, then SIGKILL after 5 s); returns its exit status."""
        if self._proc is not None:
            self.returncode = self._proc.stop()
        return self.returncode if self.returncode is not None else 0

    def __enter__(self):
        return self.start() if self._proc is None else self

    def __exit__(self, *exc) -> None:
        self.stop()


class CanSimulation(_Simulation):
    """A running ``codrive-sim`` process; made by :func:`can`, used as a context manager."""

    def __init__(self, interface: str, nodes: Mapping[int, str], heartbeat_ms: int = 0,
                 faults: Sequence[str] = (), executable: Optional[str] = None,
                 timeout: float = 10.0, extra_args: Sequence[str] = ()):
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
        super().__init__(interface, argv, timeout)
        self._bus: Optional[Bus] = None

    _program = "codrive-sim"

    def _ready(self, lines: List[str]) -> bool:
        want = {f"codrive-sim: node {n} " for n in self.nodes}
        tail = f"ready on {self.interface}"
        return want == {w for w in want for line in lines
                        if line.startswith(w) and line.endswith(tail)}

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
        return super().stop()


def can(interface: str, nodes: Mapping[int, str], heartbeat_ms: int = 0,
        faults: Sequence[str] = (), executable: Optional[str] = None,
        timeout: float = 10.0) -> CanSimulation:
    """Simulated drives on a CAN interface: ``with codrive.sim.can("vcan0", {1: "akd2g",
    2: "ds-bvs"}) as sim:`` runs ``codrive-sim -i vcan0 --node 1:akd2g --node 2:ds-bvs`` until
    the block ends. heartbeat_ms: producer heartbeat of every node; faults: ``--fault`` specs
    such as "1.2:sto@2s". The process is found as `executable`, $CODRIVE_SIM, on PATH or in the
    build tree."""
    return CanSimulation(interface, nodes, heartbeat_ms, faults, executable, timeout)


class EthercatSimulation(_Simulation):
    """A running ``codrive-ecat-sim``; made by :func:`ethercat`, used as a context manager."""

    def __init__(self, interface: str, slaves: Sequence[str], netns: Optional[str] = None,
                 executable: Optional[str] = None, timeout: float = 10.0,
                 extra_args: Sequence[str] = ()):
        if isinstance(slaves, str):
            slaves = [slaves]
        self.slaves: List[str] = list(slaves)
        if not self.slaves:
            raise ValueError("codrive.sim.ethercat: give at least one slave, e.g. ['fio']")
        argv = [_find_tool("codrive-ecat-sim", "CODRIVE_ECAT_SIM", executable),
                "--ethercat", interface]
        for profile in self.slaves:
            argv += ["--slave", profile]
        argv += list(extra_args)
        # The slave end may live in a network namespace (veth()): run the simulator there.
        super().__init__(interface, (["ip", "netns", "exec", netns] if netns else []) + argv,
                         timeout)

    _program = "codrive-ecat-sim"

    def _ready(self, lines: List[str]) -> bool:
        return any(line.endswith(f"on {self.interface} ready") for line in lines)


def ethercat(interface: str, slaves: Sequence[str], netns: Optional[str] = None,
             executable: Optional[str] = None, timeout: float = 10.0,
             extra_args: Sequence[str] = ()) -> EthercatSimulation:
    """Simulated EtherCAT slaves on an Ethernet interface: ``with codrive.sim.ethercat("veth1",
    ["fio", "akd2g"]) as sim:`` runs ``codrive-ecat-sim --ethercat veth1 --slave fio --slave
    akd2g`` (slaves in chain order) until the block ends; `netns` runs it inside that network
    namespace (the slave end of :func:`veth`). extra_args: further options
    (docs/cli/codrive-ecat-sim.md), e.g. ``["--drop-frames", "10"]``. Needs root or
    CAP_NET_RAW. Found as `executable`, $CODRIVE_ECAT_SIM, on PATH or in the build tree."""
    return EthercatSimulation(interface, slaves, netns, executable, timeout, extra_args)


class VethPair:
    """A veth pair for an EtherCAT segment without hardware: `master` is the end the master
    opens (in this namespace), `slave` the end the simulator answers on, inside network
    namespace `netns` (so the host's own traffic never reaches the simulated slaves). Made by
    :func:`veth`; removed when the ``with`` block ends. Needs root (``ip`` from iproute2)."""

    def __init__(self, master: str = "ecpy0", slave: str = "ecpy0s",
                 netns: Optional[str] = None):
        self.master = master
        self.slave = slave
        self.netns = netns or f"codrive-{master}"
        self._made = False

    @staticmethod
    def _ip(*args: str) -> None:
        r = subprocess.run(["ip", *args], capture_output=True, text=True)
        if r.returncode != 0:
            raise Error(f"ip {' '.join(args)} failed: {r.stderr.strip() or r.returncode} "
                        "(creating a veth pair needs root and a kernel with veth)")

    def create(self) -> "VethPair":
        """Creates the namespace and the pair and brings both ends up."""
        self.remove()  # a pair left behind by an interrupted run
        self._made = True
        self._ip("netns", "add", self.netns)
        self._ip("link", "add", self.master, "type", "veth", "peer", "name", self.slave,
                 "netns", self.netns)
        self._ip("link", "set", self.master, "up")
        self._ip("-n", self.netns, "link", "set", self.slave, "up")
        return self

    def remove(self) -> None:
        """Deletes the pair and the namespace (nothing if they do not exist)."""
        subprocess.run(["ip", "link", "del", self.master], capture_output=True)
        subprocess.run(["ip", "netns", "del", self.netns], capture_output=True)
        self._made = False

    def __enter__(self) -> "VethPair":
        return self.create() if not self._made else self

    def __exit__(self, *exc) -> None:
        self.remove()


def veth(master: str = "ecpy0", slave: str = "ecpy0s",
         netns: Optional[str] = None) -> VethPair:
    """``with codrive.sim.veth() as link:`` creates veth ends `master` ("ecpy0", for the master
    and the bus file's ``ethercat.interface``) and `slave` (inside namespace `netns`, default
    "codrive-<master>", for :func:`ethercat` with ``netns=link.netns``)."""
    return VethPair(master, slave, netns)


__all__ = ["CanSimulation", "EthercatSimulation", "VethPair", "VirtualDrive", "can", "ethercat",
           "veth"]
