# SPDX-License-Identifier: MIT
"""Programs through the binding: read, check and run with callbacks, the
errors with file:line, callbacks that raise."""
import pathlib
import threading

import pytest

import sh2000


def test_check_and_run_part_with_progress(card, part):
    lines = len(part.read_text().splitlines())
    with card.program(part) as prog:
        plan = prog.check()
        assert plan.blocks > 0 and plan.points > 0 and plan.seconds > 0
        assert plan.moved == "xyz"
        card.enable(plan.moved)
        seen = []
        stats = prog.run(progress=seen.append)
    points = [p.points for p in seen]
    assert len(seen) > 10
    assert points == sorted(points) and points[0] < points[-1]
    assert seen[-1].points == plan.points == stats.points
    assert seen[-1].fraction == 1.0
    times = [p.t for p in seen]
    assert times == sorted(times)
    assert all(-1 <= p.line <= lines for p in seen)
    assert max(p.line for p in seen) > 1
    # -1 until the card took its first point (docs/python.md), then a line
    assert seen[0].line == -1
    first = next(k for k, p in enumerate(seen) if p.line != -1)
    assert all(p.line >= 1 for p in seen[first:])
    assert isinstance(seen[-1].status, sh2000.Status)
    assert stats.time_s == pytest.approx(plan.seconds, rel=0.05)
    assert stats.distance_mm > 100 and stats.underruns == 0
    st = card.status()
    assert st.card_state == sh2000.STATE_IDLE and st.fault is None


def test_run_checks_first_when_not_checked(card, ngc):
    prog = card.program(ngc("G21 G90\nG1 X2 F600\nM2\n"))
    card.enable("x")
    stats = prog.run()
    assert prog.plan is not None and stats.points == prog.plan.points
    assert card.status().axis("x").pos_mm == pytest.approx(2.0, abs=0.001)


def test_program_error_raises_with_file_line(card, ngc):
    path = ngc("G21 G90\nG1 X1 F600\nG1 X2 Q\nG1 X3\n")
    prog = card.program(path)
    with pytest.raises(sh2000.Error) as e:
        prog.check()
    assert e.value.code == sh2000.EPROGRAM
    assert e.value.where.startswith(f"{path}:3:")
    assert str(e.value).startswith(f"{path}:3:")
    assert any(f"{path}:3:" in d and "error" in d for d in e.value.diagnostics)
    with pytest.raises(RuntimeError):
        prog._p.run(None, None)     # never streamed unchecked
    assert card.status().axis("x").pos_mm == 0


def test_program_errors_are_all_in_the_diagnostics(card, ngc):
    """Every error of the first pass, as sh2000-upload -n lists them, and
    the same again (not one more) from a second check()."""
    path = ngc("G21 G90\nG1 X10 F600\nG5 X3\nG1 X1e9\nG1 Q5\nG7\nM2\n")
    prog = card.program(path)
    for _ in range(2):
        with pytest.raises(sh2000.Error) as e:
            prog.check()
        assert e.value.code == sh2000.EPROGRAM
        assert e.value.where == f"{path}:3:1"
        diags = e.value.diagnostics
        assert [d.split(": error:")[0] for d in diags] == [
            f"{path}:3:1", f"{path}:4:6", f"{path}:5:4", f"{path}:6:1"]
        assert "G5" in diags[0] and "exponent" in diags[1]
        assert "Q word" in diags[2] and "G7" in diags[3]
        assert prog.diagnostics == diags
    with pytest.raises(sh2000.Error) as e:
        prog.run()
    assert e.value.code == sh2000.EPROGRAM and len(e.value.diagnostics) == 4
    assert card.status().axis("x").pos_mm == 0


def test_program_beyond_soft_limit_raises_with_where(card, ngc):
    card.set_param("x", "soft_max", 5)
    path = ngc("G21 G90\nG1 X2 F600\nG1 X8\nM2\n")
    with pytest.raises(sh2000.Error) as e:
        card.program(path).check()
    assert e.value.code == sh2000.ELIMIT
    assert e.value.where.startswith(f"{path}:3")


def test_unreadable_program_raises(card, tmp_path):
    with pytest.raises(sh2000.Error) as e:
        card.program(tmp_path / "missing.ngc")
    assert "missing.ngc" in str(e.value)
    with pytest.raises(sh2000.Error) as e:
        card.program(tmp_path / "noext")
    assert e.value.code == sh2000.EFORMAT


def test_callback_that_raises_stops_the_run(card, part):
    prog = card.program(part)
    plan = prog.check()
    card.enable(plan.moved)
    calls = []

    class Enough(Exception):
        pass

    def progress(p):
        calls.append(p.points)
        if p.fraction > 0.3:
            raise Enough(p.points)

    with pytest.raises(Enough) as e:
        prog.run(progress=progress)
    stopped_at = e.value.args[0]
    assert calls[-1] == stopped_at            # no callback after the raise
    assert 0.3 * plan.points < stopped_at < plan.points
    st = card.status()
    assert st.card_state == sh2000.STATE_IDLE and st.fault is None
    assert st.queue_fill == 0
    # at rest on the path, and the card takes the next program
    assert not any(a.moving for a in st.axes)
    stats = card.program(part).run()
    assert stats.points > 0


def test_pause_callback_at_m0(card, ngc):
    path = ngc("G21 G90\nG1 X1 F600\nM0\nG1 X2\nM2\n")
    card.enable("x")
    pauses = []

    def pause(where, optional):
        pauses.append((where, optional, card.status().axis("x").cmd_mm))

    card.program(path).run(pause=pause)
    assert len(pauses) == 1
    where, optional, x = pauses[0]
    assert where.startswith(f"{path}:3") and optional is False
    assert x == pytest.approx(1.0, abs=1e-5)
    assert card.status().axis("x").pos_mm == pytest.approx(2.0, abs=0.001)


def test_pause_callback_that_raises_ends_the_run(card, ngc):
    path = ngc("G21 G90\nG1 X1 F600\nM0\nG1 X2\nM2\n")
    card.enable("x")

    def pause(where, optional):
        raise KeyError(where)

    with pytest.raises(KeyError):
        card.program(path).run(pause=pause)
    assert card.status().axis("x").pos_mm == pytest.approx(1.0, abs=0.001)


def test_estop_from_another_thread_ends_the_run(card, part):
    """The run releases the GIL: another thread's estop gets through."""
    prog = card.program(part)
    card.enable(prog.check().moved)
    started = threading.Event()

    def progress(p):
        if p.fraction > 0.1:
            started.set()

    def stopper():
        started.wait(10)
        card.estop()

    t = threading.Thread(target=stopper)
    t.start()
    with pytest.raises(sh2000.Error) as e:
        prog.run(progress=progress)
    t.join()
    assert e.value.code == sh2000.EESTOP
    assert e.value.where is not None and e.value.where.startswith(str(part) + ":")
    assert card.status().card_state_name == "estop"


def test_close_refused_while_running(card, part):
    prog = card.program(part)
    card.enable(prog.check().moved)
    seen = []

    def progress(p):
        if not seen:
            for f in (card.close, prog.close):
                try:
                    f()
                except RuntimeError as e:
                    seen.append(str(e))
            raise StopIteration

    with pytest.raises(StopIteration):
        prog.run(progress=progress)
    assert len(seen) == 2


def test_run_refuses_a_card_moved_since_check(card, ngc):
    prog = card.program(ngc("G21 G90\nG1 X2 Y1 F600\nM2\n"))
    prog.check()
    card.enable("xy")
    card.push([[0, 0.5, 0, 0]], end=True)      # y moves after the check
    card.wait_idle(timeout=10)
    before = card.status()
    with pytest.raises(sh2000.Error) as e:
        prog.run()
    assert e.value.code == sh2000.EMOVED
    assert "axis y moved by 0.5000 mm since the program was checked" in str(e.value)
    after = card.status()               # no set-point moved
    assert after.axis("x").cmd_mm == before.axis("x").cmd_mm == 0
    assert after.axis("y").cmd_mm == before.axis("y").cmd_mm == 0.5
    assert after.card_state == sh2000.STATE_IDLE and after.queue_fill == 0


def test_check_holds_still_the_axes_a_program_never_moves(card):
    """A slow A the program never moves does not bound its plan: planned
    as with a fast A, and run to its end (sh2000_program_axes, as
    sh2000-upload; tests/tools/upload's still_axes)."""
    data = (pathlib.Path(__file__).resolve().parents[1] /
            "tools/upload/data/still_axes.ngc")
    for axis in "xyza":
        card.set_param(axis, "amax", 20000)
    with card.program(data) as prog:
        fast = prog.check().seconds
    card.set_param("a", "amax", 5000)
    with card.program(data) as prog:
        plan = prog.check()
        assert plan.moved == "xyz"
        assert plan.seconds == fast
        card.enable(plan.moved)
        prog.run()
    assert card.status().axis("z").pos_mm == pytest.approx(42.8625, abs=0.001)


def test_check_plans_again_where_the_planner_passes_amax(card):
    """Where the planner alone takes an axis past its amax, check() plans
    again with a smaller margin (sh2000_program_check, as sh2000-upload;
    tests/tools/upload's accel_fit): the plan keeps amax, a second check
    starts from the card's margin again, and the run ends where the
    program does."""
    data = (pathlib.Path(__file__).resolve().parents[1] /
            "tools/upload/data/accel_fit.ngc")
    with card.program(data) as prog:
        plan = prog.check()
        assert plan.replans >= 1 and plan.margin < 0.95
        assert 0.9 < plan.accel_peak <= 1.0 and plan.accel_axis in "xy"
        again = prog.check()
        assert again == plan
        card.enable(plan.moved)
        stats = prog.run()
    assert stats.points == plan.points
    assert card.status().axis("x").pos_mm == pytest.approx(13.5, abs=0.001)
    assert card.status().axis("y").pos_mm == pytest.approx(7.5, abs=0.001)
    with card.program(pathlib.Path(__file__).resolve().parents[2] /
                      "examples/part.ngc") as prog:
        plan = prog.check()
        assert plan.replans == 0 and plan.margin == 0.95
        assert 0 < plan.accel_peak <= 1.0
