#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""A CAM-style surfacing program: N lines of G1 with 0.05 mm steps in X, Y
and Z at F3000 (a raster over a smooth surface, rows joined by a step in
Y), as mould and 3D-surface CAM output is. Usage: make_surface.py LINES
[OUT] (stdout without OUT). The benchmark of sh2000-upload runs it."""
import math
import sys


def main():
    n = int(sys.argv[1])
    out = open(sys.argv[2], "w") if len(sys.argv) > 2 else sys.stdout
    row = 2000                      # points per row: 100 mm at 0.05 mm
    w = out.write
    w("(surface raster, %d moves)\nG21 G90 G17 G64 P0.01\nF3000\nG0 X0 Y0 Z1\nG1 Z0\n" % n)
    x = y = 0.0
    d = 1
    for i in range(n):
        if i and i % row == 0:
            y += 0.05
            d = -d
        else:
            x += 0.05 * d
        z = 0.5 * math.sin(x * 0.07) * math.cos(y * 0.05)
        w("G1 X%.4f Y%.4f Z%.4f\n" % (x, y, z))
    w("G0 Z5\nM2\n")


if __name__ == "__main__":
    main()
