"""The fold of a branch of cycles near a given cycle: where a locked cycle ceases to exist.

A bisection on "does shooting at ``p`` find the cycle" ends at the integration floor of
the residual, not at the fold: past the fold the residual has a minimum ``~ d`` (the
distance past it), and a bracket can never be tighter than that floor allows.  The fold
itself is a regular point of the pseudo-arclength problem in ``(y0, T, p)``
(:mod:`numerics.shooting.coupled_branch`): from the cycle the branch is followed towards the
fold (a case of its driver, :class:`numerics.shooting.coupled_branch.CoupledContinuation`)
until the parameter component of its tangent changes sign, and that zero is located by
bisection on the hyperplanes normal to the chord (AUTO-07p's fold test, Doedel's lecture
notes sec. 2).
The located point has two unit multipliers (the trivial one and the one through 1 at a
saddle-node of cycles).

The fold is located at the integrator tolerances ``rtol`` and ``rtol/10``; their
difference, with the bisection bracket, is the stated error.

:func:`true_edges` (the true edges of frequency locking, :mod:`numerics.locking.mutual`)
follows the locked cycle out in the detuning, brackets its loss by bisection on shooting
(which accepts no cycle past a fold, :mod:`numerics.shooting.acceptance`) to
:data:`FOLD_BRACKET`, and takes the fold there as the edge.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from kbm.model.coupled import CoupledOscillators
from numerics.errors import ConvergenceError, IntegrationError, NoCycleError
from numerics.shooting.arclength import FAIL as _FAIL
from numerics.shooting.branch_problem import OrbitPoint, OrbitProblem
from numerics.shooting.coupled_branch import CoupledContinuation
from numerics.shooting.coupled_orbit import coupled_cycle
from numerics.flow.coupled_flow import bind_coupled, coupled_flow
from numerics.locking.start import follow_steps, march_out

__all__ = ["Fold", "locate_fold", "LockingEdge", "true_edges", "FOLD_BRACKET"]

#: the bisection's bracket from which a true locking edge is located as the fold of the
#: locked cycle
FOLD_BRACKET = 1e-5


@dataclass(frozen=True)
class Fold:
    """A located fold: the parameter, its error, the orbit there (state at the section
    ``xdot_1 = 0``, period) and its ``2N`` multipliers (the trivial one first)."""

    parameter: float
    error: float
    state: tuple
    period: float
    multipliers: tuple


class _ToFold(CoupledContinuation):
    """The walk from a cycle to the fold of its branch, a case of the coupled driver (whose
    fold test locates the fold): it ends at the first sign change of the parameter
    component of the tangent, or past ``beyond``."""

    def end(self, a: OrbitPoint, b: OrbitPoint, ds: float) -> str:
        if b.tangent[-1] * a.tangent[-1] < 0:
            return "the fold"
        return "no fold before beyond" if (float(b.u[-1]) - self.beyond) * self.side > 0 else ""


def _fold_once(model: CoupledOscillators, params: dict, vary: str, state, period: float,
               p0: float, side: int, beyond: float, rtol: float):
    prob = OrbitProblem(model, params, vary, rtol, coupled_flow)
    first = prob.start(np.concatenate([np.asarray(state, dtype=float), [period, p0]]), 1.0)
    # the branch reaches the fold within |beyond - p0| in p, the state within its root
    ds0 = min(0.05, max(1e-4, 0.5 * math.sqrt(abs(beyond - p0))))
    run = _ToFold(prob, (-math.inf, math.inf), ds=ds0, ds_max=ds0, ds_min=1e-3 * ds0,
                  max_points=200, period_factor=math.inf, hopf_fraction=0.0)
    run.side, run.beyond = side, beyond
    run.follow(first, side)
    return next((sp for sp in run.special if sp.kind == "fold"), None)


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
    f1, f2 = out
    err = max(abs(f2.parameter - f1.parameter), f1.bracket[1] - f1.bracket[0],
              f2.bracket[1] - f2.bracket[0], 1e-15)
    return Fold(f2.parameter, err, f2.state, f2.period, f2.floquet_multipliers)


@dataclass(frozen=True)
class LockingEdge:
    """One edge of the locking region at fixed other parameters.

    ``sigma`` is the edge, ``error`` its uncertainty (the bisection bracket for the true
    edge, Newton's last step for the averaged one), ``side`` +1 or -1, ``state`` the
    locked state (slow-flow fixed point or cycle state) just inside.
    """

    sigma: float
    error: float
    side: int
    state: tuple


def true_edges(model: CoupledOscillators | str, params: Mapping[str, object],
               parameter: str = "sigma", limit: float = 10.0, tol: float = 1e-5,
               guess: Mapping[int, float] | None = None, *, at: float = 0.0,
               limits: Mapping[int, float] | None = None) -> list[LockingEdge]:
    """The edges of locking of the full system: where the locked cycle ceases to exist.

    The locked cycle is followed from ``parameter = at`` (default 0), on each side up to
    ``limits[side]`` from it (default ``limit`` on both), in steps scaled to that span
    (:func:`numerics.locking.start.follow_steps`: the first a fiftieth of it, growing
    1.5 times after each success up to a tenth, halved after each failure down to 1e-3
    or the first step, the smaller, then the loss is bracketed).  ``guess`` maps a side (-1, +1) to an estimate
    of its edge (e.g. the averaged one); the steps are then 0.3 of the way to it (no less
    than the first step or 0.02, the smaller), and do not grow.

    Raises
    ------
    numerics.errors.NoCycleError, numerics.errors.ConvergenceError
        If there is no locked cycle at ``parameter = at``.
    """
    p0 = {**dict(params), parameter: at}
    base = coupled_cycle(model, p0)
    lim = {-1: limit, 1: limit} if limits is None else limits
    return [_true_edge(model, params, parameter, base, side, lim[side], tol,
                       (guess or {}).get(side), float(at)) for side in (-1, 1)]


def _shoot(model, params, parameter, s, cyc):
    """The stable locked cycle at ``s`` shot from ``cyc``, or ``None``."""
    try:
        nxt = coupled_cycle(model, {**dict(params), parameter: s}, start=cyc.state,
                            transient=0, period=cyc.period, max_iter=12)
    except (ConvergenceError, NoCycleError, IntegrationError):
        return None  # no locked cycle found there (Newton left it, or the orbit ran away)
    return nxt if nxt.stable else None


def _true_edge(model, params, parameter, base, side, limit, tol, guess,
               at: float = 0.0) -> LockingEdge:
    first, largest, smallest = follow_steps(limit)  # scaled to the span followed
    # an estimate of the edge sets the scale: 0.3 of the way to it (no less than 0.02); the
    # steps then do not grow
    step = first if guess is None else max(min(first, 0.02), 0.3 * abs(guess - at))
    s, cyc, step = march_out(lambda s, c: _shoot(model, params, parameter, s, c), at, base,
                             side, limit, step, largest, smallest, grow=guess is None)
    if step is None:
        return LockingEdge(math.copysign(math.inf, side), 0.0, side, tuple(cyc.state))
    lo, hi = s, s + side * step
    coarse = True
    while abs(hi - lo) > tol:
        if coarse and abs(hi - lo) <= max(tol, FOLD_BRACKET):
            coarse = False  # the fold itself, a regular point of the arclength problem
            fold = locate_fold(model, params, parameter, cyc.state, cyc.period, lo, side,
                               hi + side * max(abs(hi - lo), 1e-3))
            if fold is not None and (fold.parameter - lo) * side >= 0 \
                    and min(abs(z - 1) for z in fold.multipliers[1:]) < 1e-4:
                return LockingEdge(fold.parameter, fold.error, side, fold.state)
        mid = 0.5 * (lo + hi)
        nxt = _shoot(model, params, parameter, mid, cyc)
        if nxt is not None:
            lo, cyc = mid, nxt
        else:
            hi = mid
    return LockingEdge(0.5 * (lo + hi), 0.5 * abs(hi - lo), side, tuple(cyc.state))
