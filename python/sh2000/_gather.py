# SPDX-License-Identifier: MIT
"""Data gathering (protocol 1.2) as numpy arrays: the card records chosen
signals every `period` servo cycles, sh2000_gather_read reads the record,
and this module only shapes it: one array per signal, named as
`sh2000ctl gather` names its CSV columns ("x.setpoint"), with the units
the library gives, and a time axis in seconds from the trigger. numpy is
imported here only, when a record is read."""
from dataclasses import asdict, dataclass
from typing import Any, Dict, Tuple

from . import _sh2000
from ._types import AXIS_NAMES, axis_mask

# (id, name, unit) of every signal, from the library
SIGNALS = {name: (sid, unit) for sid, name, unit in _sh2000.gather_signals()}
TRIGGERS = {"now": _sh2000.GATHER_NOW, "motion": _sh2000.GATHER_ON_MOTION,
            "fault": _sh2000.GATHER_ON_FAULT}
_SIGNAL_NAMES = {sid: (name, unit) for name, (sid, unit) in SIGNALS.items()}


def need_numpy():
    """numpy, or an ImportError saying what needs it and how to get it."""
    try:
        import numpy
    except ImportError as e:
        raise ImportError("sh2000: gathered records are numpy arrays: install "
                          "numpy (Debian: python3-numpy)") from e
    return numpy


def signal_mask(signals):
    """"setpoint,encoder", ["setpoint", "encoder"] or "all" -> the mask of
    1 << signal id; sh2000.Error (EPARAM) naming an unknown name."""
    if isinstance(signals, str):
        if signals == "all":
            return sum(1 << sid for sid, _u in SIGNALS.values())
        signals = signals.split(",")
    mask = 0
    for name in signals:
        mask |= 1 << _sh2000.gather_signal_id(name)
    return mask


def config(axes, signals, period, samples, trigger, pretrigger):
    """The arguments of the extension's gather_start: unset ones (None)
    from sh2000_gather_config_default, as the card's defaults."""
    if trigger not in TRIGGERS:
        raise ValueError(f"trigger {trigger!r}: one of now, motion, fault")
    mask, sig = axis_mask(axes), signal_mask(signals)
    per_axis = tuple(sig if mask & (1 << a) else 0 for a in range(_sh2000.AXES))
    default = _sh2000.gather_config_default()
    return (per_axis,
            default["period"] if period is None else period,
            default["samples"] if samples is None else samples,
            TRIGGERS[trigger],
            default["pretrigger"] if pretrigger is None else pretrigger)


@dataclass(frozen=True)
class GatherInfo:
    """struct sh2000_gather_info: a record as the card describes it."""
    state: int          # sh2000.GATHER_OFF/ARMED/RECORDING/DONE
    record: int
    trigger: int
    period: int         # servo cycles per sample
    values: int         # values per sample
    signals: Tuple[int, int, int, int]
    samples: int        # in the record now
    capacity: int
    pretrigger: int
    trigger_index: int  # sh2000.GATHER_NO_TRIGGER if it never fired
    first_cycle: int
    trigger_cycle: int
    buffer: int
    sample_s: float

    @property
    def triggered(self):
        return self.trigger_index != _sh2000.GATHER_NO_TRIGGER


@dataclass(frozen=True)
class Gather:
    """A record read out: t (s from the trigger, or from sample 0 if it
    never fired) and one array per signal, in the card's units:
    g["x.setpoint"], g.signals (name -> array, in the record's order),
    g.units (name -> "counts", "dac", ...)."""
    t: Any
    signals: Dict[str, Any]
    units: Dict[str, str]
    info: GatherInfo
    first: int = 0

    def __getitem__(self, name):
        return self.signals[name]


def columns(info):
    """(name, unit) of each value of a sample: ("x.setpoint", "counts")."""
    d = asdict(info)
    out = []
    for k in range(info.values):
        axis, sid = _sh2000.gather_column(d, k)
        name, unit = _SIGNAL_NAMES[sid]
        out.append((f"{AXIS_NAMES[axis]}.{name}", unit))
    return out


def shape(info, first, raw):
    """The extension's bytearray of samples first.. into a Gather."""
    np = need_numpy()
    values = np.frombuffer(raw, dtype=np.float64).reshape(-1, info.values)
    t0 = info.trigger_index if info.triggered else 0
    t = (np.arange(first, first + len(values)) - float(t0)) * info.sample_s
    cols = columns(info)
    return Gather(t=t, signals={n: values[:, k] for k, (n, _u) in enumerate(cols)},
                  units=dict(cols), info=info, first=first)
