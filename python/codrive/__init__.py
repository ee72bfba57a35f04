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
    "sim",
]
