"""The long-double stick-slip cycle of the stage-attached SEDF (friction criterion 6,
:mod:`numerics.sliding.extended`), against references it does not produce:

- ``solve_ivp`` (DOP853, rtol 1e-12) on ``x'' = -Omega^2 s - Delta sin(2 pi x/lam) + mu (1 -
  beta s^2) x'``, ``s = x - v t`` (M. D'Acunto's eq. 3 with the excitation attached to the
  stage), with the integrals ``G_+' = mu s^2 x'^2``, ``G_-' = mu x'^2``, ``W' = F x'``,
  ``J' = F``, ``F = -Omega^2 s``, written here, at ``Omega, lam != 1``, through a slip;
- the equation's scaling ``x = lam X``, ``t = T/Omega``: the point ``(mu, beta, Delta, lam,
  Omega, v)`` is the point ``(mu/Omega, beta lam^2, Delta/(lam Omega^2), 1, 1, v/(lam
  Omega))`` with every force ``Omega^2 lam`` times larger (the same wells, the same gain
  ``G = 2 mu/(3 v sqrt(beta))``);
- the stuck slider's closed forms: its quasi-static state ``Delta sin(k x) = -Omega^2 s``
  and the saddle node's spring force ``Delta sqrt(1 - 1/eta^2)`` (Prandtl-Tomlinson).

The Taylor method: A. Jorba and M. Zou, Experimental Mathematics 14 (2005) 99-117.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from numerics.paper.friction import LAW_PARAMS, LAW_V
from numerics.sliding.driven import driven_system
from numerics.sliding.extended import (LD, ROUNDING, ROUNDING_LD, UNRESOLVED, _at, _Taylor,
                                       beyond_double, extended_point, gain, section,
                                       stick_slip_cycles)
from numerics.sliding.friction import _grid
from numerics.sliding.friction_records import FrictionPoint, FrictionSettings

#: the Delta = 3 law's second velocity of kbm reproduce (G = 32.2)
LAW_POINT = {**LAW_PARAMS, "Delta": 3.0, "v": float(np.geomspace(LAW_V[0], LAW_V[-1], 12)[1])}
#: the same point at Omega = 1.3, lam = 0.7 (the scaling of the module docstring)
ODD = {"mu": 0.1 * 1.3, "beta": 1 / 0.7**2, "Delta": 3 * 0.7 * 1.3**2, "lam": 0.7,
       "Omega": 1.3, "v": LAW_POINT["v"] * 0.7 * 1.3}


def _system(p: dict):
    return driven_system("sedf_comoving", p, engine="scipy")


def _rhs(p: dict):
    mu, b, D, Om2, v, k = (p["mu"], p["beta"], p["Delta"], p["Omega"]**2, p["v"],
                           2 * math.pi / p["lam"])

    def f(t, z):
        x, u = z[0], z[1]
        s = x - v * t
        F = -Om2 * s
        return [u, F - D * math.sin(k * x) + mu * (1 - b * s * s) * u,
                mu * s * s * u * u, mu * u * u, F * u, F]
    return f


def test_the_taylor_series_follows_solve_ivp_through_a_slip_at_other_omega_and_lam():
    """From the quasi-static state at 97 % of the saddle node's extension (``Delta sin(k x)
    = -Omega^2 s``) over 60 time units: the rest of the stick, the slip and its swing, the
    state and the four integrals within 1e-9 of ``solve_ivp`` (measured: 5.4e-11, and 1.3e-11
    at rtol 1e-13: ``solve_ivp``'s own error)."""
    p, t_end = ODD, 60.0
    eta = 2 * math.pi * p["Delta"] / (p["Omega"]**2 * p["lam"])
    s0 = -0.97 * p["Delta"] * math.sqrt(1 - 1 / eta**2) / p["Omega"]**2
    x0 = math.asin(-p["Omega"]**2 * s0 / p["Delta"]) * p["lam"] / (2 * math.pi)
    tay = _Taylor(_system(p))
    x, u, s, acc, t = LD(x0), LD(0), LD(s0), np.zeros(4, LD), LD(0)
    while t < t_end:
        M = tay.series(x, u, s)
        h = min(tay.step(M), LD(t_end) - t)
        end = _at(M, h)
        x, u, s, acc, t = end[0], end[1], end[2], acc + end[3:], t + h
    t0 = (x0 - s0) / p["v"]  # s = x - v t
    ref = solve_ivp(_rhs(p), (t0, t0 + t_end), [x0, 0, 0, 0, 0, 0], method="DOP853",
                    rtol=1e-12, atol=1e-13).y[:, -1]
    got = np.array([x, u, *acc], dtype=float)
    assert abs(ref[0] - x0) > 3 * p["lam"]  # slipped
    assert float(s) == pytest.approx(ref[0] - p["v"] * (t0 + t_end), abs=1e-8)
    assert np.allclose(got, ref, rtol=1e-9, atol=1e-9), got - ref


def test_the_section_lies_between_the_self_excited_zone_and_the_saddle_node():
    """``s_c`` midway between ``-1/sqrt(beta)`` and ``-Delta sqrt(1 - 1/eta^2)/Omega^2``;
    none where the saddle node lies within the zone (``beta`` large) or ``eta <= 1``."""
    sys_ = _system(ODD)
    eta = 2 * math.pi * ODD["Delta"] / (ODD["Omega"]**2 * ODD["lam"])
    s_sn = ODD["Delta"] * math.sqrt(1 - 1 / eta**2) / ODD["Omega"]**2
    assert section(sys_) == pytest.approx(-(1 / math.sqrt(ODD["beta"]) + s_sn) / 2)
    assert section(_system({**ODD, "beta": 1 / (1.1 * s_sn)**2})) is None
    assert section(_system({**ODD, "Delta": 0.2})) is None
    assert gain(sys_) == pytest.approx(2 * 0.13 / (3 * ODD["v"] * math.sqrt(ODD["beta"])))
    assert gain(driven_system("cdc", {k: ODD[k] for k in ODD if k != "beta"},
                              engine="scipy")) is None


def _measured(p: dict) -> FrictionPoint:
    sys_ = _system(p)
    _, _, dt, v_stick, min_stuck = _grid(sys_, FrictionSettings())
    pt = extended_point(sys_, FrictionSettings(), dict(model="sedf_comoving", params=p,
                                                       eta=0.0), dt, v_stick, min_stuck)
    assert isinstance(pt, FrictionPoint), pt
    return pt


@pytest.mark.slow
def test_the_cycle_obeys_the_equations_scaling_in_omega_and_lam():
    """The point at ``Omega = 1.3, lam = 0.7`` against its scaled unit point (``mu/Omega,
    beta lam^2, Delta/(lam Omega^2), v/(lam Omega)``): the same wells per slip, every force
    ``Omega^2 lam`` times the unit point's (mean force within 1e-8), both steady, their
    power balance closed (dissipation per distance = mean force within 1e-9)."""
    Om, lam = ODD["Omega"], ODD["lam"]
    unit = {"mu": ODD["mu"] / Om, "beta": ODD["beta"] * lam**2,
            "Delta": ODD["Delta"] / (lam * Om**2), "lam": 1.0, "Omega": 1.0,
            "v": ODD["v"] / (lam * Om)}
    assert unit == pytest.approx(LAW_POINT, rel=1e-15)
    a, b = _measured(ODD), _measured(unit)
    assert a.steady and b.steady and a.regime == b.regime == "stick-slip"
    assert a.wells_per_slip == b.wells_per_slip
    assert a.mean_force == pytest.approx(Om**2 * lam * b.mean_force, rel=1e-8)
    assert a.static_force == pytest.approx(Om**2 * lam * b.static_force, rel=1e-3)
    for pt in (a, b):
        assert abs(pt.dissipation_per_distance - pt.mean_force) < 1e-9 * pt.mean_force
        assert "they repeat" in pt.note


def test_a_cycle_that_needs_more_steps_than_the_bound_is_refused():
    """The cost bound: two cycles of the law point need about 12000 Taylor steps; with 50
    allowed the route says why it did not measure."""
    sys_ = _system(LAW_POINT)
    _, _, dt, v_stick, _ = _grid(sys_, FrictionSettings())
    why = stick_slip_cycles(sys_, dt, v_stick, max_steps=50)
    assert why == "0 of 2 cycles within 50 Taylor steps"


def _irregular_point(p: dict) -> FrictionPoint:
    return FrictionPoint(model="sedf_comoving", params=p, eta=0.0, regime="stick-slip",
                         mean_force=-0.5, note="irregular")


def test_only_points_beyond_double_precision_are_measured_again():
    """``ROUNDING e^G`` below ``UNRESOLVED`` (G = 15.5 at the law's third velocity) or the
    CDC: the point as it was.  Beyond long double too (``ROUNDING_LD e^G`` above it: G =
    66.7 at the law's slowest stage): as it was, its note saying so with both numbers."""
    s = FrictionSettings()
    for v in (float(np.geomspace(LAW_V[0], LAW_V[-1], 12)[2]), float(LAW_V[0])):
        p = {**LAW_POINT, "v": v}
        sys_ = _system(p)
        G = 2 * 0.1 / (3 * v)
        pt = _irregular_point(p)
        out = beyond_double(sys_, s, {}, pt, "said", 1.0, 1e-3, 1)
        assert replace(out, note=pt.note) == pt
        if ROUNDING * math.exp(G) < UNRESOLVED:
            assert out.note == pt.note
        else:
            assert ROUNDING_LD * math.exp(G) > UNRESOLVED
            assert "not resolved in double precision" in out.note
            assert "not measured in extended precision" in out.note
            assert f"{math.exp(G):.2g}" in out.note
