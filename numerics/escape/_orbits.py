"""Orbit integrals of an annulus whose orbits pass over saddles (bands, the outer annulus).

On such an orbit the velocity ``v = sqrt(2 (E - G(x)))`` nearly vanishes at every saddle
``x_s`` it passes: close to the separatrix energy ``E_s``, ``v ~ sqrt(2 (E - E_s) +
|g'(x_s)| (x - x_s)^2)`` has a kink of width ``sqrt(E - E_s)``, which the midpoint rule
of :meth:`numerics.energy.portrait.Annulus.orbit_integrals` resolves only algebraically
(3e-7 relative error of the action of the CDC's outer annulus next to its separatrix;
issue 36, finding 1).  Here the same variable ``x = c - r cos s`` (smooth at the turning
points) is integrated by composite Gauss-Legendre on panels graded geometrically towards
the saddles' ``s_k = arccos((c - x_s)/r)`` and towards both turning points (which near a
separatrix above the annulus approach a saddle too), so that a kink of any width met by
the grading is integrated to rounding.
"""

from __future__ import annotations

import numpy as np

__all__ = ["graded_orbit_integrals", "interior_saddles"]

#: geometric ratio and depth of the grading, Gauss-Legendre nodes per panel
RATIO, LEVELS, NODES = 0.25, 16, 12
#: the most panels in the middle of an interval between saddles
MAX_MIDDLE = 512


def interior_saddles(annulus, equilibria) -> np.ndarray:
    """The saddles strictly inside the annulus' orbits (between its inner bounds)."""
    _, left_in, right_in, _ = annulus.bounds
    return np.array(sorted(e.x for e in equilibria
                           if e.kind == "saddle" and left_in < e.x < right_in))


def _graded_unit(middle: int, levels: int = LEVELS, ratio: float = RATIO) -> np.ndarray:
    """Break points on ``[0, 1]`` graded geometrically towards both ends, the middle
    ``[ratio/2, 1 - ratio/2]`` cut in ``middle`` equal panels."""
    side = 0.5 * ratio ** np.arange(1, levels + 1)
    return np.unique(np.concatenate((side, 1 - side, [0.0, 1.0],
                                     np.linspace(side[0], 1 - side[0], middle + 1))))


def graded_orbit_integrals(annulus, saddles, E, integrands, tol: float = 1e-14) -> list:
    """``int_0^pi f(x(s), v+(s), sqrt(2 q(s))) ds`` for each integrand, each energy.

    Parameters
    ----------
    annulus : numerics.energy.portrait.Annulus
    saddles : array_like
        The saddles inside the annulus' orbits (:func:`interior_saddles`).
    E : array_like
        Energies inside the annulus.
    integrands : sequence of callable
        ``f(x, v, sq)`` as for :meth:`~numerics.energy.portrait.Annulus.orbit_integrals`.
    tol : float
        Agreement of two successive rules, relative to ``int |f| ds``.

    Returns
    -------
    list of numpy.ndarray
    """
    G = annulus._fun[2]
    E = np.atleast_1d(np.asarray(E, float))
    xm, xp = annulus.turning_points(E)
    c, r = 0.5 * (xp + xm), 0.5 * (xp - xm)
    sk = np.arccos(np.clip((c[:, None] - np.asarray(saddles, float)[None, :]) / r[:, None],
                           -1.0, 1.0))
    cuts = np.sort(np.concatenate([np.zeros((E.size, 1)), sk,
                                   np.full((E.size, 1), np.pi)], axis=1), axis=1)
    gx, gw = np.polynomial.legendre.leggauss(NODES)

    def rule(middle, k):
        # per energy: each interval between cuts, graded towards both of its ends
        unit = _graded_unit(middle)
        a, b = cuts[k, :-1], cuts[k, 1:]
        brk = a[:, :, None] + (b - a)[:, :, None] * unit[None, None, :]
        lo, hi = brk[:, :, :-1], brk[:, :, 1:]
        half = 0.5 * (hi - lo)
        s = (lo[..., None] + half[..., None] * (gx + 1)).reshape(k.size, -1)
        w = (half[..., None] * gw).reshape(k.size, -1)
        xs = c[k, None] - r[k, None] * np.cos(s)
        rs = r[k, None] * np.sin(s)
        q = np.maximum((E[k, None] - G(xs)) / np.maximum(rs, 1e-300) ** 2,
                       np.finfo(float).tiny)
        sq = np.sqrt(2 * q)
        vals = [w * f(xs, rs * sq, sq) for f in integrands]
        return [np.sum(v, axis=1) for v in vals], [np.sum(np.abs(v), axis=1) for v in vals]

    # the middle panels are halved until two rules agree (a near-inflection of G makes
    # v small, though not zero, away from the saddles)
    out = [np.zeros(E.size) for _ in integrands]
    active = np.arange(E.size)
    middle = 2
    prev, _ = rule(middle, active)
    while active.size:
        middle *= 2
        cur, size = rule(middle, active)
        err = np.max([np.abs(u - v) / np.maximum(m, 1e-300)
                      for u, v, m in zip(cur, prev, size)], axis=0)
        for o, v in zip(out, cur):
            o[active] = v
        keep = (err > tol) & (middle < MAX_MIDDLE)
        active = active[keep]
        prev = [v[keep] for v in cur]
    return out
