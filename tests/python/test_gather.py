# SPDX-License-Identifier: MIT
"""Data gathering through the binding: records as numpy arrays agree with
the card's own status and with the motion; triggers now, on motion and on
the emergency stop; parts of a record; the errors (bad names, bad
configurations, a busy record, numpy missing)."""
import errno
import sys

import pytest

import sh2000

try:
    import numpy as np
except ImportError:     # the tests of errors and of numpy missing still run
    np = None
needs_numpy = pytest.mark.skipif(np is None, reason="numpy is not installed")

MOVE = [[0.01 * i, 0, 0, 0] for i in range(1, 51)]     # 0.5 mm in 50 points


@needs_numpy
def test_move_on_motion_trigger_matches_status(card):
    card.enable("x")
    rec = card.gather_start("x", ["setpoint", "encoder", "ferr"], samples=2000,
                            trigger="motion", pretrigger=50)
    card.sleep(0.01)                                # 100 cycles before the move
    card.push(MOVE, end=True)
    card.wait_idle(timeout=5)
    info = card.gather_wait(rec, timeout=5)
    g = card.gather_read(info)
    assert info.triggered and info.trigger_index == 50 and info.samples == 2000
    assert list(g.signals) == ["x.setpoint", "x.encoder", "x.ferr"]
    assert g.units["x.setpoint"] == "counts"
    sp = g["x.setpoint"]
    assert np.all(sp[:50] == 0)                     # at rest before the trigger
    assert np.all(np.diff(sp) >= 0) and sp[60] > 0  # the move goes one way
    st = card.status().axis("x")
    assert sp[-1] == st.cmd_counts                  # where the card says it is
    assert sp[-1] == pytest.approx(0.5 * card.param("x", "scale"), abs=1)
    assert np.abs(g["x.ferr"] - (sp - g["x.encoder"])).max() <= 1
    assert g.t[50] == 0 and g.t[0] == pytest.approx(-50 * info.sample_s)
    assert np.allclose(np.diff(g.t), info.sample_s)


@needs_numpy
def test_trigger_now_every_signal_of_two_axes(card):
    g = card.gather("xy", "all", period=5, samples=20)
    n = len(sh2000.GATHER_SIGNALS)
    assert g.info.values == 2 * n and g.info.period == 5
    assert g.info.trigger == sh2000.GATHER_NOW and g.info.trigger_index == 0
    assert list(g.signals)[n] == "y.setpoint"
    assert all(len(v) == 20 for v in g.signals.values()) and len(g.t) == 20
    assert g.t[0] == 0 and g.t[1] == pytest.approx(g.info.sample_s)
    assert g.info.sample_s == pytest.approx(5 * 1e-4)   # 5 cycles of 100 us
    assert g.units["y.velocity"] == "counts/s"


@needs_numpy
def test_fault_trigger_fires_on_the_emergency_stop(card):
    card.enable("x")
    rec = card.gather_start("x", "dac,ferr", samples=100, trigger="fault", pretrigger=10)
    card.sleep(0.01)
    assert card.gather_info().state == sh2000.GATHER_ARMED     # no fault yet
    card.estop()
    g = card.gather_read(card.gather_wait(rec, timeout=1))
    assert g.info.triggered and g.info.trigger_index == 10 and len(g.t) == 100
    assert g.t[10] == 0 and list(g.signals) == ["x.ferr", "x.dac"]   # bit order
    assert card.status().card_state == sh2000.STATE_ESTOP


@needs_numpy
def test_part_of_a_record_equals_the_whole(card):
    card.enable("x")
    rec = card.gather_start("x", "setpoint", samples=400, trigger="motion")
    card.push(MOVE, end=True)
    info = card.gather_wait(rec, timeout=5)
    whole = card.gather_read(info)
    part = card.gather_read(info, first=100, n=50)
    assert np.array_equal(part["x.setpoint"], whole["x.setpoint"][100:150])
    assert np.array_equal(part.t, whole.t[100:150])
    with pytest.raises(sh2000.Error) as e:
        card.gather_read(info, first=390, n=20)     # beyond the record
    assert e.value.code == errno.EINVAL
    assert "samples 390..410 of a record of 400" in e.value.message
    with pytest.raises(sh2000.Error, match="of a record of 400"):
        card.gather_read(info, first=1, n=2**32 - 1)  # no memory asked for it


@needs_numpy
def test_stopped_record_keeps_what_it_holds(card):
    rec = card.gather_start("z", ["dac"], samples=100, trigger="motion")
    with pytest.raises(sh2000.Error) as e:
        card.gather_start("x", ["dac"])
    assert e.value.code == sh2000.ECMD_BUSY and "stop the gathering first" in e.value.message
    assert card.gather_info().state == sh2000.GATHER_ARMED
    card.gather_stop()
    info = card.gather_info()
    assert info.record == rec and info.state == sh2000.GATHER_DONE
    assert not info.triggered
    assert len(card.gather_read(info)["z.dac"]) == info.samples


@pytest.mark.parametrize("signals, name", [
    (["setpoint", "encodr"], "encodr"),
    ("setpoint,bogus", "bogus"),
    ([""], "''"),
])
def test_bad_signal_name_raises_naming_it(card, signals, name):
    with pytest.raises(sh2000.Error) as e:
        card.gather_start("x", signals)
    assert e.value.code == sh2000.EPARAM
    assert name in e.value.message and "setpoint_vel" in e.value.message
    assert card.gather_info().state == sh2000.GATHER_OFF


@pytest.mark.parametrize("axes, words", [("q", "'q'"), ("xq", "'q'"), (16, "0x10")])
def test_bad_axis_raises_naming_it(card, axes, words):
    with pytest.raises(ValueError, match=words):
        card.gather_start(axes, "setpoint")
    assert card.gather_info().state == sh2000.GATHER_OFF


@pytest.mark.parametrize("kw, words", [
    ({"samples": 9000}, "9000 samples of 4 values"),
    ({"pretrigger": 5}, "pre-trigger 5"),
    ({"period": 0}, "period 0"),
])
def test_bad_configuration_raises_the_library_message(card, kw, words):
    with pytest.raises(sh2000.Error) as e:
        card.gather_start("x", "setpoint,encoder,ferr,dac", **kw)
    assert e.value.code == sh2000.EPARAM and words in e.value.message
    assert card.gather_info().state == sh2000.GATHER_OFF


def test_bad_trigger_and_counts(card):
    with pytest.raises(ValueError, match="'never'"):
        card.gather_start("x", "setpoint", trigger="never")
    with pytest.raises(OverflowError):
        card.gather_start("x", "setpoint", samples=-1)


def test_without_numpy_a_clear_error_and_nothing_armed(card, monkeypatch):
    monkeypatch.setitem(sys.modules, "numpy", None)     # import numpy fails
    before = card.gather_info()
    with pytest.raises(ImportError, match="python3-numpy"):
        card.gather("x", "setpoint")
    with pytest.raises(ImportError, match="python3-numpy"):
        card.gather_start("x", "setpoint", samples=10, trigger="motion")
    assert card.gather_info() == before and before.state == sh2000.GATHER_OFF
    card.enable("x")                                    # the rest works
    card.push(MOVE, end=True)
    card.wait_idle(timeout=5)
    assert card.gather_info() == before                 # nothing was armed
    card.gather_stop()
