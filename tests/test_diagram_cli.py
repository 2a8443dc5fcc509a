"""``kbm diagram`` (issue 38): the JSON contract, the store and resume, one-line errors.

The model ``x'' + x = mu ((nu - x^2) x' - c x)`` has the origin as its only equilibrium,
with ``tr J = mu nu``: its Hopf curve is the line ``nu = 0`` exactly (closed form), and
nothing else lies in the box.
"""

from __future__ import annotations

import io
import json
from contextlib import redirect_stdout

import pytest

from numerics.cli import main

HOPF = "(nu - x**2)*xdot - c*x"
ARGS = ["diagram", "--rhs", HOPF, "-p", "mu=0.2", "--vary", "nu=-0.4:0.5", "--vary",
        "c=0:1", "--grid", "5,3", "--no-averaged"]


def _run(argv):
    buf = io.StringIO()
    with redirect_stdout(buf):
        status = main(argv)
    return status, buf.getvalue()


@pytest.mark.slow
def test_json_contract_and_resume(tmp_path):
    status, out = _run([*ARGS, "--json", "--store", str(tmp_path / "s")])
    assert status == 0
    data = json.loads(out)
    assert {"curves", "codim2", "model", "params", "axes"} <= set(data)
    assert data["axes"] == ["nu", "c"]
    (hopf,) = data["curves"]
    assert {"kind", "points", "method", "order"} <= set(hopf)
    assert hopf["kind"] == "hopf" and hopf["method"] == "true" and hopf["order"] is None
    assert all(abs(nu) < 1e-12 for nu, _ in hopf["points"])
    assert min(c for _, c in hopf["points"]) == 0.0 and max(c for _, c in hopf["points"]) == 1.0
    assert data["codim2"] == []
    # the same run again from the store: the same bytes
    status, again = _run([*ARGS, "--json", "--store", str(tmp_path / "s"), "--resume"])
    assert status == 0 and again == out


def test_figure(tmp_path):
    status, out = _run([*ARGS, "--out", str(tmp_path)])
    assert status == 0
    assert (tmp_path / "diagram.json").exists()
    assert (tmp_path / "diagram-custom.png").stat().st_size > 1000
    assert "hopf" in out
    data = json.loads((tmp_path / "diagram.json").read_text())
    (hopf,) = data["curves"]
    assert {"kind", "points", "method", "order"} <= set(hopf) and data["codim2"] == []
    assert all(abs(nu) < 1e-12 for nu, _ in hopf["points"])


@pytest.mark.parametrize("argv, words", [
    (["diagram", "sedf", "-p", "mu=0.1", "--vary", "Delta=0:6"], "two --vary"),
    (["diagram", "sedf", "-p", "mu=0.1", "-p", "lam=1", "--vary", "Delta=0:6", "--vary",
      "gamma=0:1"], "gamma"),
    (["diagram", "sedf", "-p", "lam=1", "--vary", "Delta=0:6", "--vary", "beta=6:0"], "FROM"),
    (["diagram", "sedf", "-p", "mu=0.1", "--vary", "Delta=0:6", "--vary", "beta=0:1",
      "--resume"], "--store"),
])
def test_bad_input_one_line(argv, words, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert words in err and len(err.splitlines()) == 1
