# SPDX-License-Identifier: Apache-2.0
"""EDS/DCF device descriptions (CiA 306), parsed by codrive's C++ parser (the one behind
``codrive eds lint``)."""
from ._native import eds as _eds

Eds = _eds.Eds
Object = _eds.Object
SubObject = _eds.SubObject
Finding = _eds.Finding
load = _eds.load

__all__ = ["Eds", "Finding", "Object", "SubObject", "load"]
