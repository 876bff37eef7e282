# SPDX-License-Identifier: MIT
"""Compensation tables through the binding: a table file loaded, its
status, cleared; a refused file raises with FILE:LINE and the card keeps
its tables."""
import pytest

import sh2000

GOOD = "id 0x00c0ffee\npitch X\n-10 0\n0 0.001\n10 0.0005\n"


def test_load_status_clear(card, tmp_path):
    f = tmp_path / "good.comp"
    f.write_text(GOOD)
    assert card.comp_status()["state"] == "none"
    card.comp_load(f)
    st = card.comp_status()
    assert st["state"] == "active"
    assert st["tables"] == 1
    assert st["id"] == 0x00c0ffee
    assert st["generation"] == 1
    card.comp_clear()
    assert card.comp_status()["state"] == "none"


def test_refused_names_the_line_and_changes_nothing(card, tmp_path):
    good = tmp_path / "good.comp"
    good.write_text(GOOD)
    card.comp_load(good)
    before = card.comp_status()
    bad = tmp_path / "bad.comp"
    bad.write_text("pitch X\n0 0\n1 0.001\n1 0.002\n")
    with pytest.raises(sh2000.Error) as e:
        card.comp_load(bad)
    assert e.value.code == sh2000.EPARAM
    assert f"{bad}:4: " in e.value.message
    assert "not strictly increasing" in e.value.message
    assert card.comp_status() == before
