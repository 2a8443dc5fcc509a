"""The one locator of special points on a branch of periodic orbits, as AUTO-07p does
(Doedel et al., AUTO-07p manual, sec. 10; Kuznetsov, *Elements of Applied Bifurcation
Theory*, sec. 10.2): the zero of a test function (a fold: the parameter component of the
tangent; a period doubling: ``det(Phi + I)``; a Neimark-Sacker point) between two points of
a branch, bracketed in a scalar ``w`` from one to the other (arclength, chord, segment) by
bisection or by the Illinois variant of the secant method.  Each trial point is an orbit
converged by the caller's shooting, so it passes the one acceptance standard
(:mod:`numerics.shooting.acceptance`; a fold is a regular point of the pseudo-arclength
problem, so no trial is a residual minimum past it).  The stated error of a located point is
its final bracket.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from numerics.errors import NumericsError

__all__ = ["Located", "locate_zero", "fold_on_arc", "zero_on_chord", "TRIAL_FAILURES"]

#: the failures of a trial point that end the location (the bracket so far is returned)
TRIAL_FAILURES = (NumericsError, np.linalg.LinAlgError, ValueError, ArithmeticError)


@dataclass(frozen=True)
class Located:
    """The last trial point (``None``: none converged), the final bracket ``lo, hi`` in ``w``,
    the trial points at its ends (``None``: an end never moved) and the error that ended the
    location early (or ``None``)."""

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

    ``trial(w)`` is the orbit at ``w`` (it raises one of :data:`TRIAL_FAILURES` where none
    is found), ``test(point)`` the test function (``None``: undefined, a failure); ``f_lo``
    and ``f_hi``, its values at ``lo`` and ``hi``, have opposite signs.  The location ends
    when the bracket is narrower than ``tol``, ``|f| <= f_tol`` or after ``max_iter``
    trials; ``secant``: Illinois steps instead of bisection.
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


def zero_on_chord(correct: Callable, a, b, test: Callable[[Any], float], f_a: float,
                  tol: float = 1e-11):
    """The zero of ``test`` between the points ``a`` and ``b`` of a branch (``f_a`` its value
    at ``a``, of the other sign at ``b``) by bisection on the hyperplanes normal to the chord
    ``b - a`` in the unknowns ``v`` (each meets the branch between them once, where the
    hyperplanes normal to ``a``'s tangent can miss a sharp fold); ``correct(v, row, target)``
    is the branch problem's corrector.  ``(the point nearest the zero, (the parameter at
    both ends of the last bracket))``, or ``None`` when no trial point converged."""
    chord = b.v - a.v
    length = float(np.linalg.norm(chord))
    d = chord / length

    def trial(w):
        pred = a.v + w * d
        pm = correct(pred, d, float(d @ pred))
        pm.tangent = pm.tangent if pm.tangent @ a.tangent >= 0 else -pm.tangent
        return pm

    found = locate_zero(trial, test, 0.0, length, f_a, -f_a, tol=tol)
    if found.point is None:
        return None
    p_lo = float((found.at_lo or a).u[-1])
    p_hi = float((found.at_hi or b).u[-1])
    return found.point, (min(p_lo, p_hi), max(p_lo, p_hi))


def fold_on_arc(arc: Callable[[Any, float], Any], a, b, ds: float) -> Located:
    """The fold between the points ``a`` and ``b = arc(a, ds)`` of a branch: the zero of the
    parameter (last) component of the unit tangent along the arc ``s -> arc(a, s)``
    (Illinois, to ``|dp/ds| <= 1e-10`` or a bracket of ``1e-12 ds``)."""
    return locate_zero(lambda s: arc(a, s), lambda q: float(q.tangent[-1]), 0.0, ds,
                       float(a.tangent[-1]), float(b.tangent[-1]), tol=1e-12 * ds,
                       f_tol=1e-10, max_iter=40, secant=True)
