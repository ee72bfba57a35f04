# SPDX-License-Identifier: Apache-2.0
"""Simulated drives: in-process on a VirtualNetwork, or the codrive-sim process on vcan."""
from ._native import sim as _sim

VirtualDrive = _sim.VirtualDrive

__all__ = ["VirtualDrive"]
