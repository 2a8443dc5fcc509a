"""Every JSON output is strict JSON (issue 16): NaN and infinities are written as null."""

from __future__ import annotations

import json
import math

import pytest

from kbm.cli._common import emit_json
from kbm.output.strict_json import strict_text


def _strict_loads(text: str):
    def refuse(name):
        raise ValueError(f"non-standard JSON constant {name}")
    return json.loads(text, parse_constant=refuse)


def test_emit_json_writes_null_for_non_finite_numbers(capsys):
    emit_json({"a": math.nan, "b": [1.5, math.inf, -math.inf], "c": {"d": (math.nan,)}})
    data = _strict_loads(capsys.readouterr().out)
    assert data == {"a": None, "b": [1.5, None, None], "c": {"d": [None]}}


def test_reproduce_tables_are_strict_json():
    """The text of every JSON table and file (numerics.paper.reproduce, kbm lock --out)."""
    assert _strict_loads(strict_text({"x": [math.nan, 2.0]})) == {"x": [None, 2.0]}


@pytest.mark.parametrize("argv", [
    ["cycle", "vdp", "-p", "mu=1", "--json"],
    ["predict", "vdp", "-p", "mu=0.1", "--json"],
    ["derive", "vdp", "--order", "2", "--json"],
])
def test_command_json_parses_strictly(argv, capsys):
    from numerics.cli import main

    assert main(argv) == 0
    _strict_loads(capsys.readouterr().out)
