# SPDX-License-Identifier: MIT
"""sh2000: Python binding of libsh2000 (the SH-2000TH motion card) and
libsh2000-motion (programs, planner, runner). docs/python.md is the guide.

    import sh2000
    card = sh2000.open("sim")
    print(card.status().axes[0].pos_mm)

Every error the libraries report is raised as sh2000.Error, carrying the
library's code (sh2000.EPARAM, ...) and message.
"""
from . import _sh2000
from ._card import UNITS, Card, open  # noqa: A004
from ._error import Error
from ._gather import SIGNALS as GATHER_SIGNALS
from ._gather import Gather, GatherInfo
from ._program import Program
from ._types import (AXIS_NAMES, AxisStatus, FirstFault, Plan, Progress,
                     RunStats, Status)

_v = _sh2000.version()
__version__ = _v["library"]
PROTOCOL = _v["protocol"]
strerror = _sh2000.strerror

# The library's constants: error codes (Error.code), card states
# (Status.card_state), axis state bits (AxisStatus.state).
for _name in dir(_sh2000):
    if _name.isupper():
        globals()[_name] = getattr(_sh2000, _name)
del _name, _v

# not "open": a star import would hide the built-in
__all__ = ["Card", "Program", "Error", "Status", "AxisStatus", "FirstFault", "Plan",
           "Progress", "RunStats", "Gather", "GatherInfo", "UNITS",
           "GATHER_SIGNALS", "AXIS_NAMES", "strerror"]
