"""The period-doubling curve of the strongly forced Duffing oscillator in ``(sigma, h)``
(issue 38, :mod:`numerics.bifurcation.forced`), against independent references.

The model ``x'' + x = mu (-2 zeta x' - alpha x^3 + h cos nu t)``, ``nu = 1 + mu sigma``,
``mu = 1``, ``zeta = 0.05``, ``alpha = 1`` (tests/test_coupled_branch.py's isola at
``h = 20``).  The curve is continued on the defining system ``y(T) - y0 = 0``,
``det(Phi + I) = 1 + tr Phi + det Phi = 0`` (Kuznetsov, *Elements of Applied Bifurcation
Theory*, 3rd ed., sec. 10.3.2), seeded at one period doubling of ``continue_coupled``'s
branch at ``h = 20``, and checked by

- a separate Floquet computation (scipy ``solve_ivp`` DOP853 with its own variational
  equations at ``rtol = 1e-12``, Newton on the period map): a multiplier ``-1`` at two
  points of the curve;
- the one-parameter period doublings of ``continue_coupled`` (``kbm branch``) at
  ``h = 20`` and ``h = 25``: the curve corrected onto those ``h`` gives both of them;
- the same scipy computation with Brent on ``lambda_min + 1`` at the four crossings of
  ``h = 15.9`` (the curve's wavy bottom);
- the flip bifurcation's normal form (Kuznetsov sec. 4.4): just past the curve (inside it,
  where the period-1 orbit has a multiplier below ``-1``) a long integration's
  stroboscopic map alternates between two points, and just before it settles on one;
- ``kbm diagram`` from its own seeds (slow): its period-doubling curves end where the
  seeded curve and the one-parameter doublings say.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from numerics.bifurcation.corrector import correct
from numerics.bifurcation.forced import DrivenProblem, forced_true_curves
from numerics.bifurcation.twoway import joined
from numerics.shooting.coupled_branch import continue_coupled
from _references import duffing_floquet

MU, ZETA, ALPHA = 1.0, 0.05, 1.0
VALUES = {"mu": MU, "zeta": ZETA, "alpha": ALPHA}
RANGES = {"sigma": (-0.6, 1.2), "h": (10.0, 30.0)}
KIND = "period-doubling"


def _rhs(sigma, h):
    nu = 1 + MU * sigma

    def f(t, y):
        return [y[1], -y[0] + MU * (-2 * ZETA * y[1] - ALPHA * y[0] ** 3 + h * math.cos(nu * t))]
    return f, 2 * math.pi / nu


def scipy_floquet(sigma, h, y0):
    """The period-1 response near ``y0`` and its multipliers by scipy alone (Newton on the
    period map, the monodromy from the variational equations, DOP853 at rtol 1e-12)."""
    return duffing_floquet(1 + MU * sigma, 2 * MU * ZETA, MU * ALPHA, MU * h, y0)


def stroboscopic(sigma, h, y0, n):
    """``n + 1`` points of the stroboscopic map ``y0 -> y(T)`` by one scipy integration."""
    f, T = _rhs(sigma, h)
    s = solve_ivp(f, (0, n * T), y0, method="DOP853", rtol=1e-10, atol=1e-10,
                  t_eval=T * np.arange(n + 1))
    return s.y.T


def one_parameter_pds(h):
    br = continue_coupled("duffing-forced", {**VALUES, "h": h, "sigma": 1.0}, "sigma",
                          (0.05, 1.2), directions=(-1,), max_points=150)
    return [s for s in br.special if s.kind == KIND]


@pytest.fixture(scope="module")
def pd_curve():
    pds20 = one_parameter_pds(20.0)
    prob = DrivenProblem("duffing-forced", VALUES, ("sigma", "h"))
    s = min(pds20, key=lambda s: s.parameter)
    seed = np.array([*s.state[:2], s.parameter, 20.0])
    tasks, curves, _ = forced_true_curves(prob, RANGES, [(KIND, seed)], ds=0.02,
                                          max_points=200)
    assert [c.kind for c in curves] == [KIND]
    return prob, np.array(joined(tasks[0].paths)), curves[0], pds20


def on_h(prob, zs, h):
    """The curve's points at ``h`` (Newton with ``h`` fixed from the nearest point of each
    crossing of the line)."""
    G, J = prob.system_for(KIND), prob.jacobian_for(KIND)
    out = []
    for a, b in zip(zs, zs[1:]):
        if (a[3] - h) * (b[3] - h) < 0 or a[3] == h:
            z0 = a if abs(a[3] - h) < abs(b[3] - h) else b
            z, res, _, _ = correct(G, z0, np.array([0.0, 0, 0, 1]), h, jac=J)
            assert res <= 1e-10
            out.append(z)
    return sorted(out, key=lambda z: z[2])


def test_pd_curve_is_converged_and_turns_in_h(pd_curve):
    """Every point solves the defining system to 1e-10; the curve is a U in (sigma, h): both
    ends on the upper bound h = 30, the period-1 orbit flip-unstable inside it."""
    _, zs, curve, _ = pd_curve
    assert curve.detail["residual_max"] <= 1e-10
    assert curve.detail["ends"] == ["bounds", "bounds"]
    (s0, h0), (s1, h1) = curve.points[0], curve.points[-1]
    assert h0 == pytest.approx(30) and h1 == pytest.approx(30) and abs(s0 - s1) > 0.3
    assert 12 < min(p[1] for p in curve.points) < 20


def test_pd_curve_multiplier_minus_one_by_scipy_floquet(pd_curve):
    """At two points of the curve (one on each arm) scipy's own monodromy has a
    multiplier -1 to 1e-6, at the same response; the other one is ``-det Phi = -exp(-2 mu
    zeta T)`` (Liouville's formula: the divergence of the flow is ``-2 mu zeta``)."""
    _, zs, _, _ = pd_curve
    i_low = int(np.argmin(zs[:, 3]))
    for z in (zs[i_low // 2], zs[(i_low + len(zs)) // 2]):
        y, m = scipy_floquet(z[2], z[3], z[:2])
        assert np.max(np.abs(y - z[:2])) < 1e-8
        assert min(abs(m + 1)) <= 1e-6, (z, m)
        T = 2 * math.pi / (1 + MU * z[2])
        assert max(m.real) == pytest.approx(-math.exp(-2 * MU * ZETA * T), abs=1e-9)


def test_pd_curve_meets_the_one_parameter_period_doublings(pd_curve):
    """Corrected onto h = 20 and h = 25 the curve gives the period doublings of
    continue_coupled's branch in sigma at those h (both, to 1e-7)."""
    prob, zs, _, pds20 = pd_curve
    for h, pds in ((20.0, pds20), (25.0, one_parameter_pds(25.0))):
        ref = sorted({round(s.parameter, 9) for s in pds})
        assert len(ref) == 2
        got = [z[2] for z in on_h(prob, zs, h)]
        assert got == pytest.approx(ref, abs=1e-7), (h, got, ref)


@pytest.mark.slow  # 4-7 s; the default run keeps its siblings (five-minute rule)
def test_pd_curve_wavy_bottom_against_scipy_brent(pd_curve):
    """Below the isola's reach (h = 15.9, where the branch of ``kbm branch`` from sigma = 1
    is another orbit) the curve crosses the line four times; each is a zero of scipy's
    ``lambda_min + 1`` in sigma (Brent on the separate Floquet computation) to 1e-9."""
    prob, zs, _, _ = pd_curve
    got = on_h(prob, zs, 15.9)
    assert len(got) == 4
    for z in got:
        def g(q, y0=z[:2]):
            return float(min(scipy_floquet(q, 15.9, y0)[1].real)) + 1
        ref = brentq(g, z[2] - 2e-3, z[2] + 2e-3, xtol=1e-12)
        assert z[2] == pytest.approx(ref, abs=1e-9)


def _alternation(pd_curve, offset, n):
    prob, zs, _, _ = pd_curve
    z = on_h(prob, zs, 20.0)[0]
    Y = stroboscopic(z[2] + offset, 20.0, z[:2] + np.array([0.01, 0.0]), n)
    return float(np.max(np.abs(Y[-1] - Y[-2]))), float(np.max(np.abs(Y[-1] - Y[-3])))


@pytest.mark.slow
def test_period_two_orbit_just_past_the_curve_long_run(pd_curve):
    """The flip's normal form: 0.01 past the curve (h = 20) the stroboscopic map after 400
    periods alternates between two points (period 2); 0.01 before it, it stands still."""
    d1, d2 = _alternation(pd_curve, 0.01, 400)
    assert d1 > 0.5 and d2 < 1e-6
    d1, d2 = _alternation(pd_curve, -0.01, 400)
    assert d1 < 1e-6 and d2 < 1e-6


@pytest.mark.slow  # 3-4 s; kept out of the default run (five-minute rule)
def test_period_two_orbit_past_the_curve(pd_curve):
    """The fast sibling of the long run: 0.02 on either side of the curve, 80 periods (past
    it the alternation is 1.6 while two periods apart the map has come within 1e-2; before
    it the map stands still to 1e-6).  Further in (0.03 past) the period-2 orbit has itself
    lost stability: the doubling curve is the first of a cascade."""
    d1, d2 = _alternation(pd_curve, 0.02, 80)
    assert d1 > 0.5 and d2 < 1e-2
    d1, d2 = _alternation(pd_curve, -0.02, 80)
    assert d1 < 1e-6 and d2 < 1e-6


@pytest.mark.slow
def test_kbm_diagram_finds_the_period_doubling_curves(capsys, pd_curve):
    """``kbm diagram`` from its own seeds: the period-doubling curves end on h = 25 at
    continue_coupled's doublings there, and on h = 18 where the seeded curve crosses, at
    orbits whose scipy monodromy has a multiplier -1 (to 1e-6).  Each arm is reported
    once: the symmetric partner orbit, (x, t) -> (-x, t + T/2), traces the same arm (it
    gave a second copy of each before the seeds' partners were compared)."""
    import json

    from numerics.cli import main

    code = main(["diagram", "duffing-forced", "-p", "mu=1", "-p", "zeta=0.05", "-p",
                 "alpha=1", "--vary", "sigma=0.1:0.8", "--vary", "h=18:25", "--no-averaged",
                 "--json"])
    out, err = capsys.readouterr()
    assert code == 0, err
    pds = [c["points"] for c in json.loads(out)["curves"] if c["kind"] == KIND]
    assert len(pds) == 2
    prob, zs, _, _ = pd_curve
    ref25 = sorted({round(s.parameter, 9) for s in one_parameter_pds(25.0)})
    at18 = on_h(prob, zs, 18.0)
    assert len(ref25) == 2 and len(at18) == 2
    for pts in pds:
        ends = {round(p[1]): p[0] for p in (pts[0], pts[-1])}
        assert set(ends) == {18, 25}
        assert min(abs(ends[25] - r) for r in ref25) < 1e-7
        assert min(abs(ends[18] - z[2]) for z in at18) < 1e-7
    # the two arms: one ends at each doubling of h = 25
    assert sorted(round(next(p[0] for p in (c[0], c[-1]) if round(p[1]) == 25), 7)
                  for c in pds) == pytest.approx(ref25, abs=1e-7)
    for z in at18:
        _, m = scipy_floquet(z[2], 18.0, z[:2])
        assert min(abs(m + 1)) <= 1e-6


def test_symmetric_partner_traces_the_same_curve(pd_curve):
    """The partner of a point of the curve, ``-y(T/2)`` (:meth:`DrivenProblem.partner`), is
    another period-1 orbit at the same ``(sigma, h)`` with a multiplier ``-1``: the scipy
    Floquet computation (Newton on the period map from the partner's state) converges to it
    (1e-8) and finds ``-1`` (1e-6), while the orbit itself is not symmetric (the states
    differ by more than 0.1).  Seeded with both, the continuation reports one curve and
    names the partner."""
    prob, zs, _, _ = pd_curve
    z = zs[len(zs) // 3]
    zp = prob.partner(z)
    assert zp is not None and np.allclose(zp[2:], z[2:])
    assert np.linalg.norm(zp[:2] - z[:2]) > 0.1
    y, m = scipy_floquet(zp[2], zp[3], zp[:2])
    assert np.linalg.norm(np.asarray(y) - zp[:2]) < 1e-8 and min(abs(m + 1)) <= 1e-6
    _, curves, _ = forced_true_curves(prob, RANGES, [(KIND, z), (KIND, zp)], ds=0.02,
                                      max_points=6)
    assert len(curves) == 1 and "symmetric_partner" in curves[0].detail


def test_no_partner_without_the_symmetry():
    """A forced model whose field is not odd under the half-period shift (the quadratic
    force of ``x'' + x = mu (-2 zeta x' - x^2 + h cos nu t)``) has no partner."""
    import sympy as sp

    from kbm.model.forced import ForcedOscillator, Resonance
    from kbm.model.forced import theta
    from kbm.symbols import x, xdot

    zeta, h = sp.symbols("zeta h")
    model = ForcedOscillator("quad-forced", -2 * zeta * xdot - x ** 2 + h * sp.cos(theta),
                             resonance=Resonance(1, 1))
    prob = DrivenProblem(model, {"mu": 0.1, "zeta": 0.05}, ("sigma", "h"))
    assert prob.partner(np.array([0.5, 0.1, 0.0, 1.0])) is None
