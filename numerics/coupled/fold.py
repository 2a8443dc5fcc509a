"""The fold of a branch of cycles near a given cycle: where a locked cycle ceases to exist.

A bisection on "does shooting at ``p`` find the cycle" ends at the integration floor of
the residual, not at the fold: past the fold the residual has a minimum ``~ d`` (the
distance past it), and a bracket can never be tighter than that floor allows.  The fold
itself is a regular point of the pseudo-arclength problem in ``(y0, T, p)``
(:mod:`numerics.coupled.continuation`): from the cycle the branch is followed towards the
fold until the parameter component of its tangent changes sign, and that zero is located
by bisection on the hyperplanes normal to the chord (AUTO-07p's fold test, Doedel's
lecture notes sec. 2).  The located point has two unit multipliers (the trivial one and
the one through 1 at a saddle-node of cycles).

The fold is located at the integrator tolerances ``rtol`` and ``rtol/10``; their
difference, with the bisection bracket, is the stated error.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from kbm.coupled import CoupledOscillators
from numerics.errors import ConvergenceError
from .continuation import _FAIL, _arc, _correct, _locate, _null, _Problem
from .flow import bind_coupled

__all__ = ["Fold", "locate_fold"]


@dataclass(frozen=True)
class Fold:
    """A located fold: the parameter, its error, the orbit there (state at the section
    ``xdot_1 = 0``, period) and its ``2N`` multipliers (the trivial one first)."""

    parameter: float
    error: float
    state: tuple
    period: float
    multipliers: tuple


def _fold_once(model: CoupledOscillators, params: dict, vary: str, state, period: float,
               p0: float, side: int, beyond: float, rtol: float):
    prob = _Problem(model, params, vary, rtol)
    n2 = 2 * model.dof
    prob.scale = np.concatenate([np.full(n2, max(1.0, float(np.max(np.abs(state))))),
                                 [period], [1.0]])
    u0 = np.concatenate([np.asarray(state, dtype=float), [period, p0]])
    row = np.zeros(len(u0))
    row[-1] = 1.0
    cur = _correct(prob, u0 / prob.scale, row, p0, max_iter=20)
    t = _null(cur.J)
    cur.tangent = t if t[-1] * side > 0 else -t
    # the branch reaches the fold within |beyond - p0| in p, the state within its root
    ds = ds0 = min(0.05, max(1e-4, 0.5 * math.sqrt(abs(beyond - p0))))
    for _ in range(200):
        try:
            new = _arc(prob, cur, cur.tangent, ds)
            if float(new.tangent @ cur.tangent) < 0.9:
                raise ConvergenceError("the tangent turned too fast")
        except _FAIL:
            ds /= 2
            if ds < 1e-3 * ds0:
                return None
            continue
        if new.tangent[-1] * cur.tangent[-1] < 0:
            found = _locate(prob, cur, new, "fold", float(cur.tangent[-1]))
            if found is None:
                return None
            pt, bracket = found
            return pt, bracket
        if (float(new.u[-1]) - beyond) * side > 0:
            return None  # no fold before ``beyond``: the cycle ends otherwise there
        cur = new
        ds = min(1.5 * ds, ds0)
    return None


def locate_fold(model: CoupledOscillators | str, params: Mapping[str, object], vary: str,
                state, period: float, p0: float, side: int, beyond: float,
                rtol: float = 1e-11) -> Fold | None:
    """The fold of the branch through the cycle ``(state, period)`` at ``vary = p0``, met
    going ``side`` (+1: towards larger ``vary``) before ``vary = beyond``; ``None`` when
    there is none (the cycle is lost otherwise, e.g. by a torus bifurcation).

    Parameters
    ----------
    model, params
        The coupled system and its other parameters (``mu`` included).
    vary
        The parameter followed.
    state, period, p0
        A cycle of the branch at ``vary = p0`` (state at the section ``xdot_1 = 0``).
    side, beyond
        The direction, and the parameter value the fold lies before.
    rtol
        The integrator tolerance; the fold is located again at ``rtol/10`` for its error.
    """
    m, _ = bind_coupled(model, {**dict(params), vary: p0})
    rest = {k: v for k, v in dict(params).items() if k != vary}
    out = []
    for tol in (rtol, rtol / 10):
        try:
            got = _fold_once(m, rest, vary, state, period, p0, side, beyond, tol)
        except _FAIL:
            got = None
        if got is None:
            return None
        out.append(got)
    (pt, bracket), (pt2, bracket2) = out
    p1, p2 = float(pt.u[-1]), float(pt2.u[-1])
    err = max(abs(p2 - p1), bracket[1] - bracket[0], bracket2[1] - bracket2[0], 1e-15)
    n2 = len(pt2.Phi)
    return Fold(p2, err, tuple(float(v) for v in pt2.u[:n2]), float(pt2.T),
                tuple(complex(z) for z in pt2.mults))
