"""The one locator of special points on a branch of periodic orbits: the zero of a test
function between two converged points, as AUTO-07p does (Doedel et al., AUTO-07p manual,
sec. 10; Kuznetsov, *Elements of Applied Bifurcation Theory*, sec. 10.2).

A test function ``f`` changes sign between two points ``a`` and ``b`` of a branch (a fold:
the parameter component of the tangent; a period doubling: ``det(Phi + I)``; a
Neimark-Sacker point: ``det Phi - 1`` or its ``2N`` form).  :func:`locate_zero` brackets its
zero in a scalar ``w`` that runs from ``a`` to ``b`` (the arclength along ``a``'s tangent,
the distance along the chord, the fraction of the segment): each trial point
``trial(w)`` is a periodic orbit corrected by the caller's shooting, so it passes the one
acceptance standard (:mod:`numerics.shooting.acceptance`; a fold itself is a regular
point of the pseudo-arclength problem, so no trial is a residual minimum past it).  The
bracket shrinks by bisection, or by the Illinois variant of the secant method (regula falsi
with the retained end's value halved: superlinear, and the zero stays bracketed).

The stated error of a located point is the final bracket (in ``w``, or in the parameter
at its two ends).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from numerics.errors import NumericsError

__all__ = ["Located", "locate_zero", "TRIAL_FAILURES"]

#: the failures of a trial point that end the location (the bracket so far is returned)
TRIAL_FAILURES = (NumericsError, np.linalg.LinAlgError, ValueError, ArithmeticError)


@dataclass(frozen=True)
class Located:
    """The result of :func:`locate_zero`.

    Attributes
    ----------
    point
        The last trial point (nearest the zero), or ``None`` when none converged.
    lo, hi
        The final bracket in ``w``.
    at_lo, at_hi
        The trial points at ``lo`` and ``hi`` (``None`` for an end never moved: the caller's
        ``a`` or ``b``).
    failure
        The error that ended the location early, or ``None``.
    """

    point: Any
    lo: float
    hi: float
    at_lo: Any = None
    at_hi: Any = None
    failure: Exception | None = None


def locate_zero(trial: Callable[[float], Any], test: Callable[[Any], float | None],
                lo: float, hi: float, f_lo: float, f_hi: float, *, tol: float,
                f_tol: float = 0.0, max_iter: int = 60, secant: bool = False) -> Located:
    """The zero of ``test(trial(w))`` for ``w`` between ``lo`` and ``hi``.

    Parameters
    ----------
    trial
        ``w -> point``: the periodic orbit at ``w``, converged by the acceptance standard;
        it raises one of :data:`TRIAL_FAILURES` where no orbit is found.
    test
        ``point -> f``, the test function (``None``: not defined there, which ends the
        location like a failure).
    lo, hi, f_lo, f_hi
        The bracket and the test function at its ends (of opposite signs).
    tol
        The location ends when the bracket is narrower than this.
    f_tol
        ... or when ``|f|`` at a trial point is at most this.
    max_iter
        Bound on the trial points.
    secant
        Illinois steps instead of bisection.

    Returns
    -------
    Located
        The last trial point, the bracket and the points at its ends.
    """
    best = at_lo = at_hi = None
    for _ in range(max_iter):
        w = 0.5 * (lo + hi)
        if secant and f_hi != f_lo:
            s = hi - f_hi * (hi - lo) / (f_hi - f_lo)
            w = s if lo < s < hi else w
        try:
            pt = trial(w)
            f = test(pt)
            if f is None:
                raise ArithmeticError(f"the test function is not defined at w = {w:.6g}")
        except TRIAL_FAILURES as exc:
            return Located(best, lo, hi, at_lo, at_hi, exc)
        best = pt
        if abs(f) <= f_tol:
            break
        if f * f_lo > 0:
            lo, f_lo, at_lo = w, f, pt
            f_hi = f_hi / 2 if secant else f_hi
        else:
            hi, f_hi, at_hi = w, f, pt
            f_lo = f_lo / 2 if secant else f_lo
        if hi - lo < tol:
            break
    return Located(best, lo, hi, at_lo, at_hi)
