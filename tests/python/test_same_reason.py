# SPDX-License-Identifier: MIT
"""One rule, one wording: a value the card cannot take is refused by
sh2000ctl and by the binding (through libsh2000) with the same reason,
which the protocol table and sh2000_param_value_check() own, and nothing
is set."""
import os
import subprocess

import pytest

import sh2000

CTL = os.environ.get("SH2000CTL")

CASES = [
    ("x", "kp", "-1", "-1 DAC/count is outside 0..1000 DAC/count"),
    ("x", "vmax", "-1", "-1 mm/s is outside (exclusive) 0..10000 mm/s"),
    ("y", "dac_range", "2.5", "2.5 is not an integer"),
    ("z", "kaff", "1e-50", "1e-50 DAC/(count/s^2) does not fit a 32-bit float in card units"),
    ("global", "time_scale", "20000", "20000 1/10000 of full rate is outside 0..10000 1/10000 of full rate"),
]


@pytest.mark.skipif(not CTL, reason="SH2000CTL names no sh2000ctl")
@pytest.mark.parametrize("axis,name,value,reason", CASES)
def test_ctl_and_binding_give_the_same_reason(card, axis, name, value, reason):
    before = card.param(axis, name)
    with pytest.raises(sh2000.Error) as e:
        card.set_param(axis, name, float(value))
    assert e.value.code == sh2000.EPARAM
    assert str(e.value).endswith(f"parameter {name}: {reason}")
    out = subprocess.run([CTL, "-d", "sim", "params", axis, f"{name}={value}"],
                         capture_output=True, text=True)
    assert out.returncode == 1
    assert out.stderr.strip().endswith(f"{axis} {name}: {reason}" if axis != "global"
                                       else f"{name}: {reason}"), out.stderr
    assert card.param(axis, name) == before
