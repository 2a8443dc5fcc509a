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

from _proc import _default_sigint
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


# A real SIGINT delivered to the command's own process after the ``n``-th point it stores
# (a deterministic moment: the signal is sent by the process to itself from the store's
# ``put``, so the test does not race the run); everything else is ``python -m numerics.cli``.
_INTERRUPT_AFTER = """
import os, signal, sys
from numerics.bifurcation.store import PathStore
_put, _count = PathStore.put, [0]
def put(self, key, record):
    _put(self, key, record)
    _count[0] += 1
    if _count[0] == int(os.environ["KBM_TEST_SIGINT_AFTER"]):
        os.kill(os.getpid(), signal.SIGINT)
PathStore.put = put
from numerics.cli import main
sys.exit(main(sys.argv[1:]))
"""


def _subprocess(argv, sigint_after=None):
    import os
    import subprocess
    import sys
    from pathlib import Path

    env = {**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[1])}
    if sigint_after is None:
        cmd = [sys.executable, "-m", "numerics.cli", *argv]
    else:
        env["KBM_TEST_SIGINT_AFTER"] = str(sigint_after)
        cmd = [sys.executable, "-c", _INTERRUPT_AFTER, *argv]
    # SIGINT at its default in the command (tests/_proc.py: a suite launched as a background
    # job of a non-interactive shell ignores SIGINT, and the ignore is inherited)
    return subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=600,
                          preexec_fn=_default_sigint)


@pytest.mark.slow
def test_ctrl_c_keeps_the_points_and_resume_finishes(tmp_path):
    """Issue 38's long runs: SIGINT part-way exits 130 with the points found kept in
    ``--store``; ``--resume`` ends with the same JSON as a run never interrupted."""
    whole = _subprocess([*ARGS, "--json", "--store", str(tmp_path / "whole")])
    assert whole.returncode == 0, whole.stderr
    stopped = _subprocess([*ARGS, "--json", "--store", str(tmp_path / "part")], sigint_after=8)
    assert stopped.returncode == 130, stopped.stderr
    assert "interrupted" in stopped.stderr and "--resume" in stopped.stderr
    assert len(stopped.stderr.strip().splitlines()) == 1
    # the kept path: not done, its points those of the whole run's curve
    (run_dir,) = (tmp_path / "part").iterdir()
    records = [json.loads(p.read_text()) for p in run_dir.glob("*.json")]
    open_paths = [r for r in records if "path" in r and not r["done"]]
    assert len(open_paths) == 1
    kept = json.loads(stopped.stdout)
    (hopf_part,) = kept["curves"]
    (hopf_whole,) = json.loads(whole.stdout)["curves"]
    assert 2 <= len(hopf_part["points"]) < len(hopf_whole["points"])
    whole_points = {tuple(p) for p in hopf_whole["points"]}
    assert all(tuple(p) in whole_points for p in hopf_part["points"])
    resumed = _subprocess([*ARGS, "--json", "--store", str(tmp_path / "part"), "--resume"])
    assert resumed.returncode == 0, resumed.stderr
    assert resumed.stdout == whole.stdout


def test_header_without_fixed_parameters_has_no_empty_parentheses():
    """Every parameter of the --rhs model an axis: the header printed "custom ()"; it names
    the fixed parameters only when there are some."""
    status, out = _run(["diagram", "--rhs", "(-nu + x**2 - x**4)*xdot", "--vary",
                        "nu=0.1:0.15", "--vary", "mu=0.05:0.3", "--grid", "5,3",
                        "--max-points", "20", "--no-averaged"])
    assert status == 0
    assert out.splitlines()[0].startswith("bifurcation diagram of custom over nu in [0.1, ")
