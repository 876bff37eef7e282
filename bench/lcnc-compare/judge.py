#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Judges both planners' recordings of the same programs the same way and
prints the comparison table.

    judge.py [--detail] LCNC_SAMPLES NAME:CANON:OURS_CSV:MARKER...

LCNC_SAMPLES: halsampler -t output of bench.hal (sample number, the joint
commands x y z in mm, the marker), one row per LinuxCNC servo period (1 ms).
OURS_CSV: sh2000-upload --trace with --trace-every 10 (the card's fine
set-points every 10 servo cycles of 100 us: 1 ms). CANON: `rs274 -g` on
the program, the reference path. MARKER: the program's marker in the
samples.

Both recordings are positions every T = 1 ms, and everything below is
computed from them alike:
  cycle time   from the last sample before any axis moves to the first
               after the last movement, in samples x T (LinuxCNC's counted
               in its servo periods, ours in the card's servo cycles)
  deviation    the largest distance of a sample from the reference path
               (canon.py: chords within 0.1 um of the arcs), in the table
               of the samples nearest to a feed move (G1, G2, G3), in
               the details of all (G0 included)
  v, a, j      raw first, second and third differences of each axis' samples
               over T (no smoothing); the peak over the axes, with its axis
  slow         time below 50 mm/s (the path speed of the central difference)
The exit code is 1 if a recording is missing or empty.
"""
import sys
import warnings

import numpy as np

sys.dont_write_bytecode = True    # no __pycache__ beside the sources
import canon

T = 1e-3
SLOW = 50.0             # mm/s


def load_ours(path):
    data = np.loadtxt(path, delimiter=",", skiprows=1, usecols=(0, 1, 3, 5), ndmin=2)
    if len(data) > 2:
        dt = np.diff(data[:, 0])
        if np.max(np.abs(dt - T)) > 1e-6:
            raise ValueError("%s: samples are not %g s apart (use --trace-every 10)" % (path, T))
    return data[:, 1:4], 0


def load_lcnc(rows, marker):
    sel = rows[rows[:, 4] == marker]
    lost = 0
    if len(sel) > 1:
        lost = int(np.sum(np.diff(sel[:, 0]) - 1))
    return sel[:, 1:4], lost


def moving_span(pos):
    """First and last sample index of the motion (a sample at rest before
    and after it included)."""
    moved = np.any(np.diff(pos, axis=0) != 0.0, axis=1)
    idx = np.nonzero(moved)[0]
    if len(idx) == 0:
        return None
    return int(idx[0]), int(idx[-1]) + 1


def peak(series):
    """(largest |value| over every axis, its axis letter)."""
    if len(series) == 0:
        return 0.0, "-"
    m = np.max(np.abs(series), axis=0)
    i = int(np.argmax(m))
    return float(m[i]), "xyz"[i]


def measure(ref, pos, lost):
    span = moving_span(pos)
    if span is None:
        return None
    i0, i1 = span
    # three samples of rest either side, where there are any, so that the
    # start and the stop count in the differences
    seg = pos[max(0, i0 - 3):i1 + 4]
    run = pos[i0:i1 + 1]
    speed = np.linalg.norm(run[2:] - run[:-2], axis=1) / (2 * T)
    dist, where = canon.locate(ref, run)
    move = np.minimum(np.searchsorted(ref.cum[ref.ends], where), len(ref.ends) - 1)
    feed = np.array([k != "G0" for k in ref.kinds])[move] if ref.ends else np.zeros(len(run), bool)
    length = float(np.sum(np.linalg.norm(np.diff(run, axis=0), axis=1)))
    return {
        "time": (i1 - i0) * T,
        "dev": float(np.max(dist[feed])) if np.any(feed) else 0.0,
        "dev_all": float(np.max(dist)),
        "v": peak(np.diff(seg, 1, axis=0) / T),
        "a": peak(np.diff(seg, 2, axis=0) / T ** 2),
        "j": peak(np.diff(seg, 3, axis=0) / T ** 3),
        "slow": float(np.sum(speed < SLOW)) * T,
        "length": length,
        "lost": lost,
    }


def fmt_pair(a, b, f):
    return "%s / %s" % (f(a) if a is not None else "-", f(b) if b is not None else "-")


def row(name, ref, ours, lcnc):
    def get(m, key):
        return None if m is None else m[key]

    ratio = ("%.2f" % (ours["time"] / lcnc["time"])) if ours and lcnc else "-"
    return "| %s | %d | %s | %s | %s | %s | %s | %s | %s | %s |" % (
        name, ref.moves, ", ".join(sorted(set(ref.modes))) or "-",
        fmt_pair(get(ours, "time"), get(lcnc, "time"), lambda t: "%.3f" % t), ratio,
        fmt_pair(get(ours, "dev"), get(lcnc, "dev"), lambda d: "%.4f" % d),
        fmt_pair(get(ours, "v"), get(lcnc, "v"), lambda p: "%.1f %s" % p),
        fmt_pair(get(ours, "a"), get(lcnc, "a"), lambda p: "%.0f %s" % p),
        fmt_pair(get(ours, "j"), get(lcnc, "j"), lambda p: "%.3g %s" % p),
        fmt_pair(get(ours, "slow"), get(lcnc, "slow"), lambda t: "%.2f" % t))


def detail(name, ref, side, m):
    if m is None:
        return "%s, %s: no motion recorded" % (name, side)
    return ("%s, %s: %.3f s, %.1f mm, mean %.1f mm/s, %.2f s below %g mm/s (%.0f %%), "
            "largest deviation with G0 %.4f mm, %d samples lost%s" % (
                name, side, m["time"], m["length"], m["length"] / m["time"], m["slow"], SLOW,
                100 * m["slow"] / m["time"], m["dev_all"], m["lost"],
                ("; non-zero offsets not applied: " + "; ".join(ref.offsets)) if ref.offsets else ""))


def main(argv):
    show_detail = "--detail" in argv
    args = [a for a in argv if a != "--detail"]
    if len(args) < 2:
        sys.exit(__doc__)
    rows = np.zeros((0, 5))
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            data = np.loadtxt(args[0], ndmin=2)
        if data.shape[1] == 5:
            rows = data
    except (OSError, ValueError) as e:
        print("judge: LinuxCNC's samples: %s" % e, file=sys.stderr)
    print("| program | moves | path mode | cycle time ours / LinuxCNC (s) | ratio "
          "| largest deviation on feed moves ours / LinuxCNC (mm) | peak axis v (mm/s, limit 400) "
          "| peak axis a (mm/s^2, limit 5000) | peak axis jerk (mm/s^3, ours' limit 5e6) "
          "| time below 50 mm/s (s) |")
    print("| --- " * 10 + "|")
    bad = 0
    notes = []
    for spec in args[1:]:
        name, ref_path, ours_path, marker = spec.split(":")
        ref = canon.read(ref_path)
        results = []
        for side, load in (("ours", lambda: load_ours(ours_path)),
                           ("LinuxCNC", lambda: load_lcnc(rows, int(marker)))):
            try:
                pos, lost = load()
                m = measure(ref, pos, lost) if len(pos) else None
            except (OSError, ValueError) as e:
                print("judge: %s, %s: %s" % (name, side, e), file=sys.stderr)
                m = None
            bad += m is None
            results.append(m)
            notes.append(detail(name, ref, side, m))
        print(row(name, ref, results[0], results[1]), flush=True)
    if show_detail:
        print()
        print("\n".join(notes))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
