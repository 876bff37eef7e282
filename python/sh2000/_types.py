# SPDX-License-Identifier: MIT
"""The data the binding hands out: frozen dataclasses whose fields are the
C structs' own (sh2000/sh2000.h, sh2000/run.h), built from the dicts the
extension returns."""
from dataclasses import dataclass, fields
from typing import Optional, Tuple

from . import _sh2000
from ._error import Error

AXIS_NAMES = "xyza"


def axes_text(mask):
    """Axis mask -> "xz"."""
    return "".join(n for i, n in enumerate(AXIS_NAMES) if mask & (1 << i))


def _build(cls, d):
    """cls from a dict with exactly its fields (a mismatch with the
    extension fails loudly)."""
    return cls(**{f.name: d[f.name] for f in fields(cls)})


@dataclass(frozen=True)
class AxisStatus:
    """One axis of struct sh2000_status."""
    pos_counts: int
    cmd_counts: int
    ferr_counts: int
    pos_mm: float
    cmd_mm: float
    ferr_mm: float
    dac: int
    state: int
    faults: int
    fault_names: Tuple[str, ...]

    @property
    def enabled(self):
        return bool(self.state & _sh2000.AXIS_ENABLED)

    @property
    def homed(self):
        return bool(self.state & _sh2000.AXIS_HOMED)

    @property
    def moving(self):
        return bool(self.state & _sh2000.AXIS_MOVING)


@dataclass(frozen=True)
class FirstFault:
    """struct sh2000_first_fault: the fault that latched first since the
    last reset (a card from protocol 1.4). axis is 0..3 for an axis fault
    (bit an AXIS_FAULT_*), None for a card fault (bit a FAULT_*)."""
    axis: Optional[int]
    bit: int
    name: str
    cycle: int


@dataclass(frozen=True)
class Status:
    """struct sh2000_status (one sh2000_poll). fault is the sh2000.Error the
    latched faults stand for (sh2000_status_error), or None; faulted is
    whether there is one (sh2000_status_faulted: a latched fault, or the
    card in FAULT or ESTOP); moving is whether the card moves
    (sh2000_state_moving: RUNNING, STOPPING or HOMING)."""
    card_state: int
    card_state_name: str
    card_faults: int
    card_fault_names: Tuple[str, ...]
    queue_fill: int
    queue_free: int
    heartbeat: int
    heartbeat_age_ns: int
    card_cycle: int
    reject_count: int
    host_time_ns: int
    retries: int
    axes: Tuple[AxisStatus, ...]
    first_fault: Optional[FirstFault]
    fault: Optional[Error]
    faulted: bool
    moving: bool

    @classmethod
    def from_c(cls, d):
        d = dict(d, card_fault_names=tuple(d["card_fault_names"]))
        d["axes"] = tuple(_build(AxisStatus, dict(a, fault_names=tuple(a["fault_names"])))
                          for a in d["axes"])
        if d["first_fault"] is not None:
            d["first_fault"] = _build(FirstFault, d["first_fault"])
        return _build(cls, d)

    def axis(self, name):
        """The AxisStatus of axis "x".."a" (or 0..3)."""
        return self.axes[axis_index(name)]


@dataclass(frozen=True)
class Plan:
    """struct sh2000_program_plan: what check() found."""
    blocks: int
    points: int
    seconds: float
    moved: str          # the axes the program moves, "xy"
    moved_mask: int
    optional_skipped: int
    accel_peak: float   # the set-points' largest acceleration / its axis' amax
    accel_axis: str     # that axis, "x"
    margin: float       # the planner's margin it was planned with
    replans: int        # times planned again with a smaller one

    @classmethod
    def from_c(cls, d):
        return cls(blocks=d["blocks"], points=d["points"], seconds=d["seconds"],
                   moved=axes_text(d["moved"]), moved_mask=d["moved"],
                   optional_skipped=d["optional_skipped"],
                   accel_peak=d["accel_peak"],
                   accel_axis=axes_text(1 << d["accel_axis"]),
                   margin=d["margin"], replans=d["replans"])


@dataclass(frozen=True)
class Progress:
    """struct sh2000_run_progress, with the plan's total: what a progress
    callback gets after every batch and poll of a run."""
    points: int
    total_points: int
    t: float
    queue_fill: int
    line: int           # the block the card ran last (-1 before any)
    status: Status

    @property
    def fraction(self):
        return self.points / self.total_points if self.total_points else 1.0


@dataclass(frozen=True)
class RunStats:
    """struct sh2000_run_stats of a finished run."""
    points: int
    batches: int
    motions: int
    polls: int
    time_s: float
    distance_mm: float
    max_ferr_mm: float
    max_ferr_axis: str
    min_fill: int
    underruns: int

    @classmethod
    def from_c(cls, d):
        return _build(cls, dict(d, max_ferr_axis=AXIS_NAMES[d["max_ferr_axis"] % 4]))


def axis_index(axis):
    """"x".."a" or 0..3 -> 0..3; ValueError otherwise."""
    if isinstance(axis, str) and len(axis) == 1 and axis.lower() in AXIS_NAMES:
        return AXIS_NAMES.index(axis.lower())
    if isinstance(axis, int) and not isinstance(axis, bool) and 0 <= axis < _sh2000.AXES:
        return axis
    raise ValueError(f"axis {axis!r}: one of x, y, z, a (or 0..3)")


def axis_mask(axes):
    """"xy", ["x", "y"], a Plan's moved, or a mask int -> mask, at least
    one axis; ValueError otherwise."""
    if isinstance(axes, int) and not isinstance(axes, bool):
        if not 0 <= axes < 1 << _sh2000.AXES:
            raise ValueError(f"axis mask {axes:#x}: bits 0..3 only")
        mask = axes
    elif isinstance(axes, str) and axes == "all":
        mask = (1 << _sh2000.AXES) - 1
    else:
        mask = 0
        for a in axes:
            mask |= 1 << axis_index(a)
    if not mask:
        raise ValueError(f"axes {axes!r}: no axis (x, y, z, a, or \"all\")")
    return mask
