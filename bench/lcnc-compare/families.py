#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Chains of short moves against amax on the card's set-points.

Zigzags, S-bends and spirals of 160 short G1 moves (turns of +-THETA
degrees, lengths L times 1 + 0.3 sin(0.7 i), 3 degrees more every 5th
move, F24000 under G64 P Q0) are what CAM surfacing output is made of,
and where the planner's per-junction bounds are weakest: the blends eat
the moves, the curvature flips from blend to blend, and the controller's
braking between their speed limits swings the acceleration. Each program
goes through LinuxCNC's rs274 (as bench/lcnc-compare/run makes its canon
files) and bench_peaks, which plans it at the card model's limits and
measures the card's fine set-points at every servo cycle.

    families.py BUILD_DIR [--quick]

prints one line per program (pattern, THETA, L, P, planned time, peak axis
acceleration over one servo cycle / amax) and a summary: how many pass
amax, the worst. --quick runs two programs (the suite's smoke test).
A benchmark: it prints figures and never fails on them (exit 77 without
rs274).
"""
import math
import os
import shutil
import subprocess
import sys
import tempfile

PATTERNS = {
    "zig": lambda th: [th, -th],
    "s": lambda th: [th, -th, -th, th],
    "spiral": lambda th: [th, th, th, -th / 2.0],
}
THETAS = (10, 30, 60, 90, 135)
LENGTHS = (0.2, 0.6, 1.2, 3.0)
TOLERANCES = ("0.1", "0.01")
QUICK = (("zig", 10, 0.6, "0.01"), ("s", 30, 1.2, "0.1"))


def program(pattern, theta, length, tol):
    """The G-code of one family member."""
    turns = PATTERNS[pattern](float(theta))
    x = y = heading = 0.0
    out = ["G21 G90 G64 P%s Q0" % tol, "G0 X0 Y0 Z0"]
    for i in range(160):
        heading += turns[i % len(turns)] + (3.0 if i % 5 == 2 else 0.0)
        step = length * (1.0 + 0.3 * math.sin(i * 0.7))
        x += step * math.cos(math.radians(heading))
        y += step * math.sin(math.radians(heading))
        out.append("G1 X%.6f Y%.6f F24000" % (x, y))
    out.append("M2")
    return "\n".join(out) + "\n"


def measure(build, work, case):
    """(planned s, a/amax) of one program, through rs274 and bench_peaks."""
    ngc = os.path.join(work, "p.ngc")
    canon = os.path.join(work, "p.canon")
    with open(ngc, "w") as f:
        f.write(program(*case))
    with open(canon, "w") as f:
        r = subprocess.run(["rs274", "-g", "-t",
                            os.path.join(work, "tools.tbl"), "-v",
                            os.path.join(work, "empty.var"), ngc],
                           stdout=f, stderr=subprocess.PIPE, text=True,
                           # its own HOME: rs274 keeps $HOME/.tool.mmap,
                           # which two at once share and die of (SIGBUS)
                           env=dict(os.environ, HOME=work))
    if r.returncode:    # rs274 says "executing" on stderr every time
        sys.exit("rs274 failed on %s: %s" % (case, r.stderr))
    peaks = os.path.join(build, "bench", "lcnc-compare", "bench_peaks")
    line = subprocess.run([peaks, canon, "0.95"], capture_output=True,
                          text=True, check=True).stdout.split()
    # margin 0.950: planned T s, peak axis v/vmax V, a/amax A (1 servo cycle) ...
    return float(line[3]), float(line[line.index("a/amax") + 1])


def main(argv):
    if len(argv) < 2 or argv[1].startswith("-"):
        sys.exit(__doc__)
    build = argv[1]
    if not shutil.which("rs274"):
        print("rs274 (Debian's linuxcnc-uspace) not found: skipped")
        sys.exit(77)
    cases = QUICK if "--quick" in argv[2:] else [
        (p, th, L, P) for p in PATTERNS for th in THETAS
        for L in LENGTHS for P in TOLERANCES]
    over, worst, total = 0, (0.0, None), 0.0
    with tempfile.TemporaryDirectory() as work:
        for name in ("tools.tbl", "empty.var"):
            open(os.path.join(work, name), "w").close()
        print("pattern theta  L(mm) P(mm)  planned(s)  a/amax")
        for case in cases:
            t, a = measure(build, work, case)
            total += t
            over += a > 1.0
            worst = max(worst, (a, case))
            print("%-7s %5d %6.1f %5s %11.3f  %.4f%s" %
                  (case + (t, a, "  over amax" if a > 1.0 else "")))
    print("%d programs, %d over amax, worst %.4f (%s %d deg %.1f mm P%s), "
          "planned %.3f s in all" % ((len(cases), over, worst[0]) +
                                     worst[1] + (total,)))


if __name__ == "__main__":
    main(sys.argv)
