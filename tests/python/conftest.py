# SPDX-License-Identifier: MIT
"""Fixtures of the binding's tests: a fresh simulated card per test, the
examples folder, a program file writer."""
import pathlib

import pytest

import sh2000

EXAMPLES = pathlib.Path(__file__).resolve().parents[2] / "examples"


@pytest.fixture
def card():
    c = sh2000.open("sim")
    yield c
    c.close()


@pytest.fixture
def part():
    return EXAMPLES / "part.ngc"


@pytest.fixture
def ngc(tmp_path):
    """ngc(text, name): a G-code file in a temporary folder."""
    def write(text, name="prog.ngc"):
        p = tmp_path / name
        p.write_text(text)
        return p
    return write
