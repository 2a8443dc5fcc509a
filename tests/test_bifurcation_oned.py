"""Two-parameter diagrams of autonomous one-degree-of-freedom models (issue 38), each true
curve checked against an independent computation:

- the first Lyapunov coefficient of ``x'' + x = mu (nu - x^2) x'`` at its Hopf point is
  ``-mu/8`` (van der Pol's supercritical Hopf; Guckenheimer & Holmes (3.4.11));
- the SEDF (paper eq. 3): its equilibria ``x + Delta sin(2 pi x/lam) = 0`` do not depend on
  ``beta``, so the folds of equilibria are the lines ``Delta = -x/sin(2 pi x)`` with
  ``tan(2 pi x) = 2 pi x`` (closed form), and the Hopf curve of a well at ``x_e`` is
  ``beta = 1/x_e^2`` (``tr J = -mu (beta x_e^2 - 1)``);
- its heteroclinic curves: at each checked point the two manifolds are shot here by scipy
  on a right-hand side written in this file, and their turning points agree; at
  ``beta = 1`` and ``0.5`` the curves pass the one-parameter ends of issue 38
  (``Delta = 3.2494``, ``3.9876``);
- the fold of cycles of ``F = (-nu + x^2 - x^4) x'`` over ``(nu, mu)`` against the
  one-parameter continuation's fold at fixed ``mu`` (:func:`numerics.cycles.continue_cycles`)
  and against KBM order 3 (``O(mu^4)`` apart; orders 1-2 give ``1/8``, ``O(mu^2)`` apart).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from kbm import custom_model
from numerics.bifurcation.autonomous import OneDof
from numerics.bifurcation.connections import GAP_TOL, Loop, gap_function, scan
from numerics.bifurcation.curve import continue_curve
from numerics.flow import compile_model

SEDF = ("sedf", {"mu": "0.1", "lam": "1"}, ("Delta", "beta"))
BOX = {0: (0.0, 6.0), 1: (0.3, 1.6)}


_PLANES = {}


def _plane_kit(axes):
    if axes not in _PLANES:
        params = {"mu": "0.1", "lam": "1", "beta": "0.5", "Delta": "4"}
        at = tuple(float(params[k]) for k in axes)
        _PLANES[axes] = (OneDof("sedf", params, axes, at), params)
    return _PLANES[axes]


@settings(max_examples=30)
@given(st.sampled_from([("Delta", "beta"), ("beta", "lam"), ("Delta", "mu")]),
       st.floats(0.3, 6.0), st.floats(0.05, 1.6))
def test_compiled_on_the_plane_equals_compile_model(axes, a, b):
    """:meth:`OneDof.compiled` at ``(a, b)`` (the values from two parameter lines bound
    once, no sympy) is :func:`numerics.flow.compile_model`'s model there: the same parameter
    vector bit for bit, the same bound values; over ``(Delta, mu)``, where ``delta =
    Delta/mu`` depends on both, it is compile_model's itself."""
    kit, params = _plane_kit(axes)
    assert (kit._plane is None) == (axes == ("Delta", "mu"))
    cm = kit.compiled(a, b)
    ref = compile_model("sedf", {**params, axes[0]: a, axes[1]: b})
    assert cm.pvec == ref.pvec
    assert (cm.omega0, cm.plus_factor) == (ref.omega0, ref.plus_factor)
    assert cm.bound.values == ref.bound.values


def test_lyapunov_coefficient_of_van_der_pol():
    kit = OneDof(custom_model("(nu - x**2)*xdot - c*x"), {"mu": "0.2"}, ("nu", "c"), (0.0, 1.0))
    assert kit.lyapunov(0.0, 0.0, 1.0) == pytest.approx(-0.2 / 8, rel=1e-12)
    G, tests = kit.hopf()
    path = continue_curve(G, [0.01, 0.01, 1.0], ds=0.05, ds_max=0.1,
                          bounds={1: (-1, 1), 2: (0.5, 2.0)})
    assert path.end == "bounds"
    assert max(abs(p.z[1]) for p in path.points) < 1e-12  # nu = 0 on the whole curve


def test_sedf_folds_and_hopf_curves_closed_form():
    kit = OneDof(*SEDF, (3.0, 1.0))
    # the fold of equilibria born near x = 1.74: tan(2 pi x) = 2 pi x
    x = brentq(lambda s: math.tan(2 * math.pi * s) - 2 * math.pi * s, 1.70, 1.74)
    delta_sn = -x / math.sin(2 * math.pi * x)
    G, _ = kit.saddle_node()
    path = continue_curve(G, [x + 0.01, delta_sn + 0.01, 1.0], tangent=[0, 0, 1], ds=0.1,
                          ds_max=0.3, bounds={1: (0, 6), 2: (0.3, 1.6)}, tol=1e-12)
    assert path.end == "bounds"
    assert all(abs(p.z[1] - delta_sn) < 1e-11 for p in path.points)
    G, tests = kit.hopf()
    path = continue_curve(G, [0.96, 4.0, 1.07], tangent=[0, 1, 0], ds=0.05, ds_max=0.2,
                          bounds={1: (0, 6), 2: (0.3, 1.6)}, tests=tests, tol=1e-12)
    for p in path.points:
        xe, d, b = p.z
        assert abs(xe + d * math.sin(2 * math.pi * xe)) < 1e-11
        assert abs(b - 1 / xe ** 2) < 1e-11
    # the Bautin point (first Lyapunov coefficient zero) on the well at x = 0.97
    (ev,) = [e for e in path.events if e.name == "bautin"]
    assert abs(kit.lyapunov(*ev.z)) < 1e-9 and 5.8 < ev.z[1] < 6.0


def _manifolds(delta, beta, xs, mu, event, side):
    """The points where the unstable manifold of the saddle near ``xs`` (forward, leaving
    left) and the stable one of ``-xs`` (backward, leaving on ``side`` = +-1) first meet
    ``event``, shot by scipy on the SEDF written here:
    x'' + mu (beta x^2 - 1) x' + Delta sin(2 pi x) + x = 0."""
    xs = brentq(lambda s: s + delta * math.sin(2 * math.pi * s), xs - 0.1, xs + 0.1,
                xtol=1e-15)
    fx = -1 - 2 * math.pi * delta * math.cos(2 * math.pi * xs)
    fv = -mu * (beta * xs ** 2 - 1)
    lu = (fv + math.sqrt(fv ** 2 + 4 * fx)) / 2
    ls = (fv - math.sqrt(fv ** 2 + 4 * fx)) / 2  # the stable one at -xs, same fv, fx

    def rhs(sign):
        return lambda t, y: [sign * y[1], sign * (-mu * (beta * y[0] ** 2 - 1) * y[1]
                                                   - delta * math.sin(2 * math.pi * y[0])
                                                   - y[0])]

    event.terminal = True
    eps = 1e-7
    up = solve_ivp(rhs(1), (0, 100), [xs - eps, -eps * lu], events=event, rtol=1e-12,
                   atol=1e-14, method="DOP853")
    dn = solve_ivp(rhs(-1), (0, 100), [-xs + side * eps, side * eps * ls], events=event,
                   rtol=1e-12, atol=1e-14, method="DOP853")
    return up.y_events[0][0], dn.y_events[0][0]


def _shoot(delta, beta, xs, mu=0.1):
    """The gap of the heteroclinic cycle through +-xs at the turning points (x' = 0)."""
    up, dn = _manifolds(delta, beta, xs, mu, lambda t, y: y[1], -1)
    return up[0] - dn[0]


def test_sedf_heteroclinic_curves_shot_independently():
    kit = OneDof(*SEDF, (3.0, 1.0))
    found = {}
    for b in (0.5, 1.0):
        (loop, z0), = scan(kit, [(a, b) for a in np.linspace(2.9, 4.3, 8)], 4.0)
        found[b] = (loop, z0)
    assert found[1.0][1][0] == pytest.approx(3.24943, abs=2e-5)  # issue 38's end at beta = 1
    assert found[0.5][1][0] == pytest.approx(3.98757, abs=2e-5)  # and at beta = 0.5
    loop0, z0 = found[1.0]
    loop = Loop(loop0.x_from, loop0.x_to, loop0.leave, loop0.arrive)
    path = continue_curve(gap_function(kit, loop), z0, tangent=[1, 0], ds=0.05, ds_max=0.3,
                          bounds=BOX, scale=[6, 1.3], tol=GAP_TOL, fd_step=1e-6,
                          on_point=lambda p: __import__(
                              "numerics.bifurcation.connections", fromlist=["accept"]
                          ).accept(kit, loop, p.z))
    assert path.end == "bounds" and path.points[-1].z[0] == 6.0
    assert path.points[-1].z[1] > 0.75  # beta = 0.75 is not reached by Delta = 6
    for p in path.points[::4]:
        assert p.residual <= GAP_TOL
        assert abs(_shoot(p.z[0], p.z[1], loop.x_from)) < 1e-7


@pytest.mark.slow
def test_fold_model_against_one_parameter_folds_and_kbm():
    from numerics.bifurcation.oned import autonomous_diagram
    from numerics.bifurcation.run import Settings
    from numerics.cycles import continue_cycles

    model = custom_model("(-nu + x**2 - x**4)*xdot")
    d = autonomous_diagram(model, {}, ("nu", "mu"), {"nu": (0.1, 0.15), "mu": (0.05, 0.3)},
                           settings=Settings(grid=(5, 5), max_points=200, orders=(1, 3)))
    true = [c for c in d.curves if c.kind == "fold" and c.method == "true"]
    assert len(true) == 1
    pts = np.array(true[0].points)
    for mu in (0.1, 0.2):
        br = continue_cycles(model, {"mu": mu, "nu": 0.11}, "nu", (0.1, 0.15), rtol=1e-12)
        nu_b = br.folds()[0].parameter
        nu_d = float(np.interp(mu, pts[:, 1][np.argsort(pts[:, 1])], pts[:, 0][np.argsort(pts[:, 1])]))
        assert abs(nu_b - nu_d) < 2e-6
    avg = {c.order: np.array(c.points) for c in d.curves if c.method == "averaged"}
    assert np.allclose(avg[1][:, 0], 0.125, atol=1e-12)
    # order 3 is closer to the true curve than order 1 (the O(mu^2) shift) at mu >= 0.1
    for nu3, mu in avg[3]:
        if mu >= 0.1:
            nu_t = float(np.interp(mu, np.sort(pts[:, 1]), pts[:, 0][np.argsort(pts[:, 1])]))
            assert abs(nu3 - nu_t) < 0.2 * abs(0.125 - nu_t)


def _shoot_middle(delta, beta, xs, mu=0.1):
    """The velocity gap at ``x = 0`` of the connection ``xs -> -xs`` through the middle
    (the unstable manifold of ``xs`` leaving left, the stable one of ``-xs`` arriving from
    the right), shot by scipy on the SEDF written here (a section the connection crosses
    transversally, not the one of :func:`numerics.bifurcation.connections.section_gap`)."""
    up, dn = _manifolds(delta, beta, xs, mu, lambda t, y: y[0], 1)
    return up[1] - dn[1]


def test_sedf_connection_through_the_middle():
    """The loop of the saddle 2.613 (Delta = 4) that passes its mirror saddle: the turning
    points' gap jumps by 0.8 there, so the scan's root is the heteroclinic cycle +-2.613
    through the middle, found and continued on the section gap (smooth) with every point
    below GAP_TOL; each checked point shot here on the section x = 0."""
    kit = OneDof(*SEDF, (4.0, 0.6))
    found = scan(kit, [(4.0, b) for b in np.linspace(0.5, 0.7, 5)], 4.0)
    (loop, z0), = found  # the false homoclinic root at the same point is dropped
    assert loop.section and not loop.homoclinic
    assert loop.x_from == pytest.approx(2.6133139682, abs=1e-9) and loop.x_to == -loop.x_from
    assert "through the middle" in loop.label()
    assert z0[1] == pytest.approx(0.57617440575, abs=1e-10)
    assert abs(_shoot_middle(4.0, z0[1], loop.x_from)) < 1e-8
    # smooth: the gap is linear within 1e-6 of the root on both sides (slope ~ 8)
    g = gap_function(kit, loop.copy())
    lo, mid, hi = (float(g((4.0, z0[1] + d))[0]) for d in (-1e-6, 0.0, 1e-6))
    assert abs(mid) <= GAP_TOL and lo * hi < 0
    assert abs((hi - mid) / (mid - lo) - 1) < 1e-3
    from numerics.bifurcation.connections import accept

    path = continue_curve(g, z0, tangent=[1, 0], ds=0.05, ds_max=0.2,
                          bounds={0: (3.5, 4.5), 1: (0.5, 0.7)}, scale=[1, 0.2], tol=GAP_TOL,
                          fd_step=1e-6, on_point=lambda p: accept(kit, loop, p.z))
    assert path.end == "bounds" and path.points[-1].z[0] == 4.5
    assert all(p.residual <= GAP_TOL for p in path.points)
    for p in path.points[::3]:
        assert abs(_shoot_middle(p.z[0], p.z[1], loop.x_from)) < 1e-8


def test_neutral_saddle_loop_located():
    """``x'' = x - x^3 + mu (nu + c x^2 - x^4) x'`` (mu = 0.1): the saddle at the origin has
    ``tr J = mu nu`` (closed form), so the homoclinic curve's neutral saddle loop, where a
    fold of cycles ends (Kuznetsov sec. 6.2), is at ``nu = 0``; there the Melnikov
    integral on ``x = sqrt(2) sech t`` gives ``c = 8/7`` to first order in mu.  The
    located point's manifolds are shot here by scipy (turning points)."""
    from numerics.bifurcation.oned import autonomous_diagram
    from numerics.bifurcation.run import Settings

    model = custom_model("k*(2*x - x**3) + (nu + c*x**2 - x**4)*xdot")
    d = autonomous_diagram(model, {"mu": "0.1", "k": "10"}, ("nu", "c"),
                           {"nu": (-0.04, 0.06), "c": (0.9, 1.4)},
                           settings=Settings(grid=(5, 5), averaged=False))
    (hom,) = [c for c in d.curves if c.kind == "homoclinic"]
    assert hom.detail["gap_max"] <= GAP_TOL
    (ns,) = [p for p in d.codim2 if p.kind == "neutral-saddle-loop"]
    nu, c = ns.point
    assert abs(nu) < 1e-9 and abs(ns.detail["gap"]) <= GAP_TOL
    assert abs(c - 8 / 7) < 1e-3

    def rhs(sign):
        return lambda t, y: [sign * y[1], sign * (y[0] - y[0] ** 3 + 0.1 * (
            nu + c * y[0] ** 2 - y[0] ** 4) * y[1])]

    def turn(t, y):
        return y[1]
    turn.terminal = True
    tr = 0.1 * nu
    lu, ls = (tr + math.sqrt(tr ** 2 + 4)) / 2, (tr - math.sqrt(tr ** 2 + 4)) / 2
    eps = 1e-7
    up = solve_ivp(rhs(1), (0, 100), [eps, eps * lu], events=turn, rtol=1e-12, atol=1e-14,
                   method="DOP853")
    dn = solve_ivp(rhs(-1), (0, 100), [eps, eps * ls], events=turn, rtol=1e-12, atol=1e-14,
                   method="DOP853")
    assert abs(up.y_events[0][0][0] - dn.y_events[0][0][0]) < 1e-8


def test_neutral_saddle_loop_eigenvalues_independent():
    """The neutral saddle loop of :func:`test_neutral_saddle_loop_located`, checked by an
    independent computation of the saddle's eigenvalues: the Jacobian of the right-hand
    side written here (central differences) at its saddle ``x = 0``, ``numpy.linalg.eigvals``;
    ``lambda_u + lambda_s = 0`` to 1e-9 at the located point (Kuznetsov sec. 6.2: the
    saddle quantity vanishes at a neutral saddle loop).  The point is located on a short
    piece of the homoclinic curve continued from a Brent root of the gap (fast sibling of
    the whole diagram's test)."""
    model = custom_model("k*(2*x - x**3) + (nu + c*x**2 - x**4)*xdot")
    kit = OneDof(model, {"mu": "0.1", "k": "10"}, ("nu", "c"), (0.0, 1.14))
    from numerics.bifurcation.connections import saddle_quantity

    loop = Loop(0.0, 0.0, 1, 1)
    g = gap_function(kit, loop)
    c0 = brentq(lambda c: float(g((-0.01, c))[0]), 1.1, 1.2, xtol=1e-14)
    path = continue_curve(g, (-0.01, c0), tangent=[1, 0], ds=0.005, ds_max=0.01,
                          bounds={0: (-0.02, 0.01), 1: (1.0, 1.3)}, scale=[0.1, 0.5],
                          tol=GAP_TOL, fd_step=1e-6,
                          tests={"saddle-quantity": saddle_quantity(kit, loop)})
    (ev,) = [e for e in path.events if e.name == "saddle-quantity"]
    nu, c = ev.z
    assert abs(ev.residual) <= GAP_TOL

    def field(x, v):
        return x - x ** 3 + 0.1 * (nu + c * x ** 2 - x ** 4) * v
    xs = brentq(lambda x: field(x, 0.0), -0.5, 0.5, xtol=1e-15)
    h = 1e-6
    J = np.array([[0.0, 1.0],
                  [(field(xs + h, 0) - field(xs - h, 0)) / (2 * h),
                   (field(xs, h) - field(xs, -h)) / (2 * h)]])
    lam = np.linalg.eigvals(J)
    assert np.all(np.isreal(lam)) and lam.real.min() < 0 < lam.real.max()  # a saddle
    assert abs(lam.real.sum()) < 1e-9


def _sc_field(s, b):
    """``x'' = -x + x^3 + s + 0.1 (b - x^2) x'`` (``x'' + x = mu F``, ``F = 10 (x^3 + s)
    + (b - x^2) x'``, mu = 0.1), written here."""
    return lambda x, v: -x + x ** 3 + s + 0.1 * (b - x * x) * v


def _sc_leg(s, b, x_from, x_to):
    """The velocity gap on the section ``x = 0`` of the connection ``x_from -> x_to``
    (unstable manifold of ``x_from`` forward, stable manifold of ``x_to`` backward), shot
    by scipy."""
    f = _sc_field(s, b)

    def eig(x):
        fx = (f(x + 1e-7, 0) - f(x - 1e-7, 0)) / 2e-7
        tr = 0.1 * (b - x * x)
        r = math.sqrt(tr * tr + 4 * fx)
        return (tr + r) / 2, (tr - r) / 2

    def sec(t, y):
        return y[0]
    sec.terminal = True
    side = 1.0 if x_to > x_from else -1.0
    lu, _ = eig(x_from)
    _, ls = eig(x_to)
    eps = 1e-7
    up = solve_ivp(lambda t, y: [y[1], f(*y)], (0, 200), [x_from + side * eps,
                   side * eps * lu], events=sec, rtol=1e-12, atol=1e-14, method="DOP853")
    dn = solve_ivp(lambda t, y: [-y[1], -f(*y)], (0, 200), [x_to - side * eps,
                   -side * eps * ls], events=sec, rtol=1e-12, atol=1e-14, method="DOP853")
    return up.y_events[0][0][1] - dn.y_events[0][0][1]


def test_saddle_change_located_and_shot():
    """``x'' = -x + x^3 + s + mu (b - x^2) x'`` (mu = 0.1): the loop of the left saddle
    ``x_1 ~ -1`` around the centre ends where its manifold reaches the right saddle
    ``x_2 ~ 1`` (a saddle change: the heteroclinic cycle ``x_1 -> x_2 -> x_1``).  At
    ``s = 0`` the field is odd, so the cycle is there exactly; Melnikov along the
    separatrix ``v = (1 - x^2)/sqrt 2`` gives ``int (b - x^2)(1 - x^2) dx = 0``,
    ``b = 1/5`` to first order in mu.  Located from a homoclinic point at ``s = -1e-3``
    (Brent on the gap): ``s`` within 1e-9 of 0, both legs shot here by scipy on the
    section ``x = 0`` within 1e-8."""
    from numerics.bifurcation.connections import saddle_change

    model = custom_model("k*(x**3 + s) + (b - x**2)*xdot")
    kit = OneDof(model, {"mu": "0.1", "k": "10"}, ("s", "b"), (0.0, 0.2))
    loop = Loop(-1.0, -1.0, 1, 1)
    g = gap_function(kit, loop)
    b0 = brentq(lambda b: float(g((-1e-3, b))[0]), 0.19, 0.205, xtol=1e-14)
    from numerics.bifurcation.connections import accept

    accept(kit, loop, (-1e-3, b0))
    found = saddle_change(kit, loop, (-1e-3, b0), 3.0, scale=(0.12, 0.35))
    assert found is not None
    s, b = found["point"]
    assert abs(s) < 1e-9 and abs(b - 0.2) < 1e-3
    assert max(abs(v) for v in found["gaps"]) <= GAP_TOL
    x1, x2 = found["saddles"]
    assert x1 == pytest.approx(-1.0, abs=1e-12) and x2 == pytest.approx(1.0, abs=1e-12)
    assert abs(_sc_leg(s, b, -1.0, 1.0)) < 1e-8 and abs(_sc_leg(s, b, 1.0, -1.0)) < 1e-8
    # the homoclinic point at s = -1e-3 lies within the diagram's 5 % of the box (0.12 x
    # 0.35) of the located point (measured: 3.0e-3 in b)
    assert math.hypot((s + 1e-3) / 0.12, (b - b0) / 0.35) < 0.05


def test_fold_of_cycles_ends_at_the_neutral_saddle_loop():
    """The fold of cycles of ``x'' = x - x^3 + mu (nu + c x^2 - x^4) x'`` (mu = 0.1) near
    the homoclinic loop ``x = sqrt 2 sech t`` of the saddle at 0 heads to the neutral saddle
    loop ``nu = 0`` (Kuznetsov sec. 6.2): with ``sigma = mu nu`` the cycle's
    ``int div f dt = mu nu T + mu int (c x^2 - x^4) dt`` along the loop,
    ``mu (4 c - 16/3)``, so the fold (``int div f = 0``) has ``nu T = 16/3 - 4 c`` to first
    order: ``nu -> 0`` as ``T -> oo``, at ``c -> 8/7`` (Melnikov).  The fold curve's
    distance to the homoclinic curve falls like ``exp(-lambda_u T)``, ``lambda_u = 1``.
    Continued from a point of the diagram's fold curve (corrected by Newton) until
    ``T = 26``; in double precision it can go no closer (at ``T ~ 28`` the cycle is
    ``1e-12`` from the saddle, and the continuation's ``x0`` turns to noise), so the end is
    checked by the law, not by a converged point at ``nu = 0``."""
    model = custom_model("k*(2*x - x**3) + (nu + c*x**2 - x**4)*xdot")
    kit = OneDof(model, {"mu": "0.1", "k": "10"}, ("nu", "c"), (0.0, 1.14))
    z0 = np.array([-8.106987888809e-4, 17.7018958601, 0.06, 1.0677916462539])
    path = continue_curve(kit.cycle_fold(), z0, tangent=[0, 0, -1.0, 1.25], ds=0.01,
                          ds_max=0.04, bounds={2: (0.0, 0.0601), 3: (1.0, 1.3)},
                          max_points=40, tol=1e-10, fd_step=1e-7,
                          scale=[1.0, 17.7, 0.1, 0.5],
                          stop=lambda pt, p: "period" if pt.z[1] > 26 else None)
    assert path.end == "stopped" and all(p.residual <= 1e-10 for p in path.points)
    P = np.array([p.z for p in path.points])
    T, nu, c = P[:, 1], P[:, 2], P[:, 3]
    # first-order law (measured: -5e-5 .. -8e-5 against nu T ~ 0.76)
    assert np.all(np.abs(nu * T + 4 * c - 16 / 3) < 1e-3)
    # T = T0 + K/nu with K = 16/3 - 4 (8/7) = 0.761905 (measured 0.762045)
    K = np.linalg.lstsq(np.vstack([np.ones_like(nu), 1 / nu]).T, T, rcond=None)[0][1]
    assert abs(K / (16 / 3 - 32 / 7) - 1) < 1e-3
    # on the homoclinic curve within exp(-lambda_u T): the gap's Brent root c_h(nu)
    g = gap_function(kit, Loop(0.0, 0.0, 1, 1))
    sel = path.points[::4]
    dc = [p.z[3] - brentq(lambda cc: float(g((p.z[2], cc))[0]), p.z[3] - 0.01,
                          p.z[3] + 0.01, xtol=1e-15) for p in sel]
    rate = -np.polyfit([p.z[1] for p in sel], np.log(np.abs(dc)), 1)[0]
    assert abs(dc[-1]) < 1e-10 and abs(rate - 1.0) < 0.15


@pytest.mark.slow
def test_diagram_names_the_located_saddle_change():
    """The whole diagram of :func:`test_saddle_change_located_and_shot`'s model (1.5 to 5 min
    on the shared machine; that test is its fast sibling): the loops of the saddles near
    ``-1`` and ``+1`` both end at the one ``saddle-change`` point, located at ``s = 0``
    (exact, by symmetry) with both legs' gaps at most GAP_TOL and shot here by scipy."""
    from numerics.bifurcation.oned import autonomous_diagram
    from numerics.bifurcation.run import Settings

    model = custom_model("k*(x**3 + s) + (b - x**2)*xdot")
    d = autonomous_diagram(model, {"mu": "0.1", "k": "10"}, ("s", "b"),
                           {"s": (-0.06, 0.06), "b": (0.05, 0.4)},
                           settings=Settings(grid=(13, 5), averaged=False, L=3.0))
    homs = [c for c in d.curves if c.kind == "homoclinic"]
    assert len(homs) == 2 and all(c.detail["gap_max"] <= GAP_TOL for c in homs)
    (sc,) = [p for p in d.codim2 if p.kind == "saddle-change"]
    assert not [p for p in d.codim2 if p.kind == "connection-end"]
    s, b = sc.point
    assert abs(s) < 1e-9 and abs(b - 0.2) < 1e-3
    assert max(abs(v) for v in sc.detail["gaps"]) <= GAP_TOL
    assert abs(_sc_leg(s, b, -1.0, 1.0)) < 1e-8 and abs(_sc_leg(s, b, 1.0, -1.0)) < 1e-8
    for c in homs:  # each curve's nearer end within 1e-5 of the located point (2e-7)
        assert min(math.dist(q, sc.point) for q in (c.points[0], c.points[-1])) < 1e-5
