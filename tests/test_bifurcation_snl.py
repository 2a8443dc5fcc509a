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
  right-hand side written in this file (other starts than the locator's);

and the end of a heteroclinic cycle of an odd field by a saddle change
(:func:`numerics.bifurcation.connections.saddle_change`), against first-order Melnikov
integrals in closed form and both legs shot here by scipy.
"""

from __future__ import annotations

import math

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


def test_saddle_node_loop_in_reversed_time():
    """The closed-form model with time reversed (``x' -> -x'``: ``f(x, -v)``, so ``f_v = 2 >
    0`` at the saddle-node): the same orbit, now leaving along the strong unstable
    eigenvector and returning along the centre manifold; the located point is again
    ``(0, 0)``."""
    model = custom_model("x + r - x**2*(3*x + 2)/2 - (b - 2 - 7*x/2)*xdot")
    kit = OneDof(model, {"mu": "1"}, ("r", "b"), (0.01, 0.0))
    loop = Loop(-0.1, -0.1, -1, -1)
    g = gap_function(kit, loop)
    b0 = brentq(lambda b: float(g((0.01, b))[0]), -0.05, 0.0, xtol=1e-14)
    accept(kit, loop, (0.01, b0))
    found = locate_saddle_node_loop(kit, loop, (0.01, b0), scale=(0.1, 0.1))
    assert found is not None and kit.d(0, 1, 0.0, 0.0, 0.0, 0.0) == 2.0
    r, b = found["point"]
    assert abs(r) < 1e-12 and abs(b) < 1e-10 and abs(found["gap"]) <= GAP_TOL


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
    from numerics.bifurcation.oned import autonomous_diagram
    from numerics.bifurcation.run import Settings

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


# -- the end of a heteroclinic cycle by a saddle change (connections.saddle_change) --------

#: x'' = -sin(pi x)/pi - s x + m (x^2 - b) x' (x'' + x = mu F, mu = 1): odd, saddles near
#: the odd integers, centres near the even ones
PENDULUM = "x - sin(pi*x)/pi - s*x + m*(x**2 - b)*xdot"


def _pendulum_saddle(s, guess):
    return brentq(lambda x: math.sin(math.pi * x) / math.pi + s * x, guess - 0.4, guess + 0.4,
                  xtol=1e-15)


def _pendulum_leg(s, b, m, x_from, x_to, leave, arrive, section):
    """The velocity gap on ``x = section`` of the connection ``x_from -> x_to`` (unstable
    manifold leaving towards ``leave`` forward, stable manifold arriving from ``arrive``
    backward), shot by scipy on the field written here."""
    def f(x, v):
        return -math.sin(math.pi * x) / math.pi - s * x + m * (x * x - b) * v

    def eig(x):
        fx, fv = -math.cos(math.pi * x) - s, m * (x * x - b)
        r = math.sqrt(fv * fv + 4 * fx)
        return (fv + r) / 2, (fv - r) / 2

    def sec(t, y):
        return y[0] - section
    sec.terminal = True
    eps = 1e-7
    lu, ls = eig(x_from)[0], eig(x_to)[1]
    up = solve_ivp(lambda t, y: [y[1], f(*y)], (0, 400), [x_from + leave * eps,
                   leave * eps * lu], events=sec, rtol=1e-12, atol=1e-14, method="DOP853")
    dn = solve_ivp(lambda t, y: [-y[1], -f(*y)], (0, 400), [x_to + arrive * eps,
                   arrive * eps * ls], events=sec, rtol=1e-12, atol=1e-14, method="DOP853")
    return up.y_events[0][0][1] - dn.y_events[0][0][1]


def test_heteroclinic_cycle_saddle_change_located_and_shot():
    """The heteroclinic cycle ``x_1 -> -x_1 -> x_1`` (``x_1 ~ 1``; leaving to the right,
    turning back before ``x_2 ~ 3``, passing below ``x_1`` to ``-x_1``; the mirror leg by
    the odd symmetry) of ``x'' = -sin(pi x)/pi - s x + m (x^2 - b) x'`` ends where it
    reaches ``x_2``: ``x_1 -> x_2`` and ``x_2 -> -x_1`` both connections.  First-order
    Melnikov on the pendulum's separatrices ``|v| = (2/pi)|cos(pi x/2)|``, with the
    saddles' energies ``E(3) - E(1) = 4 s``: ``4 s = m M_13`` and ``-4 s = m (M_13 +
    M_1,-1)``, ``M_13 = (40 - 8 b)/pi^2 - 64/pi^4``, ``M_1,-1 = (8 - 8 b)/pi^2 - 64/pi^4``,
    so ``b = 11/3 - 8/pi^2`` and ``s = 8 m/(3 pi^2)``.  Located at ``m = 0.05`` from that
    estimate (Newton on both legs' section gaps, each at most GAP_TOL): the saddles are the
    zeros of ``sin(pi x)/pi + s x`` (Brent, 1e-12), both legs shot here by scipy agree to
    1e-8 on the sections ``x = 2`` and ``x = 0``, and the point lies within the first-order
    error of the estimate (measured: ``s/m = 0.3023`` against ``0.2702``, ``b = 2.686``
    against ``2.856``; 0.2933, 2.738 at ``m = 0.025`` and 0.2851, 2.781 at ``m = 0.0125``:
    the error falls slowly, as near a saddle)."""
    from numerics.bifurcation.connections import saddle_change

    m = 0.05
    kit = OneDof(custom_model(PENDULUM), {"mu": "1", "m": str(m)}, ("s", "b"), (0.0, 2.8))
    assert kit.odd
    s0, b0 = 8 * m / (3 * math.pi ** 2), 11 / 3 - 8 / math.pi ** 2
    found = saddle_change(kit, Loop(1.0, -1.0, 1, 1), (s0, b0), 4.0, scale=(0.04, 2.5))
    assert found is not None
    s, b = found["point"]
    assert max(abs(g) for g in found["gaps"]) <= GAP_TOL and found["newton_step"] <= 1e-9
    x1, x2 = _pendulum_saddle(s, 1.0), _pendulum_saddle(s, 3.0)
    assert found["saddles"] == pytest.approx([x1, x2, -x1], abs=1e-12)
    assert abs(_pendulum_leg(s, b, m, x1, x2, 1, -1, 2.0)) < 1e-8
    assert abs(_pendulum_leg(s, b, m, x2, -x1, -1, 1, 0.0)) < 1e-8
    assert abs(s / s0 - 1) < 0.15 and abs(b - b0) < 0.2


@pytest.mark.slow
def test_heteroclinic_cycle_curve_ends_at_the_saddle_change():
    """The heteroclinic cycle's curve of :func:`test_heteroclinic_cycle_saddle_change_located_
    and_shot` (its fast sibling), continued from a Brent root of its gap at ``s = 1.5 s_0``
    towards smaller ``s``: every point's gap at most GAP_TOL, and its end within 5 % of the
    box (the diagram's rule for naming the end ``saddle-change``) of the located point
    (measured: ``1e-6`` in ``s``, ``9e-5`` in ``b``)."""
    from numerics.bifurcation.connections import saddle_change
    from numerics.bifurcation.curve import continue_curve

    m = 0.05
    kit = OneDof(custom_model(PENDULUM), {"mu": "1", "m": str(m)}, ("s", "b"), (0.0, 2.8))
    s1 = 1.5 * 8 * m / (3 * math.pi ** 2)
    loop = Loop(1.0, -1.0, 1, 1)
    g = gap_function(kit, loop)
    b1 = brentq(lambda b: float(g((s1, b))[0]), 2.3, 2.8, xtol=1e-14)
    accept(kit, loop, (s1, b1))
    path = continue_curve(g, (s1, b1), tangent=[-1, 0], ds=0.002, ds_max=0.01,
                          bounds={0: (0.0, 0.04), 1: (1.5, 4.0)}, scale=[0.04, 2.5],
                          tol=GAP_TOL, fd_step=1e-6, on_point=lambda p: accept(kit, loop, p.z))
    assert all(p.residual <= GAP_TOL for p in path.points)
    end = path.points[-1].z
    found = saddle_change(kit, loop, end, 4.0, scale=(0.04, 2.5))
    assert found is not None
    assert math.hypot((found["point"][0] - end[0]) / 0.04,
                      (found["point"][1] - end[1]) / 2.5) < 0.05
