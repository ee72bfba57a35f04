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
)
from . import dump, eds, sim


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
