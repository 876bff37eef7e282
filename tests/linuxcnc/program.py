#!/usr/bin/python3
# SPDX-License-Identifier: GPL-2.0-or-later
"""Headless LinuxCNC session that runs one G-code program to the end on
the sample machine (configs/sh2000-sim) with a card served by sh2000-sim:
the [DISPLAY] program of the test copy of the INI (tests/linuxcnc/run
BUILD program). LinuxCNC's exit code is this script's.

Checks, each printed as "ok ..." or "FAIL ...": machine on, homing, the
program runs to its end (M2) with the machine on and no error from
LinuxCNC, the card ends where the program does, no underrun. Prints the
program's run time, the smallest queue fill and the longest servo period
seen (program.hal). The helpers shared with ui.py are in lcnc.py.

Environment: SH2000_TEST_DEVICE (sim:NAME), SH2000_TEST_CTL (sh2000ctl),
SH2000_TEST_PROGRAM (the G-code file), SH2000_TEST_FEED (feed override,
default 1), SH2000_TEST_TIMEOUT (seconds the program may take, default 120),
SH2000_TEST_COMP (the table file hal_sh2000 loaded at start, if any: the
card's status shows those tables active, before and after the program, and
hal_sh2000's sh2000.0.comp-sum is their sum; with the machine off,
sh2000ctl comp clear and then comp load of the same file from beside
LinuxCNC: sh2000.0.comp-* follow the card within 5 s each time).
"""
import os
import re
import subprocess
import sys
import time

import linuxcnc

from lcnc import (CTL, DEVICE, c, card_pos_at_rest, check, errors, halget,
                  home_all, machine_off, machine_on, mdi, s, session, wait)

PROGRAM = os.environ["SH2000_TEST_PROGRAM"]
FEED = float(os.environ.get("SH2000_TEST_FEED", "1"))
TIMEOUT = float(os.environ.get("SH2000_TEST_TIMEOUT", "120"))
COMP = os.environ.get("SH2000_TEST_COMP", "")
# where the program runs: mid-travel (the card's axes travel 0..600 mm)
ORIGIN = (300.0, 300.0, 300.0)


def program_end():
    """Where the program leaves the tool, in mm of its own coordinates:
    the last X, Y and Z words (G20 programs in inches)."""
    last = {}
    inch = False
    with open(PROGRAM) as f:
        for line in f:
            line = line.split(";")[0].split("(")[0].lower()
            if re.search(r"g20(?!\d)", line):
                inch = True
            if re.search(r"g21(?!\d)", line):
                inch = False
            for axis, v in re.findall(r"([xyz])\s*(-?[\d.]+)", line):
                last[axis] = float(v)
    unit = 25.4 if inch else 1.0
    return [last.get(a, 0.0) * unit for a in "xyz"]


def run_program():
    """Runs PROGRAM at FEED; returns (ran to the end, seconds)."""
    c.mode(linuxcnc.MODE_AUTO)
    c.wait_complete()
    c.program_open(PROGRAM)
    c.wait_complete()
    c.feedrate(FEED)
    for m in ("minmax.0", "minmax.1"):
        subprocess.run(["halcmd", "setp", m + ".reset", "1"], check=True)
        subprocess.run(["halcmd", "setp", m + ".reset", "0"], check=True)
    before = len(errors)
    t0 = time.time()
    print("--   program starts", flush=True)
    c.auto(linuxcnc.AUTO_RUN, 0)
    check("program started", wait(lambda: s.interp_state != linuxcnc.INTERP_IDLE, 5))
    done = wait(lambda: s.interp_state == linuxcnc.INTERP_IDLE or
                s.task_state != linuxcnc.STATE_ON, TIMEOUT)
    took = time.time() - t0
    ok = done and s.task_state == linuxcnc.STATE_ON and len(errors) == before
    return ok, took


def longest_period():
    """minmax.1.max (CPU clocks) in ms, at the CPU's nominal clock rate
    (/proc/cpuinfo's first "cpu MHz"), which the time-stamp counter keeps."""
    clocks = float(halget("minmax.1.max"))
    with open("/proc/cpuinfo") as f:
        for line in f:
            if line.startswith("cpu MHz"):
                return "%.1f ms" % (clocks / float(line.split(":")[1]) / 1000.0)
    return "%g clocks" % clocks


def explain():
    """What the card and hal_sh2000 say after a failed run."""
    for pin in ("ok", "fault", "card-state", "underruns", "queue-fill"):
        print("--   sh2000.0.%s = %s" % (pin, halget("sh2000.0." + pin)), flush=True)
    r = subprocess.run([CTL, "-d", DEVICE, "status"], capture_output=True, text=True)
    for line in (r.stdout + r.stderr).splitlines():
        print("--   " + line, flush=True)


def comp_active(when):
    """The card's tables are COMP's (sh2000ctl comp show FILE), with the
    sum hal_sh2000 shows."""
    r = subprocess.run([CTL, "-d", DEVICE, "comp", "show", COMP],
                       capture_output=True, text=True)
    out = (r.stdout + r.stderr).strip()
    m = re.search(r": sum (0x[0-9a-f]+): the active tables", out)
    check("%s: the card's tables are %s" % (when, os.path.basename(COMP)),
          r.returncode == 0 and m is not None, out.replace("\n", "; "))
    if m:
        hal = int(halget("sh2000.0.comp-sum"), 0)
        check("%s: sh2000.0.comp-sum is their sum" % when, hal == int(m.group(1), 16),
              "%#x, card %s" % (hal, m.group(1)))


def comp_follows():
    """sh2000ctl clears the card's tables and loads them again, from
    beside LinuxCNC (the machine off, the card at rest): hal_sh2000's
    comp-* parameters follow the card (its watch reads them twice a
    second)."""
    def params():
        return tuple(int(halget("sh2000.0.comp-" + p), 0) for p in ("id", "sum", "tables"))

    loaded = params()
    r = subprocess.run([CTL, "-d", DEVICE, "comp", "clear"], capture_output=True, text=True)
    check("sh2000ctl comp clear beside LinuxCNC", r.returncode == 0,
          (r.stdout + r.stderr).strip())
    check("sh2000.0.comp-* show no tables after the clear",
          wait(lambda: params() == (0, 0, 0), 5), "%s" % (params(),))
    r = subprocess.run([CTL, "-d", DEVICE, "comp", "load", COMP], capture_output=True,
                       text=True)
    check("sh2000ctl comp load beside LinuxCNC", r.returncode == 0,
          (r.stdout + r.stderr).strip())
    check("sh2000.0.comp-* show the tables again after the load",
          wait(lambda: params() == loaded, 5), "%s, at start %s" % (params(), loaded))


def run():
    check("LinuxCNC up", wait(lambda: s.task_state != 0, 30))
    if COMP:
        comp_active("at start")
    check("machine on", machine_on())
    if not check("homed all joints", home_all(3, 60), "homed %s" % (s.homed[:3],)):
        return
    # the card at LinuxCNC's HOME (5 mm in every joint): the offset
    # between the card's coordinates and LinuxCNC's, which homing made
    home_card = card_pos_at_rest()
    check("work offset", mdi("G10 L2 P1 X%g Y%g Z%g" % ORIGIN))
    name = os.path.basename(PROGRAM)
    ok, took = run_program()
    s.poll()
    print("--   %s at %g x feed: %.1f s, smallest queue fill %s of %s, longest servo "
          "period %s, underruns %s, delay %s ms" %
          (name, FEED, took, halget("minmax.0.min"), halget("sh2000.0.queue-target"),
           longest_period(), halget("sh2000.0.underruns"), halget("sh2000.0.delay-ms")),
          flush=True)
    if not check("%s ran to its end, machine on, no error from LinuxCNC" % name, ok,
                 "interp %d, task %d, line %d" % (s.interp_state, s.task_state,
                                                 s.motion_line)):
        explain()
    check("no underrun", int(halget("sh2000.0.underruns"), 0) == 0,
          halget("sh2000.0.underruns"))
    end = program_end()
    got = card_pos_at_rest()
    want = [h - 5.0 + o + p for h, o, p in zip(home_card or [0.0] * 3, ORIGIN, end)]
    check("the card ends where %s does" % name,
          got is not None and all(abs(a - b) < 0.001 for a, b in zip(got, want)),
          "card %s, expected %s (card at home %s)" % (got, want, home_card))
    if COMP:
        comp_active("after the program")
        pins = ["sh2000.0.fault"] + ["sh2000.0.%s.amp-fault" % a for a in "xyz"]
        bad = [p for p in pins if halget(p) != "FALSE"]
        check("no card fault, no axis fault", not bad, " ".join(bad))
    c.feedrate(1.0)
    machine_off()
    if COMP:
        comp_follows()


if __name__ == "__main__":
    sys.exit(session(run))
