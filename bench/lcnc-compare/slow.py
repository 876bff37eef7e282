#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Where a planner's cycle time goes on one program of the comparison:
every sample of each side (1 ms) is given to the nearest junction between
two moves of the reference path (by arc length), and the time is summed
per kind of junction (the two moves' kinds, the turn between their
tangents, the shorter move's length), with the time below 50 mm/s, the
slowest speed at those junctions (median) and what each side was doing
while slow: the share of slow time spent changing speed at more than 90 %
of its path acceleration ("accel"), and the largest axis acceleration and
jerk there.

    slow.py KEEPDIR NAME [--by=angle|length|kinds]... [--worst=N]

--worst=N lists the N junctions where ours loses most time against
LinuxCNC, each with both sides' time near it and slowest speed at it.

KEEPDIR: what `SH2000_LCNC_KEEP=KEEPDIR bench/lcnc-compare/run` kept.
"""
import math
import os
import sys

import numpy as np

sys.dont_write_bytecode = True    # no __pycache__ beside the sources
import canon
import judge

ANGLES = [0, 1, 5, 15, 45, 90, 181]           # degrees
LENGTHS = [0, 0.1, 0.25, 0.5, 1, 5, 1e9]      # mm


def junctions(ref):
    """Per junction (end of move k, start of move k+1): arc length, turn in
    degrees, shorter adjacent move in mm, the kinds "G1-arc"; the path's
    start and end are junctions "start" and "end"."""
    v, cum, ends = ref.vertices, ref.cum, ref.ends
    out = [(0.0, 0.0, 0.0, "start")]
    for k in range(len(ends) - 1):
        e = ends[k]
        a = v[e] - v[e - 1] if e > 0 else None
        b = v[e + 1] - v[e] if e + 1 < len(v) else None
        turn = 0.0
        if a is not None and b is not None and np.linalg.norm(a) > 0 and np.linalg.norm(b) > 0:
            c = np.dot(a, b) / np.linalg.norm(a) / np.linalg.norm(b)
            turn = math.degrees(math.acos(max(-1.0, min(1.0, c))))
        start = cum[ends[k - 1]] if k else 0.0
        shorter = min(cum[e] - start, cum[ends[k + 1]] - cum[e])
        out.append((cum[e], turn, shorter, "%s-%s" % (ref.kinds[k], ref.kinds[k + 1])))
    out.append((cum[-1], 0.0, 0.0, "end"))
    return out


def label(junction, by):
    _, turn, shorter, kinds = junction
    if by == "kinds" or kinds in ("start", "end"):
        return kinds
    edges, x, unit = (ANGLES, turn, "deg") if by == "angle" else (LENGTHS, shorter, "mm")
    for lo, hi in zip(edges, edges[1:]):
        if x < hi:
            return "%s %g-%g" % (unit, lo, hi) if hi < 1e8 else "%s >%g" % (unit, lo)
    return "?"


def nearest(ref, pos, js):
    """The moving samples: (positions, path speed, index of the junction
    each is nearest to), or None when nothing moved."""
    span = judge.moving_span(pos)
    if span is None:
        return None
    run = pos[span[0]:span[1] + 1]
    _, where = canon.locate(ref, run)
    speed = np.zeros(len(run))
    speed[1:-1] = np.linalg.norm(run[2:] - run[:-2], axis=1) / (2 * judge.T)
    jpos = np.array([j[0] for j in js])
    after = np.minimum(np.searchsorted(jpos, where), len(jpos) - 1)
    before = np.maximum(after - 1, 0)
    near = np.where(np.abs(jpos[before] - where) < np.abs(jpos[after] - where), before, after)
    return run, speed, near


def side_stats(ref, pos, js, by):
    """{class: [time, slow time, accel share of slow, min speeds, peak a, peak j]}"""
    got = nearest(ref, pos, js)
    if got is None:
        return {}
    run, speed, near = got
    acc_t = np.gradient(speed, judge.T)
    acc = np.zeros_like(run)
    acc[1:-1] = (run[2:] - 2 * run[1:-1] + run[:-2]) / judge.T ** 2
    jerk = np.zeros_like(run)
    jerk[2:-1] = (run[3:] - 3 * run[2:-1] + 3 * run[1:-2] - run[:-3]) / judge.T ** 3
    amax_t = np.max(np.abs(acc_t))
    out = {}
    slowest = {}
    for k in range(len(run)):
        c = label(js[near[k]], by)
        st = out.setdefault(c, [0.0, 0.0, 0.0, [], 0.0, 0.0])
        st[0] += judge.T
        if speed[k] < judge.SLOW:
            st[1] += judge.T
            st[2] += judge.T * (abs(acc_t[k]) > 0.9 * amax_t)
            st[4] = max(st[4], float(np.max(np.abs(acc[k]))))
            st[5] = max(st[5], float(np.max(np.abs(jerk[k]))))
        j = int(near[k])
        slowest[j] = min(slowest.get(j, 1e9), speed[k])
    for j, vmin in slowest.items():
        out[label(js[j], by)][3].append(vmin)
    return out


def report(keep, name, by):
    ref, js, ours_pos, lcnc_pos = load_sides(keep, name)
    ours = side_stats(ref, ours_pos, js, by)
    lcnc = side_stats(ref, lcnc_pos, js, by)
    count = {}
    for j in js:
        count[label(j, by)] = count.get(label(j, by), 0) + 1
    print("%s by %s: time ours / LinuxCNC (s), below 50 mm/s, slowest speed at a junction "
          "(median mm/s), share of slow time at >90 %% of the path acceleration, peak axis "
          "a and jerk while slow" % (name, by))
    for c in sorted(set(ours) | set(lcnc), key=lambda c: -(ours.get(c, [0])[0])):
        o = ours.get(c, [0, 0, 0, [], 0, 0])
        lc = lcnc.get(c, [0, 0, 0, [], 0, 0])
        print("  %-14s %5d junctions | %7.2f / %6.2f s | slow %6.2f / %6.2f s | vmin %6.1f / %6.1f"
              " | accel %3.0f / %3.0f %% | a %5.0f / %5.0f | j %8.3g / %8.3g" % (
                  c, count.get(c, 0), o[0], lc[0], o[1], lc[1],
                  np.median(o[3]) if o[3] else float("nan"),
                  np.median(lc[3]) if lc[3] else float("nan"),
                  100 * o[2] / o[1] if o[1] else 0, 100 * lc[2] / lc[1] if lc[1] else 0,
                  o[4], lc[4], o[5], lc[5]))


def per_junction(ref, pos, js):
    """Per junction: (time of the samples nearest to it, slowest speed)."""
    got = nearest(ref, pos, js)
    out = np.zeros((len(js), 2))
    out[:, 1] = np.inf
    if got is not None:
        _, speed, near = got
        np.add.at(out[:, 0], near, judge.T)
        np.minimum.at(out[:, 1], near, speed)
    return out


def worst(keep, name, count):
    """The junctions where ours loses most against LinuxCNC."""
    ref, js, ours, lcnc = load_sides(keep, name)
    o = per_junction(ref, ours, js)
    lc = per_junction(ref, lcnc, js)
    loss = o[:, 0] - lc[:, 0]
    print("%s: the %d junctions where ours loses most (time near it ours / LinuxCNC, "
          "slowest speed there), of %.2f s lost in all" % (name, count, float(np.sum(loss))))
    for k in np.argsort(-loss)[:count]:
        at, turn, shorter, kinds = js[k]
        print("  #%-5d at %9.2f mm %-8s turn %6.1f deg shorter move %7.2f mm | %6.3f / %6.3f s"
              " (+%5.1f ms) | vmin %6.1f / %6.1f" % (k, at, kinds, turn, shorter, o[k, 0],
                                                     lc[k, 0], 1e3 * loss[k], o[k, 1], lc[k, 1]))


def load_sides(keep, name):
    """The reference, its junctions and both recordings of one program."""
    with open(os.path.join(keep, "programs.txt")) as f:
        marker = [ln.split()[0] for ln in f].index(name) + 1
    ref = canon.read(os.path.join(keep, name + ".canon"))
    ours = judge.load_ours(os.path.join(keep, name + ".ours.csv"))[0]
    rows = np.loadtxt(os.path.join(keep, "lcnc", "samples.txt"), ndmin=2)
    return ref, junctions(ref), ours, judge.load_lcnc(rows, marker)[0]


def main(argv):
    if len(argv) < 2:
        sys.exit(__doc__)
    bys = [a.split("=")[-1] for a in argv[2:] if a.startswith("--by")]
    counts = [int(a.split("=")[-1]) for a in argv[2:] if a.startswith("--worst")]
    for count in counts:
        worst(argv[0], argv[1], count)
    if not bys and not counts:
        bys = ["kinds", "angle", "length"]
    for by in bys:
        report(argv[0], argv[1], by)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
