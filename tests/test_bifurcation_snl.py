"""The saddle-node loop located (issue 38): where a homoclinic curve ends on the fold of its
saddle, the non-central saddle-node homoclinic orbit (Kuznetsov, *Elements of Applied
Bifurcation Theory*, sec. 7.1.2; Schecter 1987), checked against

- a model with the orbit in closed form:
  ``x'' = r - x^2 (3 x + 2)/2 + (b - 2 - 7 x/2) x'``.  At ``r = b = 0`` the curve
  ``F = (v + x (x + 1))^2 - x^2 (x + 1) = 0`` is invariant (``dF/dt = -(3 x + 2) F``,
  checked here by sympy), the origin is a saddle-node (``f = f_x = 0``, ``f_v = -2``) and
  the piece of ``F = 0`` over ``-1 <= x <= 0`` leaves it along the centre manifold
  (``v ~ -x^2/2``) and returns along the strong stable eigenvector ``(1, -2)``: the
  saddle-node loop is exactly ``(r, b) = (0, 0)``;
- the SEDF (paper eq. 3) at ``mu = 0.1``, ``lam = 1``: its fold line ``Delta =
  -x/sin(2 pi x)``, ``tan(2 pi x) = 2 pi x`` (closed form), and at the located points the
  saddle-node's centre branch and strong stable manifold shot here by scipy on a
  right-hand side written in this file (other starts than the locator's).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from kbm import custom_model
from numerics.bifurcation.autonomous import OneDof
from numerics.bifurcation.connections import GAP_TOL, Loop, accept, gap_function
from numerics.bifurcation.saddle_node_loop import locate_saddle_node_loop

#: x'' + x = mu F with mu = 1: x'' = r - x^2 (3x + 2)/2 + (b - 2 - 7x/2) x'
EXACT = "x + r - x**2*(3*x + 2)/2 + (b - 2 - 7*x/2)*xdot"


def test_exact_model_invariant_curve():
    """The closed form the locator is checked against: ``F = 0`` is invariant at
    ``r = b = 0`` and the origin is a saddle-node with ``f_v = -2``."""
    x, v = sp.symbols("x v")
    f = -x ** 2 * (3 * x + 2) / 2 + (-2 - sp.Rational(7, 2) * x) * v
    F = (v + x * (x + 1)) ** 2 - x ** 2 * (x + 1)
    assert sp.simplify(sp.diff(F, x) * v + sp.diff(F, v) * f + (3 * x + 2) * F) == 0
    f0 = f.subs(v, 0)
    assert f0.subs(x, 0) == 0 and sp.diff(f0, x).subs(x, 0) == 0
    assert sp.diff(f, v).subs({x: 0, v: 0}) == -2


def test_saddle_node_loop_located_exactly():
    """From a point of the homoclinic curve of the saddle near ``-sqrt(r)`` at ``r = 0.01``
    (Brent on its gap), the located saddle-node loop is ``(0, 0)`` (closed form, module
    docstring): ``r`` within 1e-12, ``b`` within 1e-10, the gap at most GAP_TOL."""
    kit = OneDof(custom_model(EXACT), {"mu": "1"}, ("r", "b"), (0.01, 0.0))
    loop = Loop(-0.1, -0.1, -1, -1)
    g = gap_function(kit, loop)
    b0 = brentq(lambda b: float(g((0.01, b))[0]), -0.05, 0.0, xtol=1e-14)
    accept(kit, loop, (0.01, b0))
    assert loop.x_from == pytest.approx(-0.1094, abs=1e-4)  # the saddle, left of the node
    found = locate_saddle_node_loop(kit, loop, (0.01, b0), scale=(0.1, 0.1))
    assert found is not None and found["along"] == "b"
    r, b = found["point"]
    assert abs(r) < 1e-12 and abs(b) < 1e-10 and abs(found["x"]) < 1e-12
    assert abs(found["gap"]) <= GAP_TOL and found["parameter_step"] <= 1e-10
    assert found["fold_residual"] < 1e-14
    # the other sides are no saddle-node loop here: the centre branch leaves to the left
    assert locate_saddle_node_loop(kit, Loop(loop.x_from, loop.x_from, 1, 1), (0.01, b0),
                                   scale=(0.1, 0.1)) is None


def _sedf_fold():
    """The SEDF fold of equilibria near ``x = 1.74`` in closed form."""
    x = brentq(lambda s: math.tan(2 * math.pi * s) - 2 * math.pi * s, 1.70, 1.74, xtol=1e-15)
    return x, -x / math.sin(2 * math.pi * x)


def _sedf_snl_gap(beta, through_middle, mu=0.1):
    """The gap of the saddle-node loop ``x_sn -> -x_sn`` of the SEDF
    ``x'' + mu (beta x^2 - 1) x' + Delta sin(2 pi x) + x = 0`` on its fold, shot by scipy:
    the centre branch from ``u = -2e-4`` on ``v = k u^2`` (``k = -f_xx/(2 f_v)``) forward,
    the strong stable manifold of ``-x_sn`` from ``1e-6`` along ``(1, f_v)`` backward
    (arriving from the left, or from the right through the middle), compared where they
    first turn, or where they cross ``x = 0`` (through the middle)."""
    xs, delta = _sedf_fold()
    fv = -mu * (beta * xs ** 2 - 1)
    fxx = 4 * math.pi ** 2 * delta * math.sin(2 * math.pi * xs)
    k = -fxx / (2 * fv)
    assert k < 0  # the centre branch leaves to the left

    def rhs(sign):
        return lambda t, y: [sign * y[1], sign * (-mu * (beta * y[0] ** 2 - 1) * y[1]
                                                   - delta * math.sin(2 * math.pi * y[0])
                                                   - y[0])]

    def event(t, y):
        return y[0] if through_middle else y[1]
    event.terminal = True
    u = -2e-4
    side = 1 if through_middle else -1
    up = solve_ivp(rhs(1), (0, 400), [xs + u, k * u * u], events=event, rtol=1e-12,
                   atol=1e-14, method="DOP853")
    dn = solve_ivp(rhs(-1), (0, 400), [-xs + side * 1e-6, side * 1e-6 * fv], events=event,
                   rtol=1e-12, atol=1e-14, method="DOP853")
    i = 1 if through_middle else 0
    return up.y_events[0][0][i] - dn.y_events[0][0][i]


@pytest.mark.parametrize("through_middle, start, located", [
    (False, (1.742739, 1.502306), 1.502366547595883),
    (True, (1.742739, 1.502428), 1.5024202348946578)])
def test_sedf_saddle_node_loops_shot_by_scipy(through_middle, start, located):
    """The SEDF heteroclinic cycles of the pair ``+-1.73`` end on the fold line at two
    saddle-node loops (the last session named the curves' last points
    ``(1.742739, 1.502306)`` and ``(1.742739, 1.502428)``).  Located from those: ``Delta``
    the closed-form fold to 1e-12, and the scipy shot of the module docstring changes sign
    within ``1e-7`` of the located ``beta`` and is below ``1e-8`` there."""
    kit = OneDof("sedf", {"mu": "0.1", "lam": "1"}, ("Delta", "beta"), (3.0, 1.0))
    xs, delta = _sedf_fold()
    loop = Loop(1.7337, -1.7337, -1, 1 if through_middle else -1, through_middle)
    found = locate_saddle_node_loop(kit, loop, start, scale=(6.0, 1.3))
    assert found is not None and found["along"] == "beta"
    d, b = found["point"]
    assert abs(d - delta) < 1e-12 and abs(found["x"] - xs) < 1e-12
    assert abs(found["gap"]) <= GAP_TOL and found["parameter_step"] <= 1e-10
    assert b == pytest.approx(located, abs=1e-9)  # regression (measured, this session)
    assert abs(_sedf_snl_gap(b, through_middle)) < 1e-8
    lo, hi = _sedf_snl_gap(b - 1e-7, through_middle), _sedf_snl_gap(b + 1e-7, through_middle)
    assert lo * hi < 0


@pytest.mark.slow
def test_diagram_reports_the_located_saddle_node_loop():
    """The whole diagram of the closed-form model over ``r`` in ``[-0.02, 0.05]``, ``b`` in
    ``[-0.1, 0.1]`` (about 10 s; :func:`test_saddle_node_loop_located_exactly` is its fast
    sibling): the fold line ``r = 0``, the homoclinic curve of the saddle near
    ``-sqrt(r)`` followed to within ``1e-5`` of the fold (``b ~ -0.49 sqrt(r)`` there:
    tangent to it), and the ``saddle-node-loop`` reported at the located ``(0, 0)``, not at
    the curve's last point."""
    from numerics.bifurcation.oned import Settings, autonomous_diagram

    d = autonomous_diagram(custom_model(EXACT), {"mu": "1"}, ("r", "b"),
                           {"r": (-0.02, 0.05), "b": (-0.1, 0.1)},
                           settings=Settings(grid=(9, 5), averaged=False, L=2.0))
    (hom,) = [c for c in d.curves if c.kind == "homoclinic"]
    assert hom.detail["gap_max"] <= GAP_TOL
    (snl,) = [p for p in d.codim2 if p.kind == "saddle-node-loop"]
    assert not [p for p in d.codim2 if p.kind == "connection-end"]
    r, b = snl.point
    assert abs(r) < 1e-12 and abs(b) < 1e-10 and abs(snl.detail["gap"]) <= GAP_TOL
    end = min((hom.points[0], hom.points[-1]), key=lambda q: math.hypot(*q))
    assert snl.detail["last_curve_point"] == pytest.approx(list(end), abs=1e-15)
    assert 0 < end[0] < 1e-4 and abs(end[1]) > 10 * abs(b)
