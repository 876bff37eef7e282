# SPDX-License-Identifier: MIT
"""The reference path of a program: LinuxCNC's `rs274 -g` canonical output
read into a polyline in mm (arcs and helices as chords that stay within
CHORD_SAG of the arc), with the path mode the program set (G64 P)."""
import math
import re

import numpy as np

CHORD_SAG = 1e-4        # mm: a chord's largest distance from its arc

_CALL = re.compile(r"^\s*\d+\s+N\S*\s+([A-Z_]+)\((.*)\)\s*$")
_PLANES = {"CANON_PLANE_XY": (0, 1, 2), "CANON_PLANE_YZ": (1, 2, 0),
           "CANON_PLANE_XZ": (2, 0, 1)}


class Reference:
    """vertices (N x 3, mm), cum (N: arc length at each vertex), moves
    (motion calls), ends and kinds (each move's last vertex and "G0", "G1"
    or "arc"), modes (the path modes set, as text), offsets (non-zero work
    offsets seen, which the reference does not apply)."""

    def __init__(self):
        self.points = [(0.0, 0.0, 0.0)]
        self.moves = 0
        self.ends = []
        self.kinds = []
        self.modes = []
        self.offsets = []
        self.vertices = None
        self.cum = None


def _arc(ref, scale, plane, args):
    """ARC_FEED(first_end, second_end, first_axis, second_axis, rotation,
    axis_end_point, a, b, c) in the plane's (first, second, axis) order."""
    i0, i1, i2 = plane
    e0, e1, c0, c1 = (float(a) * scale for a in args[:4])
    rot = int(args[4])
    e2 = float(args[5]) * scale
    start = ref.points[-1]
    s0, s1, s2 = start[i0], start[i1], start[i2]
    r0 = math.hypot(s0 - c0, s1 - c1)
    r1 = math.hypot(e0 - c0, e1 - c1)
    a0 = math.atan2(s1 - c1, s0 - c0)
    a1 = math.atan2(e1 - c1, e0 - c0)
    if rot > 0:
        sweep = (a1 - a0) % (2 * math.pi)
        if sweep < 1e-12:
            sweep = 2 * math.pi
        sweep += (rot - 1) * 2 * math.pi
    else:
        sweep = -((a0 - a1) % (2 * math.pi))
        if sweep > -1e-12:
            sweep = -2 * math.pi
        sweep -= (-rot - 1) * 2 * math.pi
    r = max(r0, r1, 1e-9)
    step = 2 * math.acos(max(-1.0, 1 - CHORD_SAG / r)) if r > CHORD_SAG else math.pi / 2
    n = max(2, int(math.ceil(abs(sweep) / step)))
    for k in range(1, n + 1):
        f = k / n
        ang = a0 + sweep * f
        rad = r0 + (r1 - r0) * f
        p = [0.0, 0.0, 0.0]
        p[i0] = c0 + rad * math.cos(ang)
        p[i1] = c1 + rad * math.sin(ang)
        p[i2] = s2 + (e2 - s2) * f
        ref.points.append(tuple(p))
    ref.points[-1] = tuple(e0 if i == i0 else e1 if i == i1 else e2 for i in range(3))


def read(path):
    """The reference of a canonical output file."""
    ref = Reference()
    scale = 1.0
    plane = _PLANES["CANON_PLANE_XY"]
    with open(path) as f:
        for line in f:
            m = _CALL.match(line)
            if not m:
                continue
            name, args = m.group(1), [a.strip() for a in m.group(2).split(",")]
            if name == "USE_LENGTH_UNITS":
                scale = {"CANON_UNITS_INCHES": 25.4, "CANON_UNITS_MM": 1.0,
                         "CANON_UNITS_CM": 10.0}[args[0]]
            elif name == "SELECT_PLANE":
                plane = _PLANES[args[0]]
            elif name in ("STRAIGHT_TRAVERSE", "STRAIGHT_FEED"):
                ref.points.append(tuple(float(a) * scale for a in args[:3]))
                ref.moves += 1
                ref.ends.append(len(ref.points) - 1)
                ref.kinds.append("G0" if name == "STRAIGHT_TRAVERSE" else "G1")
            elif name == "ARC_FEED":
                _arc(ref, scale, plane, args)
                ref.moves += 1
                ref.ends.append(len(ref.points) - 1)
                ref.kinds.append("arc")
            elif name == "SET_MOTION_CONTROL_MODE":
                mode = args[0].replace("CANON_", "")
                if len(args) > 1:
                    mode += " P%.4g mm" % (float(args[1]) * scale)
                ref.modes.append(mode)
            elif name in ("SET_G5X_OFFSET", "SET_G92_OFFSET"):
                vals = [float(a) for a in args[1 if name == "SET_G5X_OFFSET" else 0:]]
                if any(v != 0.0 for v in vals):
                    ref.offsets.append(line.strip())
            elif name in ("NURBS_FEED", "STRAIGHT_PROBE", "RIGID_TAP"):
                raise ValueError("%s: %s is not judged by this benchmark" % (path, name))
    v = np.array(ref.points)
    ref.vertices = v
    ref.cum = np.concatenate(([0.0], np.cumsum(np.linalg.norm(np.diff(v, axis=0), axis=1))))
    return ref


def _window_distance(p, a, b):
    """Distances of point p to the segments a[i]-b[i]."""
    ab = b - a
    ap = p - a
    l2 = np.einsum("ij,ij->i", ab, ab)
    t = np.where(l2 > 0, np.einsum("ij,ij->i", ab, ap) / np.where(l2 > 0, l2, 1), 0.0)
    t = np.clip(t, 0.0, 1.0)
    d = ap - t[:, None] * ab
    return np.sqrt(np.einsum("ij,ij->i", d, d)), t


def deviation(ref, pos):
    """Each sample's distance to the reference path."""
    return locate(ref, pos)[0]


def locate(ref, pos, back=2.0, ahead=2.0):
    """Each sample's distance to the reference path and the arc length
    where it is nearest. The samples follow the path, so each is searched
    among the segments from BACK mm behind to AHEAD mm (plus the step since
    the sample before) in front of where the sample before was nearest."""
    v, cum = ref.vertices, ref.cum
    nseg = len(v) - 1
    if nseg < 1:
        return np.linalg.norm(pos - v[0], axis=1), np.zeros(len(pos))
    out = np.empty(len(pos))
    where = np.empty(len(pos))
    s = 0.0
    prev = pos[0]
    for k, p in enumerate(pos):
        stride = float(np.linalg.norm(p - prev))
        prev = p
        lo = max(0, int(np.searchsorted(cum, s - back)) - 1)
        hi = min(nseg, int(np.searchsorted(cum, s + ahead + 2 * stride)) + 1)
        d, t = _window_distance(p, v[lo:hi], v[lo + 1:hi + 1])
        i = int(np.argmin(d))
        out[k] = d[i]
        s = cum[lo + i] + t[i] * (cum[lo + i + 1] - cum[lo + i])
        where[k] = s
    return out, where
