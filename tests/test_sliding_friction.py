"""Friction laws of the pulled sliders (issue 12): the steady state, its measures and their limits.

References checked, none produced by the code under test:

- the power balance ``v Delta J = Delta Gamma + Delta E`` (work of the stage = dissipation +
  stored energy): in steady state the dissipation per unit distance equals the mean force;
- the quasi-static limit of the Prandtl-Tomlinson model: ``F_bar -> Delta W/lam`` as
  ``v -> 0`` where every slip crosses one well (paper eq. 4, the saddle-node slip energy of
  :func:`numerics.saddle_node`), approached as ``v^(2/3)`` (Muser, Phys. Rev. B 84, 125419
  (2011): the athermal Prandtl-Tomlinson friction near the spinodal);
- the static friction ``Delta sqrt(1 - 1/eta^2)`` of the quasi-static saddle node;
- the viscous limit ``F_bar -> mu v`` with the linear-response washboard drag
  ``mu Delta^2 w^2/(2 v ((Omega^2 - w^2)^2 + mu^2 w^2))``, ``w = 2 pi v/lam`` (the forced
  damped oscillator: the potential seen at speed v is a force of frequency w);
- the scipy (``solve_ivp``) path against the compiled path.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from kbm.errors import ParameterError
from kbm.model.builtins import get_model
from kbm.symbols import t, x, xdot

from numerics.sliding.friction import friction_point
from numerics.sliding.friction_records import FrictionSettings
from numerics.sliding.maps import friction_law, friction_map
from numerics.sliding.potential import saddle_node

ONE_WELL = {"mu": 3.0, "Omega": 2.0, "Delta": 3.0, "lam": 1.0}
PAPER = {"mu": 0.1, "Omega": 1.0, "Delta": 3.0, "lam": 1.0}


def test_stage_attached_sedf_is_the_paper_sedf_at_rest_and_follows_the_stage():
    """``sedf_comoving`` equals paper eq. (3) at v = 0; pulled, its excitation is measured by
    the spring's extension x - v t, and eq. (11)'s split keeps beta (x - v t)^2 x'^2 whole."""
    import sympy as sp

    beta, delta, k, mu = sp.symbols("beta delta k mu")
    assert get_model("sedf_comoving").F == get_model("sedf").F
    m = get_model("sedf_comoving", {"v": "1/10"})
    expected = -(beta * (x - t / 10)**2 - 1) * xdot - delta * sp.sin(k * x)
    assert sp.expand(m.F - expected) == 0
    plus, minus, factor = m.dissipation_parts()
    assert factor == beta
    assert sp.expand(plus - mu * (x - t / 10)**2 * xdot**2) == 0
    assert sp.expand(minus - mu * xdot**2) == 0
    assert not get_model("sedf", {"v": "1/10"}).F.has(t)


@pytest.mark.parametrize("model", ["cdc", "sedf_comoving"])
def test_dissipation_per_distance_equals_the_mean_force_on_every_steady_point(model):
    """Power balance: on every steady point |F_bar - Gamma/(v T)| <= 1e-3 |F_bar|, and the
    balance's integration error is below 1e-6."""
    params = {**PAPER, **({"beta": 1.0} if model != "cdc" else {})}
    law = friction_law(model, params, np.geomspace(3e-3, 2.0, 7), workers=1, progress=False,
                       settings=FrictionSettings(slips=10))
    steady = [p for p in law.points if p.steady]
    assert len(steady) >= 4, [(p.params["v"], p.regime, p.note) for p in law.points]
    for p in steady:
        assert p.energy_residual < 1e-3, (p.params, p.energy_residual)
        assert abs(p.mean_force - p.dissipation_per_distance) <= 1e-3 * abs(p.mean_force)
        assert p.audit < 1e-6


def test_quasi_static_limit_is_the_one_well_slip_energy():
    """CDC in the one-well regime (mu = 3, Omega = 2, Delta = 3): every slip crosses one well
    and F_bar -> Delta W/lam (paper eq. 4) within 1 % at v = 3e-4; the excess scales as
    v^(2/3) (athermal Prandtl-Tomlinson), and the extrapolation to v = 0 is within 0.3 %."""
    dW = saddle_node(3.0, 1.0, 2.0, n_wells=1).delta_W[0]
    s = FrictionSettings(slips=6)
    pts = {v: friction_point("cdc", {**ONE_WELL, "v": v}, settings=s) for v in (3e-4, 1e-3, 3e-3)}
    for p in pts.values():
        assert p.regime == "stick-slip" and p.wells_per_slip == 1.0 and p.steady
    assert abs(pts[3e-4].mean_force / dW - 1) < 0.01
    e1, e2 = pts[1e-3].mean_force - dW, pts[3e-3].mean_force - dW
    slope = math.log(e2 / e1) / math.log(3.0)
    assert abs(slope - 2 / 3) < 0.06, slope
    c = (pts[3e-3].mean_force - pts[1e-3].mean_force) / (3e-3**(2 / 3) - 1e-3**(2 / 3))
    assert abs((pts[1e-3].mean_force - c * 1e-3**(2 / 3)) / dW - 1) < 3e-3


def test_static_friction_is_the_quasi_static_saddle_node_force():
    """The peak spring force before a slow slip is Delta sqrt(1 - 1/eta^2) (within 0.5 %)."""
    p = friction_point("cdc", {**PAPER, "v": 0.003}, settings=FrictionSettings(slips=4))
    assert p.regime == "stick-slip"
    assert p.eta == pytest.approx(2 * math.pi * 3.0)
    assert abs(p.static_force / p.static_quasistatic - 1) < 5e-3
    assert 0.5 < p.stuck_fraction < 1


@pytest.mark.parametrize("v", [3.0, 5.0, 10.0])
def test_viscous_limit_with_the_washboard_drag(v):
    """Smooth sliding of the CDC: F_bar = mu v + mu Delta^2 w^2/(2 v ((Omega^2 - w^2)^2 +
    mu^2 w^2)) (linear response), the correction measured to 2 %."""
    mu, Om, D = PAPER["mu"], PAPER["Omega"], PAPER["Delta"]
    p = friction_point("cdc", {**PAPER, "v": v})
    w = 2 * math.pi * v
    drag = mu * D**2 * w**2 / (2 * v * ((Om**2 - w**2)**2 + mu**2 * w**2))
    assert p.regime == "smooth sliding" and p.steady
    assert abs((p.mean_force - mu * v) / drag - 1) < 0.02


def test_compiled_and_scipy_paths_agree():
    """The compiled DOP853 against scipy's solve_ivp on a periodic stick-slip state."""
    s = FrictionSettings(slips=4)
    a = friction_point("cdc", {**ONE_WELL, "v": 0.03}, settings=s)
    b = friction_point("cdc", {**ONE_WELL, "v": 0.03}, settings=s, engine="scipy")
    assert a.regime == b.regime == "stick-slip"
    assert a.mean_force == pytest.approx(b.mean_force, rel=1e-6)
    assert a.static_force == pytest.approx(b.static_force, rel=1e-6)


def test_regimes_of_the_three_sliders():
    """Stick-slip over three wells per slip (CDC at eta = 18.8, weak damping), a
    self-oscillating stage-attached SEDF, and the paper's SEDF running away (its damping
    mu beta x^2 grows with the distance slid)."""
    s = FrictionSettings(slips=6)
    cdc = friction_point("cdc", {**PAPER, "v": 0.01}, settings=s)
    assert cdc.regime == "stick-slip" and cdc.wells_per_slip == 3.0
    own = friction_point("sedf_comoving", {**PAPER, "beta": 1.0, "v": 0.1}, settings=s)
    assert own.regime == "self-oscillating sliding" and own.stuck_fraction == 0.0
    paper = friction_point("sedf", {**PAPER, "beta": 1.0, "v": 0.1}, settings=s)
    assert paper.regime == "runaway" and not paper.steady and "damping" in paper.note


@pytest.mark.parametrize("params, match", [
    ({**PAPER, "v": 0.0}, "v must be > 0"),
    ({**PAPER, "v": -0.1}, "v must be > 0"),
    ({**PAPER, "v": float("nan")}, "finite"),
    ({**PAPER}, "stage velocity is missing"),
    ({**PAPER, "v": 0.1, "beta": 1.0}, "unknown parameter 'beta'"),
    ({**PAPER, "v": 1e-7}, "outside the range of the friction laws"),
    ({**PAPER, "v": 1e5}, "outside the range of the friction laws"),
    ({**PAPER, "v": 1e-3, "Delta": 1e6}, "samples of the well's oscillation"),
])
def test_bad_points_are_refused(params, match):
    with pytest.raises(ParameterError, match=match):
        friction_point("cdc", params)


@pytest.mark.parametrize("axes, match", [
    ({"v": []}, "empty"),
    ({"v": [0.1, float("nan")]}, "finite"),
    ({"v": [0.1, 0.0]}, "> 0"),
    ({}, "at least one axis"),
    ({"Delta": [1.0]}, "v is missing"),
])
def test_bad_axes_are_refused(axes, match):
    with pytest.raises(ParameterError, match=match):
        friction_map("cdc", {"mu": 0.1}, axes, workers=1)


def test_bad_settings_are_refused():
    with pytest.raises(ParameterError, match="slips"):
        FrictionSettings(slips=0)
    with pytest.raises(ParameterError, match="steady_tol"):
        FrictionSettings(steady_tol=float("nan"))


def test_friction_table_prints_no_nan_for_a_runaway(capsys):
    """The stage-attached SEDF pulled at v = 2 runs away (its spring force grows without
    bound; :func:`friction_point` says ``runaway``): it has no mean force, dissipation per
    distance or stuck fraction, ``null`` in the JSON.  The table printed ``nan`` in those
    columns (``kbm friction sedf_comoving ... --vary v=1e-3:3:log24``, README); now ``--``
    as in the static-force column and in the noisy table, the reason on the next line."""
    import json

    from numerics.cli import main

    args = ["friction", "sedf_comoving", "-p", "Delta=3", "-p", "beta=1", "--vary", "v=2",
            "--no-progress"]
    assert main(args + ["--json"]) == 0
    rep = json.loads(capsys.readouterr().out)
    assert rep["regime"] == ["runaway"]
    assert rep["mean_force"] == rep["dissipation_per_distance"] == rep["stuck_fraction"] == [
        None]
    assert main(args) == 0
    text = capsys.readouterr().out
    row = next(line.split() for line in text.splitlines() if line.split()[:1] == ["2"])
    assert "nan" not in text and row[1:6] == ["runaway", "--", "--", "--", "--"], row
    assert "no bounded sliding state" in text
