"""Homoclinic and heteroclinic connections of ``x'' = f(x, x')`` in two parameters.

The defining function is the manifolds' gap of :func:`numerics.cycles.manifolds.connection_gap`
(the one the one-parameter homoclinic end uses): where the unstable manifold of the saddle
``x_from`` (leaving towards ``leave``) first turns (``x' = 0``), minus where the stable
manifold of ``x_to`` (arriving from ``arrive``), followed backward, first turns.  A
connection is a zero of ``d(a, b)``: a curve in the plane, continued by
:func:`numerics.bifurcation.curve.continue_curve` with every point converged to
``|d| <= 1e-10`` (:data:`GAP_TOL`).  The saddles are refined by Newton at each evaluation from
those of the last accepted point, so the curve follows the same saddles; the loop's kind:

- ``x_from == x_to``: a homoclinic loop of one saddle;
- ``x_to == -x_from`` of an odd field: a heteroclinic cycle through the pair (its mirror
  image closes it), named by both saddles.

:func:`saddle_quantity` is the test function ``tr J`` at the loop's saddle (its zeros:
neutral saddle loops); :func:`saddle_change` locates the heteroclinic cycle where a
homoclinic curve ends by changing its saddles.

:func:`scan` finds the curves' crossings of lines of the parameter plane (sign changes of
``d`` between grid values, then Brent; a jump of ``d``, where a manifold passes another
saddle, is no root and is refused by the size of ``|d|`` at the root).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from numerics.cycles.manifolds import connection_gap
from numerics.errors import ConvergenceError

__all__ = ["Loop", "GAP_TOL", "gap_function", "scan", "saddle_quantity", "saddle_change"]

#: every point of a true homoclinic curve has the manifolds' gap below this
GAP_TOL = 1e-10
_FAIL = (ConvergenceError, ValueError, ArithmeticError, ZeroDivisionError)


@dataclass
class Loop:
    """The connection followed: the saddles (updated along the curve) and the sides."""

    x_from: float
    x_to: float
    leave: int
    arrive: int
    #: the gap on the section ``x = x_to + arrive SECTION`` (:func:`section_gap`), not at
    #: the turning points: the connections through the middle of a symmetric pair
    section: bool = False

    @property
    def homoclinic(self) -> bool:
        return abs(self.x_from - self.x_to) < 1e-9 * max(1.0, abs(self.x_from))

    def visits(self) -> list[float]:
        """The saddles the loop visits (both of a symmetric heteroclinic cycle)."""
        return [self.x_from] if self.homoclinic else sorted({self.x_from, self.x_to})

    def label(self) -> str:
        return "saddle" + ("" if self.homoclinic else "s") + " at x = " + \
            ", ".join(f"{x:+.4g}" for x in self.visits()) + \
            (" (through the middle)" if self.section else "")

    def copy(self) -> "Loop":
        return Loop(self.x_from, self.x_to, self.leave, self.arrive, self.section)

    def gap(self, model, params, compiled):
        """``(d, x_s, x_t)`` of this loop: :func:`section_gap` or the turning points'; the
        manifolds followed for up to :func:`manifold_time`."""
        fn = section_gap if self.section else connection_gap
        return fn(model, params, self.x_from, self.x_to, self.leave, self.arrive,
                  manifold_time(compiled, self.x_from, self.x_to), compiled=compiled)


def manifold_time(compiled, x_from: float, x_to: float) -> float:
    """How long the manifolds are followed: 200, or ``30/lambda`` for the smaller of the
    unstable eigenvalue at ``x_from`` and the stable one's size at ``x_to`` where it is
    larger (at most 4000): near a fold of the saddle a weak eigenvalue tends to 0 and its
    manifold leaves slowly, so a homoclinic curve is followed closer to its
    saddle-node loop."""
    lam = []
    f_jac, pv = compiled.template.f_jac, compiled.pvec  # compiled.jac's rows, no array
    for x, unstable in ((x_from, True), (x_to, False)):
        for _ in range(8):  # Newton towards the saddle from the guess
            fx = float(f_jac(0.0, x, 0.0, *pv)[1][0])
            if fx == 0:
                break
            x -= compiled.acc(0.0, x, 0.0) / fx
        row = f_jac(0.0, x, 0.0, *pv)[1]
        fx, fv = float(row[0]), float(row[1])
        disc = fv * fv + 4 * fx
        if fx > 0 and disc > 0:
            r = math.sqrt(disc)
            lam.append((fv + r) / 2 if unstable else (r - fv) / 2)
    small = min(lam) if lam else 0.0
    return float(min(4000.0, max(200.0, 30.0 / small))) if small > 0 else 200.0


#: the section ``x = x_to + arrive SECTION`` of :func:`section_gap`
SECTION = 0.05


def section_gap(model, params, x_from: float, x_to: float, leave: int, arrive: int,
                t_max: float = 200.0, *, compiled) -> tuple[float, float, float]:
    """``(d, x_s, x_t)``: the velocity of the unstable manifold of the saddle near
    ``x_from`` (leaving towards ``leave``) where it first crosses ``x = x_t + arrive SECTION``
    towards ``x_t``, minus that of the stable manifold of ``x_t`` (arriving from ``arrive``)
    there, followed backward.  Unlike the turning points of
    :func:`numerics.cycles.manifolds.connection_gap`, this is smooth where the orbit passes
    close to another saddle (a turning point there jumps with the side it passes on).  Where
    the unstable manifold turns back before the section, ``d`` is continued by
    ``-v_s + (x_turn - x_section)`` (of the sign of ``-v_s``: never zero, so scans see the
    sign change at the connection).
    """
    from numerics.cycles.manifolds import EPS, _field, _saddle

    acc, fx, fv = _field(model, params, compiled)
    xs, lu, _ = _saddle(acc, fx, fv, x_from)
    xt, _, ls = _saddle(acc, fx, fv, x_to)
    return manifolds_on_section(compiled, [xs + leave * EPS, leave * EPS * lu],
                                [xt + arrive * EPS, arrive * EPS * ls], xt + arrive * SECTION,
                                arrive, t_max), xs, xt


def manifolds_on_section(compiled, yu, ys, xsec: float, arrive: int,
                         t_max: float = 200.0) -> float:
    """The gap of :func:`section_gap` from given starts: ``x'`` where the orbit from ``yu``
    (forward, the compiled flow) first crosses ``x = xsec`` moving towards ``-arrive``,
    minus ``x'`` where the orbit from ``ys`` (backward, the compiled stepper's
    ``to_section``: the crossing by Newton on the last DOP853 step, rtol 1e-12) first
    reaches it; continued by ``-v_s + (x_turn - xsec)`` where the forward orbit turns back
    before the section."""
    from numerics.flow import template_flow

    fl = template_flow(compiled.template)
    if fl is None:
        raise ConvergenceError("the section gap needs the compiled flow (numba)")
    # the stable manifold backward to the section
    _, v_s, _, status = fl.to_section(ys, -1.0, xsec, t_max, compiled.pvec, 1e-12, 1e-13)
    if status:
        raise ConvergenceError(f"the stable manifold from x = {ys[0]:.6g} did not reach the "
                               "section")
    y = np.array(yu, dtype=float)
    t, chunk, n = 0.0, 2.0, 40
    x_ext = None   # the unstable manifold's extreme x towards the section, before it turns
    turned = False
    while t < t_max:
        r = fl(y, chunk, compiled.pvec, 1e-12, 1e-13, n)
        if r.status:
            raise ConvergenceError(f"the unstable manifold: {r.message}")
        Y = r.y
        s = (Y[:, 0] - xsec) * arrive
        # the first sample k with the crossing towards -arrive between k and k + 1
        cross = np.flatnonzero((s[:-1] > 0) & (s[1:] <= 0) & (Y[1:, 1] * arrive < 0))
        if cross.size:
            return _refine(fl, compiled.pvec, Y[cross[0]], xsec) - v_s
        if not turned and t > 0:
            turn = np.flatnonzero(Y[:-1, 1] * Y[1:, 1] < 0)
            if turn.size:
                turned = True
                x_ext = Y[turn[0], 0]
        t += chunk
        y = Y[-1]
    if x_ext is None:
        raise ConvergenceError("the unstable manifold neither turned nor crossed the section")
    return -v_s + (x_ext - xsec)


def _refine(fl, pvec, y, xsec) -> float:
    """``x'`` where the orbit from ``y`` crosses ``x = xsec`` (Newton on the time)."""
    dt = 0.0
    for _ in range(12):
        z = fl(y, dt, pvec, 1e-12, 1e-13, 1).y[-1] if dt > 0 else np.asarray(y, float)
        step = (xsec - z[0]) / z[1]
        dt += step
        if abs(step) < 1e-15 * max(1.0, dt):
            break
    return float(fl(y, dt, pvec, 1e-12, 1e-13, 1).y[-1][1])


def gap_function(kit, loop: Loop):
    """``d(z)`` for ``z = (a, b)``; the saddles of ``loop`` are the Newton guesses (update
    them with :func:`accept`)."""
    def d(z):
        a, b = float(z[0]), float(z[1])
        cm = kit.compiled(a, b)
        params = {**kit.params, kit.axes[0]: a, kit.axes[1]: b}
        g, xs, xt = loop.gap(kit.model, params, cm)
        if not math.isfinite(g):
            raise ConvergenceError("the gap is not finite")
        # the same saddles: Newton must not jump to another one
        scale = 0.25 * max(0.1, abs(loop.x_to - loop.x_from) or abs(loop.x_from))
        if abs(xs - loop.x_from) > scale or abs(xt - loop.x_to) > scale:
            raise ConvergenceError("the saddle moved to another")
        return np.array([g])
    return d


def saddle_quantity(kit, loop: Loop):
    """``sigma(z) = lambda_u + lambda_s = tr J`` at the loop's saddle (its ``x_from``; the
    saddles of a symmetric cycle have the same trace).  Where it changes sign on a
    homoclinic curve (a neutral saddle loop), a fold of cycles ends on the curve
    (Kuznetsov, *Elements of Applied Bifurcation Theory*, sec. 6.2, Andronov-Leontovich)."""
    from numerics.cycles.manifolds import _field, _saddle

    def sigma(z):
        a, b = float(z[0]), float(z[1])
        params = {**kit.params, kit.axes[0]: a, kit.axes[1]: b}
        acc, fx, fv = _field(kit.model, params, kit.compiled(a, b))
        _, lu, ls = _saddle(acc, fx, fv, loop.x_from)
        return lu + ls
    return sigma


def saddle_change(kit, loop: Loop, z, L: float, *, scale=(1.0, 1.0),
                  max_iter: int = 30) -> dict | None:
    """The saddle change at the end ``z`` of the curve of ``loop``, located.

    The loop of ``x_1`` (leaving towards ``leave``) changes the saddles it visits where its
    unstable manifold reaches the next saddle ``x_2`` on that side: there ``x_1 -> x_2``
    (leaving ``x_1`` towards ``leave``) and ``x_2 -> x_1`` (leaving ``x_2`` back) are both
    connections, a heteroclinic cycle, codim 2 in the plane (Kuznetsov, *Elements of
    Applied Bifurcation Theory*, sec. 6.4, saddle connections of planar flows).  The same
    holds for the heteroclinic cycle ``x_1 -> -x_1 -> x_1`` of an odd field (its curve is
    codim 1 by the symmetry): it ends where ``x_1 -> x_2`` and ``x_2 -> -x_1`` (leaving
    ``x_2`` back, or on, and arriving at ``-x_1`` as the cycle did) are both connections,
    the mirror legs following by the symmetry.  The point is the zero of both legs'
    :func:`section_gap`, by Newton in ``(a, b)`` from ``z`` (central differences, step
    ``1e-6`` of ``scale``), for the nearest saddles on that side first.  Returns
    ``{"point", "saddles", "gaps", "newton_step"}`` (``saddles``: ``x_1, x_2``, and
    ``-x_1`` for a heteroclinic cycle) with both gaps at most :data:`GAP_TOL` and the last
    step at most ``1e-9`` (scaled), or ``None``.
    """
    if not loop.homoclinic and not kit.odd:
        return None
    a, b = float(z[0]), float(z[1])
    x1, side, xt = loop.x_from, loop.leave, loop.x_to
    others = sorted((x for x, kind in kit.equilibria(a, b, L)
                     if kind == "saddle" and (x - x1) * side > 1e-9 and abs(x - xt) > 1e-9),
                    key=lambda x: abs(x - x1))
    sc = np.asarray(scale, dtype=float)
    turns = (-side,) if loop.homoclinic else (-side, side)
    for x2, back in ((x2, back) for x2 in others[:2] for back in turns):
        legs = [Loop(x1, x2, side, -side, True), Loop(x2, xt, back, loop.arrive, True)]
        fns = [gap_function(kit, lp) for lp in legs]

        def H(w, fns=fns):
            return np.array([float(fn(w)[0]) for fn in fns])
        w = np.array([a, b])
        try:
            for _ in range(max_iter):
                h = H(w)
                J = np.empty((2, 2))
                for k in range(2):
                    e = np.zeros(2)
                    e[k] = 1e-6 * sc[k]
                    J[:, k] = (H(w + e) - H(w - e)) / (2 * e[k])
                step = np.linalg.solve(J, -h)
                w = w + step
                for lp in legs:  # the saddles followed from the new point
                    accept(kit, lp, w)
                if np.max(np.abs(step / sc)) <= 1e-9:
                    break
            else:
                continue
            h = H(w)
        except (*_FAIL, np.linalg.LinAlgError):
            continue
        if np.max(np.abs(h)) <= GAP_TOL:
            saddles = [legs[0].x_from, legs[0].x_to] + ([] if loop.homoclinic else
                                                        [legs[1].x_to])
            return {"point": (float(w[0]), float(w[1])), "saddles": saddles,
                    "gaps": [float(v) for v in h],
                    "newton_step": float(np.max(np.abs(step / sc)))}
    return None


def accept(kit, loop: Loop, z) -> Loop:
    """``loop`` with its saddles refined at the accepted point ``z``."""
    a, b = float(z[0]), float(z[1])
    params = {**kit.params, kit.axes[0]: a, kit.axes[1]: b}
    _, xs, xt = loop.gap(kit.model, params, kit.compiled(a, b))
    loop.x_from, loop.x_to = xs, xt
    return loop


def candidate_loops(kit, a: float, b: float, L: float) -> list[Loop]:
    """Every loop to look for at ``(a, b)``: each saddle to itself, leaving either way, and
    for an odd field each positive saddle to its mirror image (leaving to the right: the
    loop around everything between; the mirror loop is the same curve in the plane)."""
    sad = [x for x, kind in kit.equilibria(a, b, L) if kind == "saddle"]
    if kit.odd:  # x >= 0: a saddle at the origin is its own mirror image
        sad = [x for x in sad if x > -1e-12]
    out = []
    for x in sad:
        out += [Loop(x, x, 1, 1), Loop(x, x, -1, -1)]
        if kit.odd and abs(x) > 1e-12:
            out += [Loop(x, -x, 1, 1), Loop(x, -x, -1, -1), Loop(x, -x, -1, 1, True)]
    return out


def _gap(kit, loop, a, b):
    try:
        return float(gap_function(kit, loop.copy())((a, b))[0])
    except _FAIL:
        return float("nan")


def scan(kit, line, L: float) -> list[tuple[Loop, tuple[float, float]]]:
    """Connections on a line of the plane: ``line`` a list of points ``(a, b)`` in order;
    returns ``(loop, (a, b))`` at each root of a gap converged to :data:`GAP_TOL`."""
    found = []
    prev = None
    for a, b in line:
        loops = candidate_loops(kit, a, b, L)
        gaps = [_gap(kit, lp, a, b) for lp in loops]
        if prev is not None:
            pa, pb, ploops, pgaps = prev
            for lp, g in zip(loops, gaps):
                # the same loop at the previous point: nearest saddle, same sides
                match = [(abs(q.x_from - lp.x_from), q, h) for q, h in zip(ploops, pgaps)
                         if (q.leave, q.arrive, q.section) == (lp.leave, lp.arrive, lp.section)
                         and (q.x_to == q.x_from) == (lp.x_to == lp.x_from)]
                if not match:
                    continue
                dist, q, h = min(match, key=lambda m: m[0])
                if dist > 0.2 or not (math.isfinite(g) and math.isfinite(h)) or g * h > 0:
                    continue
                root = _root(kit, lp, (pa, pb), (a, b))
                if root is not None:
                    found.append(root)
        prev = (a, b, loops, gaps)
    # a homoclinic root of the turning points' gap where a loop through the middle of the
    # pair x, -x closes is that heteroclinic cycle (the loop of x passes -x there, and the
    # turning point jumps), not a homoclinic loop
    inner = [(lp, z) for lp, z in found if lp.section]

    def at_inner(lp, z):
        return lp.homoclinic and any(
            abs(abs(q.x_from) - abs(lp.x_from)) < 1e-6 * (1 + abs(lp.x_from))
            and math.dist(z, w) < 1e-8 * (1 + math.hypot(*z)) for q, w in inner)
    return [(lp, z) for lp, z in found if not at_inner(lp, z)]


def _root(kit, loop: Loop, p, q):
    """Brent on the gap along the segment ``p -> q``; ``None`` for a jump."""
    def g(s):
        v = _gap(kit, loop, p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1]))
        if not math.isfinite(v):
            raise ValueError
        return v
    try:
        s = brentq(g, 0.0, 1.0, xtol=1e-14, rtol=1e-15)
        z = (p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1]))
        if abs(g(s)) > 1e3 * GAP_TOL:  # a jump of the turning point, not a connection
            return None
        lp = accept(kit, loop.copy(), z)
    except _FAIL:
        return None
    return lp, z
