"""The saddle-node loop located: where a homoclinic (or symmetric heteroclinic) curve of
``x'' = f(x, x')`` ends on the fold curve of its saddle.

As the saddle of a loop meets the node beside it (a fold of equilibria, ``f = f_x = 0``),
its weak eigenvalue tends to 0 and the weak manifold becomes the saddle-node's centre
manifold; the strong one stays.  The homoclinic curve ends on the fold curve at the
**non-central saddle-node homoclinic orbit** (Kuznetsov, *Elements of Applied Bifurcation
Theory*, sec. 7.1.2 and Fig. 7.4; Schecter 1987, the saddle-node separatrix loop): the
orbit leaves the saddle-node along its centre manifold and returns along the strong
manifold (or, in reverse time, the other way round).  It is codim 2: the fold condition
plus one connection.

With ``J = [[0, 1], [0, f_v]]`` at the saddle-node, the centre direction is ``(1, 0)``, the
centre manifold ``v = k u^2 + O(u^3)`` with ``u = x - x_sn`` and ``k = -f_xx/(2 f_v)``, on
which ``u' = k u^2``:

- ``f_v < 0``: the orbit leaves along the centre manifold on the side ``sign k`` (the only
  branch leaving forward: unique there, and a start a little off it is drawn onto it at the
  rate ``f_v``), and returns along the strong stable eigenvector ``(1, f_v)``;
- ``f_v > 0``: it leaves along the strong unstable one and returns along the centre
  manifold from the side ``-sign k`` (unique backward).

:func:`saddle_node_gap` is the manifolds' gap of this orbit at a point of the fold curve
(the turning points, or the section of a loop through the middle of a symmetric pair, as
for the loop's own curve: :mod:`numerics.bifurcation.connections`).
:func:`locate_saddle_node_loop` follows the fold curve, parametrised by the parameter that
varies most along it, the other one and ``x_sn`` solved by Newton on ``f = f_x = 0``, and
finds the zero of that gap by the secant method (bracketed by Brent where the secant
leaves): the last step in the parameter at most ``1e-10`` and the gap at most ``1e-10``.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq

from numerics.bifurcation.connections import GAP_TOL, SECTION, Loop, manifolds_on_section
from numerics.errors import ConvergenceError

__all__ = ["fold_point", "saddle_node_gap", "locate_saddle_node_loop"]

#: the strong manifold is started this far from the saddle-node along its eigenvector
DELTA = 1e-7
#: the centre branch is started where ``|f_v| / (|k| eps)`` is this (the passage time from
#: ``eps`` times ``|f_v|``: the start's error is damped by ``exp(-CENTRE_DAMP)``)
CENTRE_DAMP = 40.0


def _dp(kit, i: int, x: float, a: float, b: float, k: int, h: float) -> float:
    """``d/dp_k`` of ``d^i f/dx^i`` at ``(x, 0)``, central differences of step ``h``."""
    e = (h, 0.0) if k == 0 else (0.0, h)
    return (kit.d(i, 0, x, 0.0, a + e[0], b + e[1])
            - kit.d(i, 0, x, 0.0, a - e[0], b - e[1])) / (2 * h)


def fold_point(kit, x: float, a: float, b: float, along: int, *, scale=(1.0, 1.0),
               max_iter: int = 40) -> tuple[float, float, float]:
    """The point ``(x_sn, a, b)`` of the fold of equilibria (``f = f_x = 0`` at ``v = 0``)
    with the parameter ``along`` (0: ``a``, 1: ``b``) held at its given value: Newton on
    ``(x, p_other)`` from the given values (``f_x`` and ``f_xx`` from the model's symbolic
    derivatives, the parameter derivatives by central differences of ``1e-6`` of
    ``scale``).

    Raises
    ------
    numerics.errors.ConvergenceError
        If Newton does not converge (the last step is in the message).
    """
    other = 1 - along
    h = 1e-6 * float(scale[other])
    p = [float(a), float(b)]
    x = float(x)
    step = np.full(2, np.inf)
    for _ in range(max_iter):
        r = np.array([kit.d(0, 0, x, 0.0, *p), kit.d(1, 0, x, 0.0, *p)])
        J = np.array([[kit.d(1, 0, x, 0.0, *p), _dp(kit, 0, x, *p, other, h)],
                      [kit.d(2, 0, x, 0.0, *p), _dp(kit, 1, x, *p, other, h)]])
        step = np.linalg.solve(J, -r)
        x += step[0]
        p[other] += step[1]
        if abs(step[0]) <= 1e-14 * max(1.0, abs(x)) and \
                abs(step[1]) <= 1e-14 * max(float(scale[other]), abs(p[other])):
            return x, p[0], p[1]
    raise ConvergenceError(f"the fold of equilibria near x = {x:.6g} did not converge "
                           f"(last step {step[0]:.3g}, {step[1]:.3g})")


def saddle_node_gap(kit, loop: Loop, x_sn: float, a: float, b: float,
                    t_max: float = 200.0) -> float:
    """The gap of the saddle-node loop of ``loop`` at the fold point ``(x_sn, a, b)`` (module
    docstring): the centre branch and the strong manifold of the saddle-node ``x_sn`` (for
    a loop ``x -> -x`` of an odd field: of ``x_sn`` and its mirror image, a saddle-node
    too), compared where each first turns, or on the section ``x = x_t + arrive SECTION``
    of a loop through the middle.

    Raises
    ------
    numerics.errors.ConvergenceError
        If the loop's sides are not those of a saddle-node loop (its leaving side is not the
        centre branch's, or its arriving side not the centre branch's for ``f_v > 0``), a
        heteroclinic loop of a field that is not odd, or a manifold does not turn.
    """
    from numerics.cycles.manifolds import _field, _to_turn

    if not loop.homoclinic and not kit.odd:
        raise ConvergenceError("a heteroclinic loop ends on a fold only for an odd field")
    x_t = x_sn if loop.homoclinic else -x_sn
    fv = kit.d(0, 1, x_sn, 0.0, a, b)
    k = -kit.d(2, 0, x_sn, 0.0, a, b) / (2 * fv)
    if loop.homoclinic:
        k_t = k
    else:  # the mirror image: f(-x, -v) = -f(x, v) keeps f_v and flips f_xx
        k_t = -k
    eps = abs(fv) / (CENTRE_DAMP * abs(k))
    t_max += 2 * CENTRE_DAMP / abs(fv)
    if fv < 0:  # leave along the centre branch, return along the strong stable manifold
        side = 1 if k > 0 else -1
        if loop.leave != side:
            raise ConvergenceError("the loop leaves on the centre manifold's approaching side")
        e = min(eps, 0.01)
        yu = [x_sn + side * e, k * e * e]
        ys = [x_t + loop.arrive * DELTA, loop.arrive * DELTA * fv]
    else:  # leave along the strong unstable manifold, return along the centre branch
        side = -1 if k_t > 0 else 1
        if loop.arrive != side:
            raise ConvergenceError("the loop arrives on the centre manifold's leaving side")
        e = min(eps, 0.01)
        yu = [x_sn + loop.leave * DELTA, loop.leave * DELTA * fv]
        ys = [x_t + side * e, k_t * e * e]
    cm = kit.compiled(a, b)
    params = {**kit.params, kit.axes[0]: a, kit.axes[1]: b}
    acc, _, _ = _field(kit.model, params, cm)
    if loop.section:
        return manifolds_on_section(cm, yu, ys, x_t + loop.arrive * SECTION, loop.arrive,
                                    t_max)
    return _to_turn(acc, yu, 1.0, t_max) - _to_turn(acc, ys, -1.0, t_max)


def locate_saddle_node_loop(kit, loop: Loop, z, *, scale=(1.0, 1.0), ptol: float = 1e-10,
                            max_iter: int = 40) -> dict | None:
    """The saddle-node loop where the curve of ``loop`` ends near ``z = (a, b)`` (its last
    point; the loop's saddle ``loop.x_from`` there), located on the fold curve (module
    docstring).  ``ptol``: the last secant step in the parameter along the fold
    (absolute); ``scale``: the box's sides (finite-difference steps, the secant's reach).

    Returns ``{"point", "x", "gap", "fold_residual", "parameter_step", "along"}`` with
    ``|gap| <= GAP_TOL``, the step at most ``ptol`` and ``x`` the saddle-node near the loop's
    saddle, or ``None`` where the fold point or the gap cannot be computed or the iteration
    does not converge.
    """
    sc = np.asarray(scale, dtype=float)
    a, b = float(z[0]), float(z[1])
    x0 = float(loop.x_from)
    try:  # the fold's direction in the plane: f_a da + f_b db = 0 (f_x = 0 on it)
        fa = _dp(kit, 0, x0, a, b, 0, 1e-6 * sc[0])
        fb = _dp(kit, 0, x0, a, b, 1, 1e-6 * sc[1])
    except (ArithmeticError, ValueError):
        return None
    along = 0 if abs(fb) * sc[0] >= abs(fa) * sc[1] else 1
    state = {"x": x0, "p": [a, b]}

    def point(s):
        p = list(state["p"])
        p[along] = s
        x, pa, pb = fold_point(kit, state["x"], *p, along, scale=sc)
        return x, pa, pb

    def gap(s):
        x, pa, pb = point(s)
        g = saddle_node_gap(kit, loop, x, pa, pb)
        if not math.isfinite(g):
            raise ConvergenceError("the saddle-node gap is not finite")
        state["x"], state["p"] = x, [pa, pb]
        return g

    fails = (ConvergenceError, ArithmeticError, ValueError, np.linalg.LinAlgError)
    s0 = (a, b)[along]
    h = 1e-4 * sc[along]
    try:
        s1, s2 = s0, s0 + h
        g1, g2 = gap(s1), gap(s2)
        step = math.inf
        for _ in range(max_iter):
            if g2 == g1:
                break
            s3 = s2 - g2 * (s2 - s1) / (g2 - g1)
            if abs(s3 - s0) > 0.1 * sc[along]:  # the secant leaves: bracket and Brent
                s3 = _bracketed(gap, s1, g1, s2, g2, sc[along], ptol)
                if s3 is None:
                    return None
            step = abs(s3 - s2)
            s1, g1, s2, g2 = s2, g2, s3, gap(s3)
            if step <= ptol and abs(g2) <= GAP_TOL:
                break
        if not (step <= ptol and abs(g2) <= GAP_TOL):
            return None
        x, pa, pb = point(s2)
    except fails:
        return None
    if not _merges(kit, x0, x, a, b):  # another fold than the loop's saddle's
        return None
    res = max(abs(kit.d(0, 0, x, 0.0, pa, pb)), abs(kit.d(1, 0, x, 0.0, pa, pb)))
    return {"point": (float(pa), float(pb)), "x": float(x), "gap": float(g2),
            "fold_residual": float(res), "parameter_step": float(step),
            "along": kit.axes[along]}


def _newton(fn, dfn, x: float) -> float:
    for _ in range(60):
        step = fn(x) / dfn(x)
        x -= step
        if abs(step) <= 1e-15 * max(1.0, abs(x)):
            break
    return x


def _merges(kit, x0: float, x_sn: float, a: float, b: float) -> bool:
    """Whether the fold point ``x_sn`` continues the critical point of ``f(., 0)`` next to
    the loop's saddle at ``(a, b)``: the saddle ``s`` (Newton on ``f`` from ``x0``), the
    critical point ``x_c`` (Newton on ``f_x`` from ``x_sn``), no zero of ``f`` between
    them (so ``x_c`` lies between the saddle and the node it meets on the fold), and
    ``x_sn`` no farther from ``x_c`` than the saddle is."""
    s = _newton(lambda x: kit.d(0, 0, x, 0.0, a, b), lambda x: kit.d(1, 0, x, 0.0, a, b), x0)
    xc = _newton(lambda x: kit.d(1, 0, x, 0.0, a, b), lambda x: kit.d(2, 0, x, 0.0, a, b),
                 x_sn)
    vals = [kit.d(0, 0, x, 0.0, a, b) for x in np.linspace(s, xc, 201)[1:]]
    same = all(v > 0 for v in vals) or all(v < 0 for v in vals)
    return bool(same and abs(x_sn - xc) <= abs(xc - s) + 1e-6)


def _bracketed(gap, s1, g1, s2, g2, scale, ptol):
    """Brent on ``gap`` from a bracket grown around ``s1, s2`` (``None`` without one)."""
    lo, glo, hi, ghi = (s1, g1, s2, g2) if s1 < s2 else (s2, g2, s1, g1)
    w = hi - lo
    for _ in range(12):
        if glo * ghi <= 0:
            return brentq(gap, lo, hi, xtol=ptol * scale * 0.1, rtol=4e-16)
        w *= 2
        lo, glo = lo - w, gap(lo - w)
        hi, ghi = hi + w, gap(hi + w)
    return None
