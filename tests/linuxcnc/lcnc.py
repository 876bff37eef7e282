# SPDX-License-Identifier: GPL-2.0-or-later
"""What the headless LinuxCNC sessions of the LinuxCNC stage share
(tests/linuxcnc/ui.py, tests/linuxcnc/program.py): LinuxCNC's channels,
"ok"/"FAIL" checks, waiting for a state with a bound, HAL pins, the card
beside LinuxCNC through sh2000ctl, machine on, MDI.

Environment: SH2000_TEST_DEVICE (sim:NAME), SH2000_TEST_CTL (sh2000ctl).
"""
import json
import os
import subprocess
import time

import linuxcnc

DEVICE = os.environ["SH2000_TEST_DEVICE"]
CTL = os.environ["SH2000_TEST_CTL"]

s = linuxcnc.stat()
c = linuxcnc.command()
e = linuxcnc.error_channel()
results = {"passed": 0, "failed": 0}
errors = []


def check(what, cond, detail=""):
    key = "passed" if cond else "failed"
    results[key] += 1
    print(("ok   " if cond else "FAIL ") + what + (": " + detail if detail else ""),
          flush=True)
    return cond


def drain_errors():
    while True:
        m = e.poll()
        if not m:
            return
        errors.append(m[1])
        print("--   linuxcnc: " + m[1].strip(), flush=True)


def wait(cond, timeout):
    end = time.time() + timeout
    while time.time() < end:
        s.poll()
        drain_errors()
        if cond():
            return True
        time.sleep(0.02)
    s.poll()
    return cond()


def halget(pin):
    out = subprocess.run(["halcmd", "-s", "getp", pin], capture_output=True,
                         text=True, check=True).stdout.strip()
    return out


def halset(sig, value):
    subprocess.run(["halcmd", "sets", sig, str(value)], check=True)


def card_status():
    r = subprocess.run([CTL, "-d", DEVICE, "status", "--json"],
                       capture_output=True, text=True)
    return r.returncode, r.stdout, r.stderr


def card_pos():
    """The card's x, y, z encoder positions (its own coordinates)."""
    rc, out, _ = card_status()
    if rc not in (0, 4) or not out:
        return None
    return [a["pos_mm"] for a in json.loads(out.splitlines()[-1])["axes"]][:3]


def card_pos_at_rest(timeout=3.0):
    """The card's position once it has stopped moving: LinuxCNC calls a
    move done on position-fb, while the card model (its own process) may
    still be playing the last queued periods on a loaded machine. Two
    readings 0.1 s apart within 0.1 um; the last reading after timeout."""
    end = time.time() + timeout
    last = card_pos()
    while time.time() < end:
        time.sleep(0.1)
        pos = card_pos()
        if pos and last and all(abs(a - b) < 1e-4 for a, b in zip(pos, last)):
            return pos
        last = pos
    return last


def machine_on():
    """estop reset (twice if the card had to be reset first), then on."""
    for _ in range(3):
        c.state(linuxcnc.STATE_ESTOP_RESET)
        if wait(lambda: s.task_state == linuxcnc.STATE_ESTOP_RESET, 1.0):
            break
        time.sleep(0.2)
    c.state(linuxcnc.STATE_ON)
    return wait(lambda: s.task_state == linuxcnc.STATE_ON, 2.0)


def mdi(cmd, timeout=60):
    s.poll()
    if s.task_state != linuxcnc.STATE_ON:
        return False
    c.mode(linuxcnc.MODE_MDI)
    c.wait_complete()
    c.mdi(cmd)
    return wait(lambda: s.task_state != linuxcnc.STATE_ON or
                (s.interp_state == linuxcnc.INTERP_IDLE and
                 s.state == linuxcnc.RCS_DONE), timeout) and s.task_state == linuxcnc.STATE_ON


def home_all(joints, timeout):
    """LinuxCNC homes every joint (in its HOME_SEQUENCE order): whether
    the first `joints` joints are homed within timeout seconds, the
    machine on."""
    c.mode(linuxcnc.MODE_MANUAL)
    c.wait_complete()
    c.teleop_enable(0)
    c.wait_complete()
    c.home(-1)
    return wait(lambda: all(s.homed[:joints]) or s.task_state != linuxcnc.STATE_ON,
                timeout) and all(s.homed[:joints])


def machine_off():
    c.state(linuxcnc.STATE_OFF)
    wait(lambda: s.task_state == linuxcnc.STATE_OFF, 2)


def session(run):
    """Runs a session's checks (run), then prints the tally, also when a
    check raised; the session's exit code."""
    try:
        run()
    finally:
        print("%d passed, %d failed" % (results["passed"], results["failed"]), flush=True)
    return 1 if results["failed"] else 0
