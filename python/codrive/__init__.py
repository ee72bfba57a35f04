# SPDX-License-Identifier: Apache-2.0
"""codrive from Python: CANopen SDO/NMT, simulated drives, EDS files and trace decoding.

The protocol work is done by the C++ stack (the extension ``codrive._native``); this package
gives it Python names. See docs/python.md.
"""
from ._native import (
    Axis,
    Bus,
    BusError,
    Controller,
    DriveError,
    Error,
    Nmt,
    SdoAbortError,
    SdoClient,
    SdoError,
    SdoTimeoutError,
    VirtualNetwork,
    __version__,
    measure_timer_latency,
)
from . import dump, eds, sim


async def _aread(self, index, subindex, type="bytes", **options):
    """read() for asyncio: the transfer runs in the loop's default executor (a worker thread,
    GIL released while it waits), so the event loop keeps running. Transfers on one bus take
    turns; buses are independent."""
    import asyncio
    import functools
    call = functools.partial(self.read, index, subindex, type, **options)
    return await asyncio.get_running_loop().run_in_executor(None, call)


async def _awrite(self, index, subindex, value, type=None, **options):
    """write() for asyncio (see aread)."""
    import asyncio
    import functools
    call = functools.partial(self.write, index, subindex, value, type, **options)
    return await asyncio.get_running_loop().run_in_executor(None, call)


SdoClient.aread = _aread
SdoClient.awrite = _awrite


def scan(bus, first=1, last=127, timeout=0.3):
    """The nodes on `bus` (a Bus or VirtualNetwork), as ``codrive scan`` finds them: a list of
    dicts with node, state, device_type, vendor_id, product_code, revision, serial, name."""
    return bus.scan(first, last, timeout)

__all__ = [
    "Axis",
    "Bus",
    "BusError",
    "Controller",
    "DriveError",
    "Error",
    "Nmt",
    "SdoAbortError",
    "SdoClient",
    "SdoError",
    "SdoTimeoutError",
    "VirtualNetwork",
    "__version__",
    "dump",
    "eds",
    "scan",
    "sim",
]
