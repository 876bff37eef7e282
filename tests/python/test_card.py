# SPDX-License-Identifier: MIT
"""sh2000.Card on the simulated card: open, status, parameters by name,
commands, pushed points."""
import errno
import math

import pytest

import sh2000


def test_open_sim(card):
    assert card.device == "sim"
    assert card.backend == "sim"
    assert card.card_protocol == sh2000.PROTOCOL
    assert card.queue_size > 0


@pytest.mark.parametrize("device, code, words", [
    ("io:0x301", errno.EINVAL, "io:0x301: base 0x301 invalid"),
    ("sim:no-such-card", errno.ENOENT, "sim:no-such-card"),
])
def test_open_bad_device_raises_with_code_and_message(device, code, words):
    with pytest.raises(sh2000.Error) as e:
        sh2000.open(device)
    assert e.value.code == code
    assert e.value.name == sh2000.strerror(code)
    assert words in e.value.message


def test_status_fields(card):
    st = card.status()
    assert st.card_state == sh2000.STATE_IDLE
    assert st.card_state_name == "idle"
    assert st.fault is None and st.card_faults == 0 and not st.faulted
    assert st.queue_fill == 0 and st.queue_free == card.queue_size
    assert len(st.axes) == sh2000.AXES
    x = st.axis("x")
    assert x is st.axes[0] and not x.enabled and x.faults == 0
    with pytest.raises(Exception):
        st.card_state = 0       # a frozen dataclass
    card.sleep(0.01)                            # virtual time: 0.01 s passes
    later = card.status()
    assert later.card_cycle > st.card_cycle


def test_param_get_set_by_name(card):
    card.set_param("y", "kp", 0.75)
    assert card.param("y", "kp") == pytest.approx(0.75, rel=1e-6)
    assert card.param(1, "kp") == card.param("Y", "kp")
    assert card.param("x", "kp") != pytest.approx(0.75)     # one axis only
    card.set_param(None, "host_timeout_ms", 250)
    assert card.param("global", "host_timeout_ms") == 250
    assert card.params("y")["kp"] == pytest.approx(0.75, rel=1e-6)
    assert set(card.params(None)) >= {"coarse_period_us", "host_timeout_ms"}
    assert sh2000.UNITS["vmax"] == "mm/s"


def test_bad_parameter_name_raises(card):
    with pytest.raises(sh2000.Error) as e:
        card.param("x", "kpp")
    assert e.value.code == sh2000.EPARAM
    assert "kpp" in e.value.message


@pytest.mark.parametrize("axis, name, value, words", [
    ("x", "kp", -1, "axis x parameter kp: -1 DAC/count is outside 0..1000 DAC/count"),
    ("x", "vmax", math.nan, "is not a finite number"),
    ("x", "host_timeout_ms", 10, "a global parameter"),
    (None, "kp", 1, "needs an axis"),
])
def test_bad_parameter_value_raises_with_library_message(card, axis, name, value, words):
    before = card.params("x")
    with pytest.raises(sh2000.Error) as e:
        card.set_param(axis, name, value)
    assert e.value.code == sh2000.EPARAM
    assert words in e.value.message
    assert card.params("x") == before


def test_set_params_is_all_or_nothing(card):
    before = card.params("z")
    with pytest.raises(sh2000.Error) as e:
        card.set_params("z", {"kp": 0.9, "vmax": -5})
    assert e.value.code == sh2000.EPARAM
    assert card.params("z") == before
    card.set_params("z", {"kp": 0.9, "vmax": 250})
    after = card.params("z")
    assert after["kp"] == pytest.approx(0.9, rel=1e-6) and after["vmax"] == 250


def test_bad_axis_is_a_value_error(card):
    with pytest.raises(ValueError):
        card.param("w", "kp")
    with pytest.raises(ValueError):
        card.enable("xq")


@pytest.mark.parametrize("call", [
    lambda c: c.enable(""), lambda c: c.disable([]), lambda c: c.enable(0),
    lambda c: c.gather_start("", "setpoint"),
])
def test_no_axis_is_a_value_error(card, call):
    with pytest.raises(ValueError, match="no axis"):
        call(card)
    assert card.gather_info().state == sh2000.GATHER_OFF


@pytest.mark.parametrize("call, words", [
    (lambda c: c.sleep(-1), "sleep -1"),
    (lambda c: c.sleep(math.nan), "sleep nan"),
    (lambda c: c.wait_idle(timeout=-1), "timeout -1"),
    (lambda c: c.wait_rest(timeout=-0.001), "timeout -0.001"),
    (lambda c: c.wait_space(1, timeout=-1), "timeout -1"),
    (lambda c: c.estop(timeout=-1), "timeout -1"),
    (lambda c: c.home("x", timeout=-5), "timeout -5"),
    (lambda c: c.gather_wait(1, timeout=-1), "timeout -1"),
])
def test_negative_time_is_a_value_error(card, call, words):
    """None is "no limit"; a negative time is a mistake, refused before
    the library is asked (whose negative timeout would mean no limit)."""
    with pytest.raises(ValueError, match=words):
        call(card)
    st = card.status()
    assert st.card_state == sh2000.STATE_IDLE and not st.axis("x").homed
    card.sleep(0)                                   # 0 is a time
    card.wait_idle(timeout=0)


@pytest.mark.parametrize("call", [
    lambda c: c.set_param("x", "kp", True),
    lambda c: c.set_param("x", "kp", "0.5"),
    lambda c: c.set_params("x", {"kp": False}),
    lambda c: c.set_position("x", True),
    lambda c: c.sleep(True),
    lambda c: c.wait_idle(timeout="1"),
])
def test_a_bool_or_text_is_not_a_number(card, call):
    before = card.params("x")
    with pytest.raises(TypeError, match="not a number"):
        call(card)
    assert card.params("x") == before and card.status().axis("x").pos_mm == 0


def test_enable_estop_reset(card):
    card.enable("xz")
    st = card.status()
    assert [a.enabled for a in st.axes] == [True, False, True, False]
    card.estop()
    st = card.status()
    assert st.card_state_name == "estop"
    assert isinstance(st.fault, sh2000.Error) and st.fault.code == sh2000.EESTOP
    assert st.fault.message.endswith("; a reset clears it")   # no C name
    assert st.faulted
    ff = st.first_fault     # protocol 1.4: the card's first-fault record
    assert isinstance(ff, sh2000.FirstFault)
    assert ff.axis is None and ff.bit == st.card_faults     # the only one
    assert ff.name == "emergency stop" and 0 < ff.cycle <= st.card_cycle + 10
    with pytest.raises(sh2000.Error) as e:
        card.enable("y")
    assert e.value.code == sh2000.ECMD_FAULTED
    card.reset()
    st = card.status()
    assert st.card_state == sh2000.STATE_IDLE and st.fault is None
    assert not st.faulted and st.first_fault is None
    card.disable("all")
    assert not any(a.enabled for a in card.status().axes)


def _ramp(start, distance, n):
    """n coarse points from start to start + distance on x, smooth."""
    return [[start + distance * (1 - math.cos(math.pi * i / n)) / 2, 0, 0, 0]
            for i in range(1, n + 1)]


def test_push_points_moves_the_card(card):
    card.enable("x")
    x0 = card.status().axis("x").pos_mm
    assert card.push(_ramp(x0, 1.0, 60), end=True) == 60
    card.wait_idle(timeout=5)
    x = card.status().axis("x")
    assert x.pos_mm == pytest.approx(x0 + 1.0, abs=0.001)
    assert x.cmd_mm == pytest.approx(x0 + 1.0, abs=1e-5)


def test_stop_then_wait_rest(card):
    # a stop mid-motion: the card brakes, and wait_rest returns once it
    # no longer moves, short of where the points went
    card.enable("x")
    x0 = card.status().axis("x").pos_mm
    card.push(_ramp(x0, 5.0, 60), end=True)
    card.sleep(0.02)
    assert card.status().moving
    card.stop()
    card.wait_rest(timeout=5)
    st = card.status()
    assert not st.moving and st.fault is None
    assert x0 < st.axis("x").cmd_mm < x0 + 5.0


def test_push_counts_and_numpy_points(card):
    np = pytest.importorskip("numpy")
    card.enable("x")
    scale = card.param("x", "scale")
    pts = np.array(_ramp(0.0, 0.5, 40))
    pts_counts = np.round(pts * scale).astype(np.int64)
    card.push_counts(pts_counts, end=True)
    card.wait_idle(timeout=5)
    assert card.status().axis("x").cmd_counts == pts_counts[-1][0]
    with pytest.raises(ValueError):
        card.push_counts([[0.5, 0, 0, 0]])


def test_push_refuses_a_batch_larger_than_the_ring(card):
    card.enable("x")
    with pytest.raises(sh2000.Error) as e:
        card.push([[0, 0, 0, 0]] * (card.queue_size + 1), end=True)
    assert e.value.code == errno.EMSGSIZE
    assert card.status().queue_fill == 0
    with pytest.raises(ValueError):
        card.push([[0, 0, 0]])


def test_home_timeout_stops_the_card_clean(card):
    # far from the switch, a timeout ends the homing with a STOP and a
    # wait for rest: nothing latched, even after the host timeout passes
    card.enable("x")
    card.push(_ramp(0.0, 5.0, 60), end=True)
    card.wait_idle(timeout=5)
    with pytest.raises(sh2000.Error) as e:
        card.home("x", timeout=0.2)
    assert e.value.code == sh2000.ETIMEOUT
    assert "homing stopped, card at rest" in e.value.message
    card.sleep(3 * card.param("global", "host_timeout_ms") / 1000)
    st = card.status()
    assert st.card_state_name == "idle" and st.fault is None
    assert not st.axis("x").homed and st.axis("x").enabled


def test_card_time_is_virtual_on_sim(card):
    t0 = card.now()
    card.sleep(0.5)
    assert card.now() - t0 == pytest.approx(0.5, abs=0.01)


def test_closed_card(card):
    card.close()
    with pytest.raises(ValueError):
        card.status()
    card.close()        # twice is fine
