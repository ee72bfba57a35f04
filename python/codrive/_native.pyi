# SPDX-License-Identifier: Apache-2.0
# Type stubs of the extension codrive._native (python/src/*.cpp), so editors and type checkers
# complete the API. Use it through `codrive`, `codrive.sim`, `codrive.eds`, `codrive.dump`.
from typing import Callable, Dict, List, Optional, Tuple, Union

__version__: str

ProgressFn = Callable[[int, Optional[int]], object]

class Error(Exception):
    """Base class of every codrive error."""

class BusError(Error):
    """A bus could not be opened or used."""

class SdoError(Error):
    """An SDO transfer failed; str() is one sentence naming node, object and cause."""
    node: int
    index: int
    subindex: int
    direction: str
    protocol: str
    code: Optional[int]
    origin: str
    timeout: float

class SdoAbortError(SdoError):
    """An abort frame ended the transfer; `code` is the 32-bit abort code."""
    code: int

class SdoTimeoutError(SdoError):
    """No response within `timeout` seconds."""

class SdoClient:
    """The SDO client of one node's default channel (bus.sdo(node))."""
    @property
    def node(self) -> int: ...
    def read(self, index: int, subindex: int, type: str = "bytes", *,
             timeout: Optional[float] = None, mode: str = "auto",
             progress: Optional[ProgressFn] = None) -> Union[int, float, str, bytes]: ...
    def write(self, index: int, subindex: int, value: Union[int, float, str, bytes, bytearray],
              type: Optional[str] = None, *, timeout: Optional[float] = None,
              mode: str = "auto", progress: Optional[ProgressFn] = None) -> None: ...
    def upload_file(self, index: int, subindex: int, path: str, *,
                    timeout: Optional[float] = None, mode: str = "auto",
                    progress: Optional[ProgressFn] = None) -> int: ...
    def download_file(self, index: int, subindex: int, path: str, *,
                      timeout: Optional[float] = None, mode: str = "auto",
                      progress: Optional[ProgressFn] = None) -> None: ...
    def _cpp_round_trips(self, index: int, subindex: int, count: int) -> float: ...

class Nmt:
    """The NMT master of a bus (bus.nmt); node 0 addresses every node."""
    def start(self, node: int) -> None: ...
    def stop(self, node: int) -> None: ...
    def pre_operational(self, node: int) -> None: ...
    def reset(self, node: int) -> None: ...
    def reset_communication(self, node: int) -> None: ...
    def state(self, node: int) -> str: ...
    def wait_for_state(self, node: int, state: str, timeout: float = 1.0) -> bool: ...
    def boot_ups(self, node: int) -> int: ...

class Bus:
    """A CAN bus with the master's SDO clients and NMT master on it."""
    def __init__(self, interface: str, timeout: float = 1.0) -> None: ...
    @property
    def name(self) -> str: ...
    @property
    def nmt(self) -> Nmt: ...
    def sdo(self, node: int) -> SdoClient: ...
    def run_for(self, seconds: float) -> None: ...
    def scan(self, first: int = 1, last: int = 127, timeout: float = 0.3
             ) -> List[Dict[str, object]]: ...

class VirtualNetwork(Bus):
    """An in-process CAN network on simulated time."""
    def __init__(self, timeout: float = 1.0) -> None: ...
    @property
    def time(self) -> float: ...

class _VirtualDrive:
    def __init__(self, network: VirtualNetwork, node: int, profile: str = "akd2g",
                 axes: int = 0) -> None: ...
    @property
    def node(self) -> int: ...
    @property
    def profile(self) -> str: ...
    @property
    def axes(self) -> int: ...
    @property
    def nmt_state(self) -> str: ...
    def statusword(self, axis: int = 1) -> int: ...
    def inject(self, axis: int, fault: str) -> None: ...

class _SimModule:
    CONTROL_OBJECT: int
    VirtualDrive = _VirtualDrive
    @staticmethod
    def control_subindex(fault: str) -> int: ...

sim: _SimModule

class _Finding:
    file: str
    line: int
    severity: str
    message: str

class _SubObject:
    subindex: int
    name: str
    type: str
    access: str
    pdo_mappable: bool
    value: Union[int, float, str, bytes]
    default: Union[int, float, str, bytes, None]
    low_limit: Union[int, float, str, bytes, None]
    high_limit: Union[int, float, str, bytes, None]
    default_text: str

class _Object:
    index: int
    name: str
    code: str
    subs: List[_SubObject]
    def __getitem__(self, key: Union[int, str]) -> _SubObject: ...
    def __len__(self) -> int: ...

class _Eds:
    path: str
    findings: List[_Finding]
    has_errors: bool
    device_info: Dict[str, object]
    node_id: Optional[int]
    def __getitem__(self, key: Union[int, str, Tuple[Union[int, str], Union[int, str]]]
                    ) -> Union[_Object, _SubObject]: ...
    def __contains__(self, key: Union[int, str]) -> bool: ...
    def __len__(self) -> int: ...
    def __iter__(self): ...

class _EdsModule:
    Eds = _Eds
    Object = _Object
    SubObject = _SubObject
    Finding = _Finding
    @staticmethod
    def load(path: str, node_id: Optional[int] = None) -> _Eds: ...

eds: _EdsModule

class _TraceStream:
    def __init__(self, path: str, eds: Dict[int, str], profiles: Dict[int, str],
                 sdo_timeout: float) -> None: ...
    def next_chunk(self) -> Optional[str]: ...
    problems: List[str]
    fatal: bool
    path: str

class _DumpModule:
    TraceStream = _TraceStream

dump: _DumpModule

class DriveError(Error):
    """A CiA 402 axis operation failed; the message names the axis and the cause."""

class Axis:
    """A CiA 402 axis of a started Controller."""
    @property
    def name(self) -> str: ...
    @property
    def status(self) -> Dict[str, object]: ...
    def enable(self, timeout: Optional[float] = None) -> None: ...
    def disable(self, timeout: Optional[float] = None) -> None: ...
    def quick_stop(self, timeout: Optional[float] = None) -> None: ...
    def fault_reset(self, timeout: Optional[float] = None) -> None: ...
    def set_mode(self, mode: int, timeout: Optional[float] = None) -> None: ...
    def move_to(self, target: int, relative: bool = False, velocity: Optional[int] = None,
                timeout: Optional[float] = None) -> None: ...
    def set_target_position(self, target: int) -> None: ...
    def set_target_velocity(self, target: int) -> None: ...

class Controller:
    """A bus file booted by the C++ controller."""
    @staticmethod
    def from_file(path: str) -> "Controller": ...
    def start(self) -> None: ...
    def run_for(self, seconds: float) -> None: ...
    def shutdown(self) -> None: ...
    def stats(self) -> Dict[str, object]: ...
    @property
    def events(self) -> List[str]: ...
    @property
    def boot_reports(self) -> List[str]: ...
    @property
    def axes(self) -> List[Dict[str, object]]: ...
    @property
    def running(self) -> bool: ...
    def axis(self, node: int, axis: int = 1, bus: int = 0) -> Axis: ...
