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


SOFT = ("x soft limits 50..200 mm would leave axis x (enabled, at 10.0000 mm) outside them: "
        "the card refuses every set-point outside its soft limits, so nothing could move it "
        "back; move it inside first, or give limits around it")


def test_soft_limits_leaving_an_enabled_axis_outside_are_refused(card):
    """The library judges new soft limits against the axis' position
    (sh2000_soft_limits_check()): the binding gets the rule and its words
    through sh2000_param_set and sh2000_axis_params_set, nothing changes."""
    card.set_param("x", "soft_min", -100)
    card.set_param("x", "soft_max", 200)
    card.enable("x")
    card.set_position("x", 10.0)
    before = card.params("x")
    with pytest.raises(sh2000.Error) as e:
        card.set_param("x", "soft_min", 50)
    assert e.value.code == sh2000.EPARAM
    assert str(e.value).endswith(f"axis x parameter soft_min: {SOFT}"), str(e.value)
    with pytest.raises(sh2000.Error) as e:
        card.set_params("x", {"kp": before["kp"] / 2, "soft_min": 50})
    assert e.value.code == sh2000.EPARAM
    assert str(e.value).endswith(f"axis x parameters: {SOFT}"), str(e.value)
    assert card.params("x") == before
    # limits around it are taken
    card.set_param("x", "soft_min", 5)
    assert card.param("x", "soft_min") == 5


@pytest.mark.skipif(not CTL, reason="SH2000CTL names no sh2000ctl")
def test_ctl_gives_the_soft_limit_reason_too(card):
    out = subprocess.run([CTL, "-d", "sim", "params", "x", "soft_min=-100", "soft_max=200",
                          "+", "enable", "x", "+", "move", "x=10",
                          "+", "params", "x", "soft_min=50"],
                         capture_output=True, text=True)
    assert out.returncode == 1
    assert out.stderr.strip().endswith(f"params: {SOFT}"), out.stderr
