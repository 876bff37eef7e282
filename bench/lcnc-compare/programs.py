#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""The programs of the LinuxCNC comparison, written into a directory as
both planners run them (the same file on both sides).

LinuxCNC's own examples (ncfiles of Debian's linuxcnc-uspace) are copied
with the changes the benchmark needs, each said in the copy's first
comment: feeds set as the comparison measures them and a G64 P where the
program has no path mode of its own (so that both blend within the same
tolerance). Their tool words (T1 M6, G43 H1) stay: both sides read the
tool table TOOL_TABLE, which programs.py writes beside the programs (tool
1, no length, so the path is the program's). The others are generated.

    programs.py OUTDIR [NAME...]        (default: every program but "tiny")

prints one line per program: NAME FILE "DESCRIPTION".
"""
import math
import os
import re
import subprocess
import sys

NCFILES = "/usr/share/linuxcnc/ncfiles"
HERE = os.path.dirname(os.path.abspath(__file__))


def code_sub(text, pattern, repl):
    """re.sub on the code of each line, never inside ( ) comments."""
    out = []
    for line in text.splitlines():
        parts = re.split(r"(\([^)]*\)?)", line)
        for i in range(0, len(parts), 2):
            parts[i] = re.sub(pattern, repl, parts[i], flags=re.I)
        out.append("".join(parts))
    return "\n".join(out) + "\n"


def ncfile(name):
    path = os.path.join(NCFILES, name)
    if not os.path.exists(path):
        raise FileNotFoundError("%s: not installed (Debian's linuxcnc-uspace ships it)" % path)
    with open(path) as f:
        return f.read()


def arcspiral():
    # 1000 near-tangent arcs under the program's own G64 (no P: both
    # planners blend as wide as the moves allow); its F24 in/min made 480
    text = code_sub(ncfile("arcspiral.ngc"), r"F\s*[-+]?[0-9.]+", "F480")
    return "(bench copy of ncfiles/arcspiral.ngc: every F set to 480 in/min)\n" + text


def chips():
    # 4681 short moves under the program's G64 P0.1, its feeds far above
    # the axes' limits (fscale 10000); as written
    return "(bench copy of ncfiles/3D_Chips.ngc, as written)\n" + ncfile("3D_Chips.ngc")


def cds():
    # a pocket of lines and arcs; no path mode of its own: G64 P0.01 mm
    # set before the program's G20 so that both blend within 0.01 mm
    text = code_sub(ncfile("cds.ngc"), r"F\s*[-+]?[0-9.]+", "F600")
    return ("(bench copy of ncfiles/cds.ngc: every F set to 600 in/min, "
            "G64 P0.01 mm set first)\nG21 G64 P0.01\n" + text)


def surface():
    # the CAM surfacing program of bench/upload (10^5 G1 of 0.05 mm, F3000,
    # G64 P0.01)
    return subprocess.run([sys.executable, os.path.join(HERE, "..", "upload", "make_surface.py"),
                           "100000"], check=True, capture_output=True, text=True).stdout


def pocket():
    """Eight loops inwards of a 80 x 60 mm pocket whose short sides are
    arcs of 60 degrees bulging outwards: every corner joins a line and an
    arc 30 degrees off tangent. G64 P0.01, F12000."""
    w, h, step = 80.0, 60.0, 2.0
    out = ["(pocket: lines and arcs meeting 30 degrees off tangent)",
           "G21 G90 G17 G64 P0.01", "G0 X0 Y0 Z0", "F12000"]
    for k in range(8):
        d = k * step
        r = h - 2 * d                   # chord = radius: a 60 degree arc
        if k:
            out.append("G1 X%.4f Y%.4f" % (d, d))
        out += ["G1 X%.4f Y%.4f" % (w - d, d),
                "G3 X%.4f Y%.4f R%.4f" % (w - d, h - d, r),
                "G1 X%.4f Y%.4f" % (d, h - d),
                "G3 X%.4f Y%.4f R%.4f" % (d, d, r)]
    out.append("M2")
    return "\n".join(out) + "\n"


def square():
    # a 20 mm square twice round under G61 at F6000
    corners = ["X20 Y0", "X20 Y20", "X0 Y20", "X0 Y0"] * 2
    return ("(20 mm square twice round, G61)\nG21 G90 G17 G61\nG0 X0 Y0 Z0\nF6000\n" +
            "".join("G1 %s\n" % c for c in corners) + "M2\n")


def tiny():
    # the smoke test's program: a line, a corner, an arc, back; half a second
    return ("(tiny: smoke test of the comparison)\nG21 G90 G17 G64 P0.01\nF6000\n"
            "G1 X10\nG1 Y5\nG2 X15 Y10 R5\nG1 X0 Y0\nM2\n")


# The tool table both sides read (LinuxCNC's format; lengths in machine
# units, mm): the tool the ncfiles programs call, with no length.
TOOL_TABLE = "tools.tbl"
TOOLS = "T1 P1 Z0 D3.175 ;bench tool: 1/8 in, no length\n"


PROGRAMS = [
    ("arcspiral", arcspiral, "ncfiles arcspiral.ngc, F480 in/min, G64"),
    ("3D_Chips", chips, "ncfiles 3D_Chips.ngc, G64 P0.1"),
    ("cds", cds, "ncfiles cds.ngc, F600 in/min, G64 P0.01"),
    ("surface", surface, "CAM surfacing, 10^5 G1, F3000, G64 P0.01"),
    ("pocket", pocket, "line-arc pocket, F12000, G64 P0.01"),
    ("square", square, "20 mm square x2, F6000, G61"),
    ("tiny", tiny, "smoke test: line, corner, arc"),
]


def main():
    outdir = sys.argv[1]
    names = sys.argv[2:] or [p[0] for p in PROGRAMS if p[0] != "tiny"]
    table = {p[0]: p for p in PROGRAMS}
    with open(os.path.join(outdir, TOOL_TABLE), "w") as f:
        f.write(TOOLS)
    for name in names:
        if name not in table:
            sys.exit("programs.py: unknown program %s (known: %s)" %
                     (name, " ".join(table)))
        _, make, what = table[name]
        path = os.path.join(outdir, name + ".ngc")
        try:
            text = make()
        except FileNotFoundError as e:
            print("programs.py: %s: %s" % (name, e), file=sys.stderr)
            continue
        with open(path, "w") as f:
            f.write(text)
        print("%s %s %s" % (name, path, what))


if __name__ == "__main__":
    main()
