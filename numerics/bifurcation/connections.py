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

__all__ = ["Loop", "GAP_TOL", "gap_function", "scan"]

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

    @property
    def homoclinic(self) -> bool:
        return abs(self.x_from - self.x_to) < 1e-9 * max(1.0, abs(self.x_from))

    def visits(self) -> list[float]:
        """The saddles the loop visits (both of a symmetric heteroclinic cycle)."""
        return [self.x_from] if self.homoclinic else sorted({self.x_from, self.x_to})

    def label(self) -> str:
        return "saddle" + ("" if self.homoclinic else "s") + " at x = " + \
            ", ".join(f"{x:+.4g}" for x in self.visits())


def gap_function(kit, loop: Loop):
    """``d(z)`` for ``z = (a, b)``; the saddles of ``loop`` are the Newton guesses (update
    them with :func:`accept`)."""
    def d(z):
        a, b = float(z[0]), float(z[1])
        cm = kit.compiled(a, b)
        params = {**kit.params, kit.axes[0]: a, kit.axes[1]: b}
        g, xs, xt = connection_gap(kit.model, params, loop.x_from, loop.x_to, loop.leave,
                                   loop.arrive, compiled=cm)
        if not math.isfinite(g):
            raise ConvergenceError("the gap is not finite")
        # the same saddles: Newton must not jump to another one
        scale = 0.25 * max(0.1, abs(loop.x_to - loop.x_from) or abs(loop.x_from))
        if abs(xs - loop.x_from) > scale or abs(xt - loop.x_to) > scale:
            raise ConvergenceError("the saddle moved to another")
        return np.array([g])
    return d


def accept(kit, loop: Loop, z) -> Loop:
    """``loop`` with its saddles refined at the accepted point ``z``."""
    a, b = float(z[0]), float(z[1])
    params = {**kit.params, kit.axes[0]: a, kit.axes[1]: b}
    _, xs, xt = connection_gap(kit.model, params, loop.x_from, loop.x_to, loop.leave,
                               loop.arrive, compiled=kit.compiled(a, b))
    loop.x_from, loop.x_to = xs, xt
    return loop


def candidate_loops(kit, a: float, b: float, L: float) -> list[Loop]:
    """Every loop to look for at ``(a, b)``: each saddle to itself, leaving either way, and
    for an odd field each positive saddle to its mirror image (leaving to the right: the
    loop around everything between; the mirror loop is the same curve in the plane)."""
    sad = [x for x, kind in kit.equilibria(a, b, L) if kind == "saddle"]
    if kit.odd:
        sad = [x for x in sad if x > 0]
    out = []
    for x in sad:
        out += [Loop(x, x, 1, 1), Loop(x, x, -1, -1)]
        if kit.odd:
            out += [Loop(x, -x, 1, 1), Loop(x, -x, -1, -1)]
    return out


def _gap(kit, loop, a, b):
    try:
        return float(gap_function(kit, Loop(loop.x_from, loop.x_to, loop.leave,
                                             loop.arrive))((a, b))[0])
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
                         if q.leave == lp.leave and (q.x_to == q.x_from) == (lp.x_to == lp.x_from)]
                if not match:
                    continue
                dist, q, h = min(match, key=lambda m: m[0])
                if dist > 0.2 or not (math.isfinite(g) and math.isfinite(h)) or g * h > 0:
                    continue
                root = _root(kit, lp, (pa, pb), (a, b))
                if root is not None:
                    found.append(root)
        prev = (a, b, loops, gaps)
    return found


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
        lp = accept(kit, Loop(loop.x_from, loop.x_to, loop.leave, loop.arrive), z)
    except _FAIL:
        return None
    return lp, z
