# SPDX-License-Identifier: MIT
"""sh2000.Program: an NC program on a card, read, checked (first pass) and
run (second pass) by libsh2000-motion as sh2000-upload does."""
from . import _sh2000
from ._types import Plan, Progress, RunStats, Status

_FORMATS = {None: _sh2000.PROG_AUTO, "gcode": _sh2000.PROG_GCODE,
            "canon": _sh2000.PROG_CANON, "csv": _sh2000.PROG_CSV,
            "json": _sh2000.PROG_NURBS_JSON}


class Program:
    """card.program(path): the program read from its start at the card's
    position now. check() finds every error before anything moves; run()
    streams it. Do not move the card between opening and running."""

    def __init__(self, card, path, format=None, feed_mm_s=None):
        if format not in _FORMATS:
            raise ValueError(f"format {format!r}: one of gcode, canon, csv, json")
        self.path = str(path)
        self.card = card
        self.plan = None
        self._checked_with = None
        self._p = _sh2000.Program(card._c, self.path, _FORMATS[format],
                                  float(feed_mm_s or 0))

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def close(self):
        self._p.close()

    @property
    def diagnostics(self):
        """Every error and warning so far, "file:line:column: ..." each."""
        return self._p.diagnostics()

    def check(self, override=1.0, optional_stop=False):
        """The first pass: read, check and plan all of it against the
        card's soft limits. A Plan, or sh2000.Error (EPROGRAM with
        .where and .diagnostics, ELIMIT ...)."""
        self.plan = Plan.from_c(self._p.check(float(override), bool(optional_stop)))
        self._checked_with = (float(override), bool(optional_stop))
        return self.plan

    def run(self, progress=None, pause=None, override=1.0, optional_stop=False):
        """The second pass: stream the program to the card and wait for the
        end; checks it first if check() was not called with these options.
        progress(Progress) runs after every batch and poll; pause(where,
        optional) at M0 (and M1 with optional_stop) with the card at rest.
        An exception raised in a callback stops the run on the path and is
        raised here. The axes the program moves must be enabled (Plan.moved).
        A card that moved since check() is refused before anything moves
        (sh2000.Error EMOVED, naming the axis). Returns the RunStats."""
        if self._checked_with != (float(override), bool(optional_stop)):
            self.check(override, optional_stop)
        total = self.plan.points
        cb = None
        if progress is not None:
            def cb(d):
                progress(Progress(points=d["points"], total_points=total, t=d["t"],
                                  queue_fill=d["queue_fill"], line=d["line"],
                                  status=Status.from_c(d["status"])))
        return RunStats.from_c(self._p.run(cb, pause, float(override),
                                           bool(optional_stop)))
