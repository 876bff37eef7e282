# SPDX-License-Identifier: MIT
"""docs/python.md follows the code: its gathering and commissioning
examples run and print what the page says, and its error example says
what it shows."""
import pathlib
import re

import pytest

import sh2000

DOC = pathlib.Path(__file__).resolve().parents[2] / "docs" / "python.md"


def _section(title):
    text = DOC.read_text()
    return text[text.index(title):]


def _example_prints_what_the_page_shows(title, capsys):
    """Run the section's first example; compare with the lines after
    "which prints on the simulated card"."""
    sec = _section(title)
    code = re.search(r"```python\n(.*?)```", sec, re.S).group(1)
    exec(compile(code, str(DOC), "exec"), {})
    printed = capsys.readouterr().out.strip().splitlines()
    shown = [ln[4:] for ln in sec.split("which prints on the simulated card\n\n")[1]
             .split("\n\n")[0].splitlines()]
    assert printed == shown


def test_commissioning_example_prints_what_the_page_shows(capsys):
    _example_prints_what_the_page_shows("## Commissioning example", capsys)


def test_gather_example_prints_what_the_page_shows(capsys):
    pytest.importorskip("numpy")
    _example_prints_what_the_page_shows("## Data gathering", capsys)


def test_error_example(card):
    sec = _section("## Errors")
    code = re.search(r"```python\n(.*?)```", sec, re.S).group(1)
    exec(compile(code, str(DOC), "exec"), {"card": card, "sh2000": sh2000})
