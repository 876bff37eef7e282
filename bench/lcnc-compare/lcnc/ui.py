#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""The DISPLAY of the comparison's LinuxCNC (bench.ini): machine on, homed
in place, then each program in turn from X0 Y0 Z0, with the HAL signal
`marker` set to the program's number while it runs, and exit (LinuxCNC's
exit code is this script's). halsampler writes the recording.

Environment: BENCH_PROGRAMS (the G-code files, separated by ':'),
BENCH_SAMPLES (halsampler's output file). Prints one line per program:
"ran N FILE" or "FAILED N FILE: why".
"""
import os
import subprocess
import sys
import time

import linuxcnc

PROGRAMS = os.environ["BENCH_PROGRAMS"].split(":")
SAMPLES = os.environ["BENCH_SAMPLES"]
TIMEOUT = 900          # the longest program runs about 2 minutes

s = linuxcnc.stat()
c = linuxcnc.command()
e = linuxcnc.error_channel()


def poll():
    """s.poll(), retried: the status buffer is now and then caught while
    task writes it ("emcStatusBuffer invalid")."""
    for _ in range(50):
        try:
            s.poll()
            return
        except linuxcnc.error:
            time.sleep(0.01)
    s.poll()


def wait(cond, timeout):
    end = time.time() + timeout
    while time.time() < end:
        poll()
        m = e.poll()
        if m:
            print("--   linuxcnc: " + m[1].strip(), flush=True)
        if cond():
            return True
        time.sleep(0.02)
    poll()
    return cond()


def marker(n):
    subprocess.run(["halcmd", "sets", "marker", str(n)], check=True)


def idle():
    return (s.interp_state == linuxcnc.INTERP_IDLE and s.queue == 0 and
            s.inpos and s.state == linuxcnc.RCS_DONE)


def machine_on():
    c.state(linuxcnc.STATE_ESTOP_RESET)
    wait(lambda: s.task_state == linuxcnc.STATE_ESTOP_RESET, 5)
    c.state(linuxcnc.STATE_ON)
    if not wait(lambda: s.task_state == linuxcnc.STATE_ON, 5):
        return False
    c.mode(linuxcnc.MODE_MANUAL)
    c.wait_complete()
    c.teleop_enable(0)
    c.wait_complete()
    c.home(-1)
    return wait(lambda: all(s.homed[:3]), 30)


def mdi(cmd):
    c.mode(linuxcnc.MODE_MDI)
    c.wait_complete()
    c.mdi(cmd)
    return wait(lambda: s.task_state != linuxcnc.STATE_ON or idle(), 60) and \
        s.task_state == linuxcnc.STATE_ON


def run_program(n, path):
    """Program n from X0 Y0 Z0 (machine coordinates) with marker n."""
    if not mdi("G21 G90 G53 G0 X0 Y0 Z0"):
        return "cannot return to X0 Y0 Z0"
    c.mode(linuxcnc.MODE_AUTO)
    c.wait_complete()
    c.program_open(path)
    c.wait_complete()
    marker(n)
    time.sleep(0.05)
    c.auto(linuxcnc.AUTO_RUN, 0)
    if not wait(lambda: s.interp_state != linuxcnc.INTERP_IDLE, 10):
        marker(0)
        return "did not start"
    done = wait(lambda: s.task_state != linuxcnc.STATE_ON or idle(), TIMEOUT)
    time.sleep(0.1)
    marker(0)
    if not done or s.task_state != linuxcnc.STATE_ON:
        return "did not end within %d s (task state %d)" % (TIMEOUT, s.task_state)
    return None


def main():
    if not wait(lambda: s.task_state != 0, 30):
        print("FAILED LinuxCNC did not come up", flush=True)
        return 1
    if not machine_on():
        print("FAILED machine on and homed", flush=True)
        return 1
    sampler = subprocess.Popen(["halsampler", "-t"], stdout=open(SAMPLES, "w"))
    failed = 0
    try:
        for n, path in enumerate(PROGRAMS, 1):
            why = run_program(n, path)
            print(("ran %d %s" % (n, path)) if why is None else
                  ("FAILED %d %s: %s" % (n, path, why)), flush=True)
            failed += why is not None
            if why is not None and not machine_on():
                break
        time.sleep(0.2)
    finally:
        sampler.terminate()
        sampler.wait()
    c.state(linuxcnc.STATE_OFF)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
