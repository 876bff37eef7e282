# SPDX-License-Identifier: MIT
"""sh2000.Card: an open card, over the extension's Card (one libsh2000 call
per method). Axes are "x", "y", "z", "a" (or 0..3); times in seconds."""
import numbers
import os
from dataclasses import asdict

from . import _gather, _sh2000
from ._error import Error
from ._program import Program
from ._types import Status, axis_index, axis_mask

# (id, name, unit, is_global) of every parameter, from the library
_PARAMS = _sh2000.param_table()
_AXIS_PARAMS = [(i, n) for i, n, _u, g in _PARAMS if not g]
_GLOBAL_PARAMS = [(i, n) for i, n, _u, g in _PARAMS if g]
UNITS = {n: u for _i, n, u, _g in _PARAMS}

_BACKENDS = {_sh2000.BACKEND_DEV: "dev", _sh2000.BACKEND_IO: "io",
             _sh2000.BACKEND_SIM: "sim", _sh2000.BACKEND_SHM: "shm",
             _sh2000.BACKEND_PORTS: "ports"}
_GLOBAL = -1    # SH2000_GLOBAL


def _number(value, what):
    """A real number as a float: TypeError for anything else, a bool too
    (True is not 1.0 mm)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{what} {value!r}: not a number")
    return float(value)


def _seconds(value, what):
    """A time in s, a number 0 or more: ValueError for a negative or NaN
    one (None, "no limit", is the caller's)."""
    s = _number(value, what)
    if not s >= 0:
        raise ValueError(f"{what} {value!r}: a time in s, 0 or more")
    return s


def _ms(timeout):
    """Seconds (None: no limit) -> the library's milliseconds (where a
    negative count means no limit: here only None says that)."""
    if timeout is None:
        return -1
    return int(round(_seconds(timeout, "timeout") * 1000))


def _param_axis(axis):
    """An axis, or None / "global" for the global parameters."""
    return _GLOBAL if axis is None or axis == "global" else axis_index(axis)


class Card:
    """An open SH-2000TH card: sh2000.open(device)."""

    def __init__(self, device=None):
        self._c = _sh2000.Card(device)
        info = self._c.info()
        self.device = info["device"]
        self.backend = _BACKENDS.get(info["backend"], str(info["backend"]))
        self.card_protocol = info["card_protocol"]
        self.queue_size = info["queue_size"]

    def __repr__(self):
        return f"<sh2000.Card {self.device!r} ({self.backend})>"

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def close(self):
        self._c.close()

    # ---- status and parameters ----------------------------------------
    def status(self):
        """One status poll (sh2000_poll) as a Status."""
        return Status.from_c(self._c.status())

    def param(self, axis, name):
        """A parameter in user units; axis None or "global" for globals."""
        return self._c.param_get(_param_axis(axis), _sh2000.param_id(name))

    def set_param(self, axis, name, value):
        """Set one parameter (the library checks it before it is sent)."""
        self._c.param_set(_param_axis(axis), _sh2000.param_id(name),
                          _number(value, f"parameter {name}:"))

    def params(self, axis):
        """Every parameter of an axis (or None/"global") as {name: value}."""
        if _param_axis(axis) == _GLOBAL:
            return {n: self._c.param_get(_GLOBAL, i) for i, n in _GLOBAL_PARAMS}
        values = self._c.axis_params_get(axis_index(axis))
        return {n: values[i] for i, n in _AXIS_PARAMS}

    def set_params(self, axis, values):
        """Set several parameters of one axis, all or none
        (sh2000_axis_params_set checks every value first)."""
        a = axis_index(axis)
        ids = {n: i for i, n in _AXIS_PARAMS}
        new = self._c.axis_params_get(a)
        for name, v in values.items():
            if name not in ids:
                _sh2000.param_id(name)      # sh2000.Error for an unknown name
                raise Error(_sh2000.EPARAM, _sh2000.strerror(_sh2000.EPARAM),
                            f"parameter {name}: a global parameter: set it with set_param")
            new[ids[name]] = _number(v, f"parameter {name}:")
        self._c.axis_params_set(a, new)

    # ---- commands --------------------------------------------------------
    def enable(self, axes):
        """Enable axes: "xy", ["x", "y"], a mask, or "all"."""
        self._c.enable(axis_mask(axes))

    def disable(self, axes):
        self._c.disable(axis_mask(axes))

    def stop(self):
        """Controlled stop: the card decelerates and discards the ring."""
        self._c.stop()

    def reset(self):
        """Clear latched faults and a latched emergency stop."""
        self._c.reset()

    def estop(self, timeout=0.1):
        """Emergency stop; waits up to timeout s for the card's answer."""
        self._c.estop(_ms(timeout))

    def home(self, axis, index=False, timeout=60.0):
        """Home one axis and wait for the end (sh2000_run_home)."""
        self._c.home(axis_index(axis), _sh2000.HOME_F_INDEX if index else 0,
                     _ms(timeout))

    def set_position(self, axis, mm):
        self._c.set_position(axis_index(axis), _number(mm, "position"))

    # ---- points ------------------------------------------------------------
    def push(self, points, end=False):
        """Queue coarse points in mm (rows of four, x y z a) in one
        all-or-nothing batch; end=True on a motion's last batch."""
        return self._c.push_mm(points, 1 if end else 0)

    def push_counts(self, points, end=False):
        """The same in encoder counts."""
        return self._c.push_counts(points, 1 if end else 0)

    def wait_space(self, n, timeout=None):
        self._c.wait_space(n, _ms(timeout))

    def wait_idle(self, timeout=None):
        """Wait until the card is idle with an empty ring."""
        self._c.wait_idle(_ms(timeout))

    def wait_rest(self, timeout=None):
        """Wait until the card is at rest (not moving, as
        Status.moving says): after stop(), whatever latched."""
        self._c.wait_rest(_ms(timeout))

    def queue_free(self):
        return self._c.queue_free()

    # ---- time ----------------------------------------------------------------
    def now(self):
        """The card's clock in s (virtual for "sim")."""
        return self._c.now_ns() / 1e9

    def sleep(self, seconds):
        """Let card time pass (advances a "sim" card; sleeps otherwise)."""
        self._c.sleep_ns(int(round(_seconds(seconds, "sleep") * 1e9)))

    # ---- data gathering (protocol 1.2) --------------------------------------
    def gather_start(self, axes, signals, period=None, samples=None,
                     trigger="now", pretrigger=None):
        """Arm a record (sh2000_gather_start): signals ("setpoint,encoder",
        a list of names, or "all") of each axis in axes, every period servo
        cycles; trigger "now", "motion" or "fault". Unset values are the
        library's defaults. Returns the record's number. Without numpy an
        ImportError, before anything is armed (the record could not be read)."""
        _gather.need_numpy()
        return self._c.gather_start(*_gather.config(axes, signals, period, samples,
                                                    trigger, pretrigger))

    def gather_stop(self):
        """End the record now; what it holds stays readable."""
        self._c.gather_stop()

    def gather_info(self):
        """The record (or, before the first, the configuration): GatherInfo."""
        return _gather.GatherInfo(**self._c.gather_info())

    def gather_wait(self, record, timeout=60.0):
        """Wait until record number `record` is done; its GatherInfo."""
        return _gather.GatherInfo(**self._c.gather_wait(record, _ms(timeout)))

    def gather_read(self, info, first=0, n=None):
        """Samples first..first+n (all: n None) of the record info
        describes as a Gather of numpy arrays."""
        _gather.need_numpy()            # before the card's time is spent
        n = info.samples - first if n is None else n
        raw = self._c.gather_read(asdict(info), first, n)
        return _gather.shape(info, first, raw)

    def gather(self, axes, signals, period=None, samples=None, trigger="now",
               pretrigger=None, timeout=60.0):
        """gather_start, gather_wait and gather_read in one: the record as
        a Gather (t in s, g["x.setpoint"] ...)."""
        rec = self.gather_start(axes, signals, period, samples, trigger, pretrigger)
        return self.gather_read(self.gather_wait(rec, timeout))

    # ---- compensation tables ---------------------------------------------------
    def comp_load(self, path):
        """Load a compensation table file (docs/compensation.md) and switch
        to it at rest; a refused file raises with FILE:LINE in the message
        and changes nothing on the card."""
        self._c.comp_load(os.fspath(path))

    def comp_clear(self):
        """No compensation tables (switched at rest)."""
        self._c.comp_clear()

    def comp_status(self):
        """The active tables: a dict of state ("none", "active",
        "switching"), tables, id, sum and generation (switches)."""
        st = self._c.comp_status()
        st["state"] = ("none", "active", "switching")[st["state"]]
        return st

    # ---- programs --------------------------------------------------------------
    def program(self, path, format=None, feed_mm_s=None):
        """Open an NC program to check and run on this card; it starts
        where the card is now."""
        return Program(self, path, format, feed_mm_s)


def open(device=None):  # noqa: A001 (the API's name: sh2000.open, like open())
    """Open a card by device string: "/dev/sh2000-0", "io:0x300", "sim",
    "sim:NAME"; None: $SH2000_DEVICE, else /dev/sh2000-0."""
    return Card(device)
