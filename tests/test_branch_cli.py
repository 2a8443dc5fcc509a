"""Issue 11: ``kbm branch`` (JSON contract, one-line errors), the diagram and its figure."""

from __future__ import annotations

import json

import pytest

from numerics.cli import main
from numerics.comparison.branches import energy_branch, kbm_branch

FOLD = "(-nu + x**2 - x**4)*xdot"


@pytest.fixture(scope="module")
def fold_json():
    import io
    from contextlib import redirect_stdout

    buf = io.StringIO()
    with redirect_stdout(buf):
        status = main(["branch", "--rhs", FOLD, "-p", "mu=0.1", "-p", "nu=0.05",
                       "--vary", "nu=0:0.2", "--orders", "1,3", "--json"])
    assert status == 0
    return json.loads(buf.getvalue())


def test_json_contract(fold_json):
    js = fold_json
    assert {"points", "special", "analytic"} <= set(js)
    for p in js["points"]:
        assert {"parameter", "amplitude_max", "period", "stable", "multipliers"} <= set(p)
    for s in js["special"]:
        assert {"kind", "parameter", "amplitude"} <= set(s)
    kinds = sorted(s["kind"] for s in js["special"])
    assert kinds == ["fold", "hopf"]
    fold = next(s for s in js["special"] if s["kind"] == "fold")
    assert abs(fold["parameter"] - 0.125) < 1e-5
    assert set(js["analytic"]) == {"kbm order 1", "kbm order 3", "energy order 1"}
    assert js["analytic"]["kbm order 1"]["folds"][0]["parameter"] == pytest.approx(0.125,
                                                                                  abs=1e-12)
    assert any(p["stable"] for p in js["points"]) and not all(p["stable"] for p in js["points"])


@pytest.mark.parametrize("argv,words", [
    (["branch", "vdp", "-p", "mu=1", "--vary", "nope=0:1"], "cannot vary 'nope'"),
    (["branch", "vdp", "--vary", "mu=2:1"], "empty range"),
    (["branch", "vdp", "--vary", "mu=1"], "NAME=FROM:TO"),
    (["branch", "vdp", "--vary", "mu=1:2", "--orders", "0"], "--orders"),
    (["branch", "linear_damping", "-p", "mu=0.1", "--vary", "zeta=0.1:1"],
     "no limit cycle at zeta = 0.1"),
    # "mu = 0: there is no perturbation to average; give mu != 0", where mu = 0 was FROM
    (["branch", "vdp", "--vary", "mu=0:1"], "--vary mu=0:1 starts the branch at mu = 0"),
    (["branch", "vdp", "--vary", "mu=-1:1", "-p", "mu=0"], "-p mu=0 starts the branch"),
])
def test_errors_one_line(capsys, argv, words):
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("kbm branch: error: ") and words in err[0]


def test_a_start_value_as_a_fraction(capsys):
    """``-p nu=1/20`` as the start of ``--vary nu=...`` was a ValueError traceback (``could
    not convert string to float: '1/20'``), though ``-p`` reads fractions everywhere.  The
    branch from it has the fold of ``(-nu + x^2 - x^4) x'``, ``A_1 = 0`` with
    ``dA_1/da = 0``: ``nu = 1/8`` (energy balance: ``-nu + a^2/4 - a^4/8 = 0`` is double at
    ``a^2 = 1``)."""
    assert main(["branch", "--rhs", FOLD, "-p", "mu=0.1", "-p", "nu=1/20", "--vary",
                 "nu=0:0.2", "--orders", "none", "--no-energy", "--json"]) == 0
    js = json.loads(capsys.readouterr().out)
    (fold,) = [s for s in js["special"] if s["kind"] == "fold"]
    assert abs(fold["parameter"] - 0.125) < 1e-5


def test_text_output(capsys):
    assert main(["branch", "vdp", "-p", "mu=0.5", "--vary", "mu=0.5:1", "--orders", "none",
                 "--no-energy"]) == 0
    out = capsys.readouterr().out
    assert "reached mu = 1" in out and "1 branch(es)" in out


def test_analytic_branches_fold_model():
    k1 = kbm_branch(FOLD, {"mu": 0.1}, "nu", (0.0, 0.2), order=1, n=21)
    assert len(k1.folds) == 1 and k1.folds[0].parameter == pytest.approx(0.125, abs=1e-13)
    assert k1.folds[0].amplitude == pytest.approx(1.0, abs=1e-12)
    # on the grid: a^2 = 1 +- sqrt(1 - 8 nu), the larger one stable
    for p, a, _, stable in k1.points:
        if 0 < p < 0.125:
            roots = [(1 + s * (1 - 8 * p) ** 0.5) ** 0.5 for s in (1, -1)]
            assert min(abs(a - r) for r in roots) < 1e-10
            assert stable == (abs(a - roots[0]) < 1e-10)
    from kbm import custom_model

    e = energy_branch(custom_model(FOLD), {"mu": 0.1}, "nu", (0.0, 0.2), n=11)
    # issue 26: the energy balance's fold solved as Gamma = Gamma' = 0 is the exact
    # first-order 1/8 (for a circle orbit the energy balance is A_1 = 0); by bisection on the
    # root count it was 0.12497337
    assert len(e.folds) == 1 and abs(e.folds[0].parameter - 0.125) < 1e-12


def test_diagram_figure(tmp_path, fold_json):
    from kbm import custom_model
    from numerics.comparison.diagram import branch_diagram
    from numerics.paper.figures import FIGURES
    from numerics.paper.figures.branches import diagram_figure

    assert "sedf_branches" in FIGURES
    d = branch_diagram(custom_model(FOLD), {"mu": 0.1, "nu": 0.05}, "nu", (0.0, 0.2),
                       orders=(1,), n_analytic=21)
    paths = diagram_figure(d, tmp_path / "fold")
    assert [p.suffix for p in paths] == [".png", ".pdf"] and all(p.stat().st_size > 1000
                                                                 for p in paths)


@pytest.mark.slow
def test_sedf_branch_figures(tmp_path):
    from numerics.paper.figures import write_figures

    paths = write_figures(tmp_path, only=["sedf_branches"])
    assert sorted(p.name for p in paths) == ["sedf_branches_beta.pdf", "sedf_branches_beta.png",
                                             "sedf_branches_delta.pdf",
                                             "sedf_branches_delta.png"]
