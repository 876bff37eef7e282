#!/usr/bin/python3
# SPDX-License-Identifier: GPL-2.0-or-later
"""Headless LinuxCNC session on the gantry (configs/sh2000-gantry: X Y1 Y2
Z, trivkins XYYZ) with a card served by `sh2000-sim --gantry y+z`: the
[DISPLAY] program of the test copy of the INI (tests/linuxcnc/gantry).
LinuxCNC's exit code is this script's.

Checks, each printed as "ok ..." or "FAIL ...": the card has the pair
(sh2000.hal loaded gantry.params), machine on, LinuxCNC homes all four
joints (Z, X, then Y1 and Y2 together, each on its own switch and then
its own scale's index mark) and the beam ends square (the two sides'
encoders agree); each side's zero is its own mark (the card's raw count
at LinuxCNC's zero of joints 1 and 2 is a mark's, every 1 mm, to a
count, and the same for both sides: the simulated marks agree; homed
again from elsewhere, on the same mark to a count); then the beam moves
200 mm and back (G0 Y at 200 mm/s, 2000 mm/s^2) with the carriage (X) at
side y's end: each move's peak skew (gantry.hal: the difference of the
sides' following errors as the card reports them every servo period)
stays under the card's skew limit, the card reports no fault, LinuxCNC
stays on and the sides end together. (Uncoupled, the same move trips
LinuxCNC's following-error limit on the light side: the coupling's cut
is measured by tool_tune_gantry and cardmodel_gantry.)

Environment: SH2000_TEST_DEVICE (sim:NAME), SH2000_TEST_CTL (sh2000ctl).
"""
import json
import subprocess
import sys
import time

import linuxcnc

from lcnc import (c, card_pos_at_rest, card_status, check, errors, halget,
                  home_all, machine_off, machine_on, mdi, s, session, wait)

BEAM_MOVE = 200.0   # mm of Y, at LinuxCNC's 200 mm/s and 2000 mm/s^2
SCALE = 100000      # counts per mm
MARK = 100000       # counts between the simulated scales' index marks


def pair_zeros():
    """The card's raw counts at LinuxCNC's zero of joints 1 and 2 (sides
    y and z): encoder-position minus joint.N.pos-fb, once two readings
    0.1 s apart agree within 0.01 count (at rest); None after 5 s."""
    last = None
    for _ in range(50):
        now = [(float(halget("sh2000.0.%s.encoder-position" % a)) -
                float(halget("joint.%d.pos-fb" % j))) * SCALE
               for j, a in ((1, "y"), (2, "z"))]
        if last and all(abs(a - b) < 0.01 for a, b in zip(now, last)):
            return now
        last = now
        time.sleep(0.1)
    return None


def gantry():
    """The card's gantry pair as sh2000ctl status --json has it (None
    without one, or when the card cannot be read)."""
    rc, out, _ = card_status()
    if rc not in (0, 4) or not out:
        return None
    return json.loads(out.splitlines()[-1]).get("gantry")


def card_ok():
    """The card answers and has nothing latched: (ok, what it says)."""
    rc, _, err = card_status()
    return rc == 0, "" if rc == 0 else "exit %d: %s" % (rc, err.strip())


def explain():
    """What the card and hal_sh2000 say after a failure."""
    for pin in ("ok", "fault", "card-state", "underruns"):
        print("--   sh2000.0.%s = %s" % (pin, halget("sh2000.0." + pin)), flush=True)
    rc, out, err = card_status()
    print("--   sh2000ctl status: exit %d %s %s" % (rc, err.strip(), out.strip()[-400:]),
          flush=True)


def beam_move(y):
    """G0 of the beam to Y y; the move's peak skew in mm (minmax.0, reset
    just before), or None when the move did not end with the machine on."""
    subprocess.run(["halcmd", "setp", "minmax.0.reset", "1"], check=True)
    subprocess.run(["halcmd", "setp", "minmax.0.reset", "0"], check=True)
    before = len(errors)
    if not mdi("G0 Y%g" % y) or len(errors) != before:
        return None
    return float(halget("minmax.0.max"))


def home_again(first):
    """The beam and carriage elsewhere (G53 G0), every joint unhomed, the
    four homed again: the pair's zeros those of the first homing (first)
    to a count."""
    if not check("G53 G0 elsewhere before homing again",
                 mdi("G53 G0 X%.4f Y%.4f" % (23.71, 37.13))):
        return
    c.mode(linuxcnc.MODE_MANUAL)
    c.wait_complete()
    c.teleop_enable(0)
    c.wait_complete()
    c.unhome(-1)
    if not check("unhomed", wait(lambda: not any(s.homed[:4]), 5),
                 "homed %s" % (s.homed[:4],)):
        return
    if not check("homed all four joints again", home_all(4, 120),
                 "homed %s, task state %d" % (s.homed[:4], s.task_state)):
        explain()
        return
    z = pair_zeros()
    print("--   homed again: LinuxCNC's zero of Y1 and Y2 at the card's counts %s" % z,
          flush=True)
    check("homed again: Y1 and Y2 on the same marks as before (within 1 count)",
          z is not None and first is not None and
          all(abs(a - b) <= 1 for a, b in zip(z, first)), "%s, before %s" % (z, first))


def run():
    check("LinuxCNC up", wait(lambda: s.task_state != 0, 30))
    g = gantry()
    check("the card's gantry pair y+z from gantry.params",
          g is not None and g["axes"] == ["y", "z"] and g["kp"] == 5,
          "" if g and g["axes"] == ["y", "z"] else json.dumps(g))
    limit_mm = g["skew_limit_counts"] / 1e5 if g else 0.2
    check("machine on", machine_on())
    if not check("homed all four joints (the pair together)", home_all(4, 120),
                 "homed %s, task state %d" % (s.homed[:4], s.task_state)):
        explain()
        return
    pos = card_pos_at_rest()
    check("the beam square after homing (sides y and z within 5 um)",
          pos is not None and abs(pos[1] - pos[2]) < 0.005, "card x y z %s" % pos)
    z = pair_zeros()
    print("--   LinuxCNC's zero of Y1 and Y2 at the card's counts %s" % z, flush=True)
    check("Y1 and Y2 homed on their index marks (zeros within 1 count of a mark)",
          z is not None and all(abs(v - MARK * round(v / MARK)) <= 1 for v in z),
          "%s counts" % z)
    check("Y1 and Y2 on the same mark (zeros within 1 count of each other)",
          z is not None and abs(z[0] - z[1]) <= 1, "%s counts" % z)
    first = z
    ok, said = card_ok()
    check("no fault on the card after homing", ok, said)
    # X is homed at side y's end of the beam (5 mm from its switch): the
    # carriage loads side y, the beam yaws under acceleration
    peaks = []
    for y in (5.0 + BEAM_MOVE, 5.0):
        peaks.append(beam_move(y))
        check("G0 Y%g: peak skew under the limit" % y,
              peaks[-1] is not None and peaks[-1] < limit_mm,
              "%s mm, limit %g mm" % (peaks[-1], limit_mm))
    print("--   the beam's 200 mm G0 out and back with the carriage at side y: "
          "peak skew %s mm" % peaks, flush=True)
    # a card without the beam (sh2000-sim without --gantry: four identical
    # axes on one set-point) has no skew to speak of
    check("the beam yaws: a peak skew above 20 counts each way",
          all(p is not None and p > 0.0002 for p in peaks), "%s mm" % peaks)
    ok, said = card_ok()
    check("no fault on the card after the moves", ok, said)
    s.poll()
    check("LinuxCNC still on", s.task_state == linuxcnc.STATE_ON,
          "task state %d" % s.task_state)
    pos = card_pos_at_rest()
    check("both sides back together (within 5 um)",
          pos is not None and abs(pos[1] - pos[2]) < 0.005, "card x y z %s" % pos)
    home_again(first)
    ok, said = card_ok()
    check("no fault on the card after homing again", ok, said)
    machine_off()


if __name__ == "__main__":
    sys.exit(session(run))
