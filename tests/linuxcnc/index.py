#!/usr/bin/python3
# SPDX-License-Identifier: GPL-2.0-or-later
"""Headless LinuxCNC session that homes the sample machine (configs/
sh2000-sim) again and again from different starting points: the [DISPLAY]
program of the test copy of the INI (tests/linuxcnc/run BUILD index). The
copy homes joints 0 and 2 (the card's x, z) switch then index, as the
sample does, and joint 1 (y) on the switch alone (HOME_USE_INDEX = NO),
all in the same homings. LinuxCNC's exit code is this script's.

After each homing, at rest, the card's count at LinuxCNC's zero of each
joint (the raw encoder-position minus LinuxCNC's joint.N.pos-fb, in
counts) is one row of SH2000_TEST_RESULTS: "START JOINT MODE COUNTS",
START the card's power-up place (the same for every axis). Before each
homing after the first, the machine moves elsewhere (G53 G0) and every
joint is unhomed. tests/linuxcnc/index-table makes the table of them.

Checks, each printed as "ok ..." or "FAIL ...": machine on, each homing
ends with every joint homed and no error from LinuxCNC, each at rest.

With SH2000_TEST_HOMINGS=0 the card's scale has no marks (the run script
serves it so): one homing, which must fail where LinuxCNC shows it: an
error naming joint 0's amplifier fault and hal_sh2000's reason (no mark
within the sample's index-within), joint 0 not homed.

Environment: SH2000_TEST_DEVICE, SH2000_TEST_CTL (lcnc.py),
SH2000_TEST_RESULTS (the file rows are appended to), SH2000_TEST_START
(the card's power-up place, mm), SH2000_TEST_HOMINGS (how many).
"""
import os
import sys
import time

import hal
import linuxcnc

from lcnc import c, check, errors, halget, machine_on, mdi, results, s, wait

RESULTS = os.environ["SH2000_TEST_RESULTS"]
START = float(os.environ["SH2000_TEST_START"])
HOMINGS = int(os.environ["SH2000_TEST_HOMINGS"])
SCALE = 100000.0        # [SH2000]SCALE of the sample: counts per mm
AXES = "xyz"
MODES = ("index", "switch", "index")    # joints 0, 1, 2 in the test's INI
# a homing takes some 4 s on an idle machine: room for a loaded one
HOME_TIMEOUT = 60


def joint_mode():
    c.mode(linuxcnc.MODE_MANUAL)
    c.wait_complete()
    c.teleop_enable(0)
    c.wait_complete()


def home():
    """Homes every joint at once (HOME_SEQUENCE 0 on all); True when all
    ended homed with the machine on and LinuxCNC said nothing."""
    before = len(errors)
    joint_mode()
    c.home(-1)
    done = wait(lambda: all(s.homed[:3]) or s.task_state != linuxcnc.STATE_ON,
                HOME_TIMEOUT)
    return done and all(s.homed[:3]) and len(errors) == before


def unhome():
    joint_mode()
    c.unhome(-1)
    return wait(lambda: not any(s.homed[:3]), 5)


def zeros():
    """The card's counts at LinuxCNC's zero of each joint: encoder-position
    (the card's raw counter) minus joint.N.pos-fb, in counts (hal.get_value
    works once this process is a HAL component: main)."""
    return [(hal.get_value("sh2000.0.%s.encoder-position" % a) -
             hal.get_value("joint.%d.pos-fb" % j)) * SCALE
            for j, a in enumerate(AXES)]


def zeros_at_rest(timeout=5.0):
    """zeros() once two readings 20 ms apart agree within 0.01 count (the
    card at rest after LinuxCNC's move to HOME); None after timeout."""
    last = None
    end = time.time() + timeout
    while time.time() < end:
        now = zeros()
        if last and all(abs(a - b) < 0.01 for a, b in zip(now, last)):
            return now
        last = now
        time.sleep(0.02)
    return None


def card_says():
    """hal_sh2000's counters after a failed homing: a ring that ran dry
    (an underrun) stalls the card, which LinuxCNC sees as a following
    error like any other."""
    return "; hal_sh2000: underruns %s, queue-fill %s, delay-ms %s" % tuple(
        halget("sh2000.0." + pin) for pin in ("underruns", "queue-fill", "delay-ms"))


def somewhere(i):
    """Where homing i starts, in machine coordinates (mm): spread over
    some 30 mm beyond the switch, different for each axis and homing."""
    return [2.0 + (7.31 * i + 3.17 * j) % 30.0 for j in range(3)]


def no_mark():
    """One homing on a scale without marks: LinuxCNC must show the error."""
    joint_mode()
    c.home(-1)
    why = "x: index-enable: no index mark within the arm's travel"
    # LinuxCNC queues its own "joint 0 amplifier fault" after hal_sh2000's
    # message and may turn the machine off before it arrives: wait for all
    # three, each checked below
    wait(lambda: any(why in m for m in errors) and
         any("amplifier fault" in m and "joint 0" in m for m in errors) and
         s.task_state != linuxcnc.STATE_ON, HOME_TIMEOUT)
    check("no mark: LinuxCNC shows joint 0's amplifier fault",
          any("amplifier fault" in m and "joint 0" in m for m in errors),
          "; ".join(errors[-3:]))
    check("no mark: LinuxCNC shows hal_sh2000's reason", any(why in m for m in errors),
          "; ".join(errors[-3:]))
    check("no mark: joint 0 not homed, machine off",
          not s.homed[0] and s.task_state != linuxcnc.STATE_ON,
          "homed %s, task state %d" % (s.homed[:3], s.task_state))


def run():
    check("LinuxCNC up", wait(lambda: s.task_state != 0, 30))
    if not check("machine on", machine_on()):
        return
    if HOMINGS == 0:
        no_mark()
        return
    for i in range(HOMINGS):
        if i > 0:
            where = somewhere(i)
            if not check("homing %d: G53 G0 to %s" % (i + 1, where),
                         mdi("G53 G0 X%.4f Y%.4f Z%.4f" % tuple(where))):
                return
            if not check("homing %d: unhomed" % (i + 1), unhome()):
                return
        homed = home()
        if not check("homing %d: every joint homed, no error" % (i + 1), homed,
                     "" if homed else
                     "homed %s, task state %d; %s%s" % (s.homed[:3], s.task_state,
                                                        "; ".join(errors[-2:]),
                                                        card_says())):
            return
        z = zeros_at_rest()
        if not check("homing %d: at rest" % (i + 1), z is not None):
            return
        print("--   homing %d (card powered up at %g mm): LinuxCNC's zero at the card's "
              "counts %s" % (i + 1, START, " ".join("%s %.2f" % (a, v) for a, v in zip(AXES, z))),
              flush=True)
        with open(RESULTS, "a") as f:
            for j, v in enumerate(z):
                f.write("%g %d %s %.3f\n" % (START, j, MODES[j], v))
    c.state(linuxcnc.STATE_OFF)
    wait(lambda: s.task_state == linuxcnc.STATE_OFF, 2)


def main():
    comp = hal.component("sh2000-index-test")
    comp.ready()
    try:
        run()
    finally:
        comp.exit()
        print("%d passed, %d failed" % (results["passed"], results["failed"]), flush=True)
    return 1 if results["failed"] else 0


if __name__ == "__main__":
    sys.exit(main())
