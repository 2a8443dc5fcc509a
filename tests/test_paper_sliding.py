"""The paper's driven sliders (eqs. 3, 12): energy audit, quasi-static slip energy (eq. 4),
integrator independence, bad input (issue 5)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from kbm import ParameterError
from numerics.cli import main
from numerics import analyze, saddle_node, slide
from numerics.sliding.potential import potential


@settings(max_examples=6)
@given(model=st.sampled_from(["sedf", "cdc"]), Delta=st.floats(0.5, 3.0),
       v=st.floats(0.005, 0.2), mu=st.floats(0.05, 1.0), beta=st.floats(0.2, 1.0))
@pytest.mark.slow  # 4-8 s; kept out of the default run (five-minute rule)
def test_energy_audit_closes(model, Delta, v, mu, beta):
    """Work of the spring = change of kinetic + periodic potential energy + Gamma (eq. 10),
    to integration accuracy, for random parameters of both sliders."""
    r = slide(model, {"mu": mu, "Delta": Delta, "v": v, "beta": beta}, t_end=150.0)
    scale = max(1.0, abs(r.work[-1]))
    assert abs(r.energy_residual) < 1e-7 * scale


def test_saddle_node_closed_form():
    """At the saddle node of U(x, L) = Omega^2 (x - L)^2/2 - (Delta/k) cos kx (eq. 4),
    dU/dx = 0 and d2U/dx2 = 0, i.e. cos(k x0) = -Omega^2/(Delta k); the slip ends in a
    minimum (dU/dx = 0, d2U/dx2 > 0) and Delta W = U(x0) - U(x1) > 0."""
    D, lam, Om = 3.0, 1.0, 2.0
    k = 2 * math.pi / lam
    s = saddle_node(D, lam, Om)
    assert math.cos(k * s.x0) == pytest.approx(-Om**2 / (D * k), abs=1e-14)
    assert Om**2 * (s.x0 - s.L0) + D * math.sin(k * s.x0) == pytest.approx(0, abs=1e-12)
    x1 = s.minima[0]
    assert Om**2 * (x1 - s.L0) + D * math.sin(k * x1) == pytest.approx(0, abs=1e-12)
    assert Om**2 + D * k * math.cos(k * x1) > 0
    U = potential(np.array([s.x0, x1]), s.L0, Delta=D, lam=lam, Omega=Om)
    assert s.delta_W[0] == pytest.approx(U[0] - U[1], rel=1e-14) and s.delta_W[0] > 0
    assert saddle_node(0.1, 1.0, 1.0) is None  # Delta k < Omega^2: no stick-slip


def test_eq4_is_derived_from_the_model():
    """The potential derived from the symbolic CDC (numerics.sliding.potential.eq4) is the
    paper's eq. (4), U = Omega^2 (x - L)^2/2 - (Delta/k) cos kx, typed here from the paper:
    the same expression, and the same values to the last bit (the paper's order of the
    operations is kept)."""
    import sympy as sp

    from numerics.sliding.potential import eq4

    x, L, Delta, k, Omega = sp.symbols("x L Delta k Omega")
    paper = Omega**2 * (x - L)**2 / 2 - Delta / k * sp.cos(k * x)
    assert sp.simplify(eq4().expr - paper) == 0
    D, lam, Om = 2.5, 0.8, 1.3
    kk = 2 * math.pi / lam
    xs = np.linspace(-4, 4, 2001)
    typed = Om**2 * (xs - 0.3)**2 / 2 - D / kk * np.cos(kk * xs)
    assert np.array_equal(potential(xs, 0.3, Delta=D, lam=lam, Omega=Om), typed)


@pytest.mark.slow  # 3-4 s; kept out of the default run (five-minute rule)
def test_quasi_static_slip_energy_one_well():
    """CDC with strong damping (mu = 3, Omega = 2, Delta = 3): each slip crosses one well and
    dissipates Delta W of the saddle-node formula within 1% as v -> 0 (v = 5e-4).  The
    slips start every lam/v = 2000 (at t = 2044 and 4044, each over in 4): t_end = 4500
    holds the same two as 6000 did."""
    r = slide("cdc", {"mu": 3.0, "Delta": 3.0, "Omega": 2.0, "v": 5e-4}, t_end=4500.0)
    a = analyze(r)
    assert len(a.slips) >= 2
    for s in a.slips:
        assert s.wells == 1
        assert s.energy_dissipated == pytest.approx(a.delta_W, rel=0.01)


def test_multi_well_regime_is_reported(claims_and_runs):
    """At the paper's parameters (mu = 0.1, Omega = 1, Delta = 3) a CDC slip crosses several
    wells: reported as such, with more energy than the one-well Delta W.  The run to
    t = 700 is the one :func:`numerics.paper.claims.check_claims` integrated at Fig. 5's
    parameters (those of ``slide("cdc", {"Delta": 3.0, "v": 0.01}, t_end=700.0)``, whose
    defaults are mu = 0.1, lam = 1, Omega = 1: the run's own parameters are checked here),
    not a second integration of the same run."""
    from kbm.output.paper import FIG5

    _, runs = claims_and_runs
    params = {p: v for p, v in FIG5.items() if p != "beta"}
    assert params == {"mu": 0.1, "Delta": 3.0, "v": 0.01, "lam": 1.0, "Omega": 1.0}
    r = runs[("cdc", tuple(sorted(params.items())), (("t_end", 700.0),))]
    assert r.params == params
    a = analyze(r)
    assert a.slips and all(s.wells >= 2 for s in a.slips)
    sn = saddle_node(3.0, 1.0, 1.0)
    for s in a.slips[:1]:
        assert s.energy_dissipated > a.delta_W
        # the energy of a w-well quasi-static slip brackets the measured one
        assert s.energy_dissipated == pytest.approx(sn.delta_W[s.wells - 1], rel=0.05)


def test_results_do_not_depend_on_the_integrator():
    """DOP853 at 1e-10 and LSODA (Adams/BDF) at 1e-10 agree on slip times and energies."""
    p = {"Delta": 3.0, "v": 0.01, "beta": 1.0}
    a1 = analyze(slide("sedf", p, t_end=500.0, method="DOP853", rtol=1e-10))
    a2 = analyze(slide("sedf", p, t_end=500.0, method="LSODA", rtol=1e-10, atol=1e-12))
    assert len(a1.slips) == len(a2.slips) > 0
    for s1, s2 in zip(a1.slips, a2.slips):
        assert abs(s1.t_start - s2.t_start) < 1e-3 * max(1, s1.t_start) + 0.2
        assert s1.energy_dissipated == pytest.approx(s2.energy_dissipated, rel=1e-4, abs=1e-6)
    assert a1.gamma == pytest.approx(a2.gamma, rel=1e-5)


@pytest.mark.parametrize("params, t_end, needle", [
    ({"lam": -1.0}, 10.0, "lam"), ({"Omega": 0.0}, 10.0, "Omega"), ({}, 0.0, "t_end"),
    ({}, -5.0, "t_end"), ({"Delta": float("nan")}, 10.0, "finite"), ({"v": -0.1}, 10.0, "v"),
])
def test_bad_input(params, t_end, needle):
    """Negative lambda, Omega = 0, t_end <= 0, NaN, v < 0: a clear ParameterError."""
    with pytest.raises(ParameterError, match=needle):
        slide("sedf", {"Delta": 1.0, "v": 0.1, **params}, t_end=t_end)


def test_cli_slide_json(capsys):
    """kbm slide --json has the documented keys."""
    assert main(["slide", "cdc", "--param", "Delta=3", "--param", "v=0.01",
                 "--t-end", "400", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    for key in ("model", "params", "peak_force", "mean_force", "slips", "gamma_plus",
                "gamma_minus", "gamma", "energy_residual", "delta_W"):
        assert key in data
    assert set(data["slips"][0]) == {"t_start", "t_end", "wells", "peak_force",
                                     "energy_dissipated", "complete"}
    assert main(["slide", "cdc", "--param", "Omega=0", "--t-end", "10"]) == 2
    assert main(["slide", "cdc", "--param", "Delta=0.1", "--param", "v=0", "--t-end", "50",
                 "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["delta_W"] is None


@pytest.fixture(scope="module")
def claims_and_runs():
    """:func:`numerics.paper.claims.check_claims` at t_end = 700, with the trajectories it
    integrated recorded (key: model, sorted params, sorted keywords): computed once for the
    claims' test and the multi-well test (they only read them)."""
    import numerics.paper.claims as claims_module
    from numerics import check_claims

    runs = {}

    def recording_slide(model, params, **kw):
        r = slide(model, params, **kw)
        runs[(model, tuple(sorted(params.items())), tuple(sorted(kw.items())))] = r
        return r

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(claims_module, "slide", recording_slide)
        claims = {c.key: c for c in check_claims(t_end=700.0)}
    return claims, runs


def test_claims_are_checked_against_independent_numbers(claims_and_runs):
    """Each paper claim gets a verdict with numbers, and the verdicts rest on numbers that
    independent references confirm:

    - static friction: the quasi-static saddle node has U'' = 0, i.e. cos(k x0) = -1/eta with
      the Prandtl-Tomlinson parameter eta = 2 pi Delta/(Omega^2 lam), so the static force is
      Delta sqrt(1 - 1/eta^2) (closed form);
    - dissipation: Gamma of each slider equals the work of the spring minus the change of
      the kinetic and periodic potential energy (energy balance, computed here from the
      trajectory, not from the dissipation states), and the verdict follows those numbers.

    The energy balance is computed from the very trajectories the claims were measured on
    (recorded as :func:`numerics.paper.claims.check_claims` computes them; a slider it did
    not integrate is integrated here), not from a second integration of the same runs.
    """
    from kbm.output.paper import FIG5

    t_end = 700.0
    claims, runs = claims_and_runs
    assert len(claims) == 6
    assert all(c.verdict in ("holds", "does not hold", "partly") for c in claims.values())
    D, Om, lam = FIG5["Delta"], FIG5["Omega"], FIG5["lam"]
    eta = 2 * math.pi * D / (Om**2 * lam)
    static = claims["static friction"].numbers
    assert static["quasi_static"] == pytest.approx(D * math.sqrt(1 - 1 / eta**2), rel=1e-10)
    assert static["static_cdc"] and all(abs(s - D) < 0.05 * D for s in static["static_cdc"])
    k = 2 * math.pi / lam
    balance = {}
    for model in ("sedf", "cdc"):
        params = {p: v for p, v in FIG5.items() if model == "sedf" or p != "beta"}
        key = (model, tuple(sorted(params.items())), (("t_end", t_end),))
        r = runs[key] if key in runs else slide(model, params, t_end=t_end)
        ke = r.xdot[-1] ** 2 / 2 - r.xdot[0] ** 2 / 2
        u = -D / k * (math.cos(k * r.x[-1]) - math.cos(k * r.x[0]))
        balance[model] = r.work[-1] - ke - u
        assert claims["dissipation"].numbers[f"gamma_{model}"] == pytest.approx(
            balance[model], rel=1e-6)
    expect = "holds" if balance["sedf"] < balance["cdc"] else "does not hold"
    assert claims["dissipation"].verdict == expect


def test_paper_figure_is_written(tmp_path):
    """kbm figures writes the named figure as a non-empty PNG and PDF."""
    assert main(["figures", "--out", str(tmp_path), "--only", "fig2_potential"]) == 0
    for ext in ("png", "pdf"):
        f = tmp_path / f"fig2_potential.{ext}"
        assert f.exists() and f.stat().st_size > 1000
