"""One acceptance standard for every shooting of a periodic orbit, and the Newton loop it ends.

Every shooting of the toolkit (:func:`numerics.shooting.orbit.shoot`: one degree of
freedom, ``2N`` dimensions, forced; the correctors of the continuations,
:mod:`numerics.shooting.arclength`) accepts a Newton iterate ``z`` (the state on the section,
the period, a parameter on a branch) as a periodic orbit by the same three tests:

1. **residual**: ``||phi_T(y0) - y0||_inf <= RESIDUAL_FACTOR * rtol * S``, with
   ``S = max(1, ||y0||_inf)`` the orbit's scale and ``rtol`` the integrator's tolerance:
   the residual has fallen to the integration floor;
2. **convergence**: the Newton correction computed at ``z`` is small,
   ``||dz||_inf <= CORRECTION_FACTOR * sqrt(rtol) * S``.  This tells a true orbit from a
   minimum of the residual.  Near a fold at distance ``d`` the smallest singular value of
   the shooting matrix is ``s ~ sqrt(d)``.  At a true orbit (inside the fold) the
   correction is the floor over ``s``; at the residual's minimum past the fold, where no
   orbit exists, the residual ``R_min ~ d`` is orthogonal to the matrix's range and the
   correction is ``R_min/s ~ sqrt(d)``: Newton jumps about, the residual stagnates (on
   coupled-vdp at mu = 0.08, c = 0.2, 2e-9 past the fold in sigma, at 8.7e-9 after 30
   iterations, which the earlier standard ``1e-8`` accepted);
3. **trivial multiplier** (autonomous systems): the eigenvalue of the monodromy matrix
   nearest 1 lies within :data:`TRIVIAL_TOL` of it.

The bounds of tests 1 and 2 grow by :func:`noise_factor` where the monodromy matrix is
large (near a separatrix the integration error of the residual grows with it).  The
compiled corrector of one degree of freedom (``numerics/flow/_shooting_corrector.py``)
takes these numbers as arguments (:meth:`numerics.shooting.planar.PlanarProblem.correct`
passes them), so both correctors apply this one standard.

A rejected orbit is reported with the numbers: "no periodic orbit here: the smallest
residual is R at a distance D from the start", with the shooting matrix's smallest
singular value there (small: a fold of cycles is near).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from numerics.errors import ConvergenceError

__all__ = ["RESIDUAL_FACTOR", "CORRECTION_FACTOR", "TRIVIAL_TOL", "NOISE_RTOL", "orbit_scale",
           "noise_factor", "residual_tolerance", "correction_tolerance", "accepted",
           "trivial_ok",
           "NewtonTrace", "shoot_newton", "no_orbit_message"]

#: the residual's bound in units of ``rtol`` times the orbit's scale (the integration floor)
RESIDUAL_FACTOR = 100.0

#: the Newton correction's bound in units of ``sqrt(rtol)`` times the orbit's scale
CORRECTION_FACTOR = 1.0

#: ``|trivial multiplier - 1|`` bound of an autonomous orbit (near a separatrix the monodromy
#: loses accuracy first: on the SEDF branch in Delta the last 15 points of 63 had it off by
#: 1e-5 to 5e-2 before this test)
TRIVIAL_TOL = 1e-5

#: the integrator's tolerance at which a monodromy matrix of size 1 leaves the bounds as
#: they are (:func:`noise_factor`)
NOISE_RTOL = 1e-8


def orbit_scale(y) -> float:
    """``S = max(1, ||y||_inf)``: the scale the tolerances are relative to."""
    return max(1.0, float(np.max(np.abs(np.asarray(y, dtype=float)))))


def noise_factor(size: float, rtol: float) -> float:
    """``max(1, size rtol / NOISE_RTOL)``: the factor of the bounds of tests 1 and 2 for a
    monodromy matrix of size ``size`` (its largest entry)."""
    return max(1.0, size * rtol / NOISE_RTOL)


def residual_tolerance(rtol: float, scale: float, noise: float = 1.0) -> float:
    """The largest residual accepted: ``RESIDUAL_FACTOR * rtol * scale * noise``
    (``noise >= 1`` where the monodromy matrix is large, near a separatrix)."""
    return RESIDUAL_FACTOR * rtol * scale * noise


def correction_tolerance(rtol: float, scale: float, noise: float = 1.0) -> float:
    """The largest Newton correction accepted: ``CORRECTION_FACTOR * sqrt(rtol) * scale``."""
    return CORRECTION_FACTOR * math.sqrt(rtol) * scale * noise


def accepted(residual: float, correction: float, rtol: float, scale: float,
             noise: float = 1.0) -> bool:
    """Tests 1 and 2 of the standard (see the module's description)."""
    return (residual <= residual_tolerance(rtol, scale, noise)
            and correction <= correction_tolerance(rtol, scale, noise))


def trivial_ok(multipliers) -> bool:
    """Test 3: an eigenvalue of the monodromy within :data:`TRIVIAL_TOL` of 1."""
    z = np.asarray(multipliers, dtype=complex)
    return bool(np.min(np.abs(z - 1.0)) <= TRIVIAL_TOL)


@dataclass
class NewtonTrace:
    """What Newton's iterations leave: the residuals and corrections, and the iterate with
    the smallest residual (its distance from the start, the shooting matrix's smallest
    singular value there)."""

    residuals: list = field(default_factory=list)
    corrections: list = field(default_factory=list)
    #: (residual, distance, smallest singular value, Newton correction) at the best iterate
    best: tuple = (math.inf, 0.0, math.nan, math.nan)

    def note(self, residual: float, distance: float, matrix: np.ndarray | None) -> None:
        self.residuals.append(float(residual))
        if residual < self.best[0]:
            smin = math.nan
            if matrix is not None and np.all(np.isfinite(matrix)):
                smin = float(np.linalg.svd(matrix, compute_uv=False)[-1])
            self.best = (float(residual), float(distance), smin, math.nan)

    def correction(self, value: float) -> None:
        """The Newton correction computed at the last iterate noted."""
        self.corrections.append(float(value))
        if self.residuals and self.residuals[-1] == self.best[0]:
            self.best = (*self.best[:3], float(value))


def no_orbit_message(trace: NewtonTrace, rtol: float, scale: float, what: str = "",
                     noise: float = 1.0) -> str:
    """"no periodic orbit here: the smallest residual is R at a distance D ...", with the
    numbers of ``trace``."""
    r, dist, smin, corr = trace.best
    tol = residual_tolerance(rtol, scale, noise)
    if math.isfinite(corr) and r <= tol:
        ctol = correction_tolerance(rtol, scale, noise)
        dist = (f"{dist:.2e} from the start, where Newton's correction is {corr:.2e} "
                f"(accepted: {ctol:.2e}): a minimum of the residual, not an orbit")
    else:
        dist = f"{dist:.2e} from the start"
    last = ", ".join(f"{h:.2e}" for h in trace.residuals[-5:])
    fold = ""
    if math.isfinite(smin) and smin < 1e-2:
        fold = (f"; the shooting matrix's smallest singular value there is {smin:.2e}: a "
                "fold of cycles is near (past it no orbit exists)")
    elif math.isfinite(smin):
        fold = f"; the shooting matrix's smallest singular value there is {smin:.2e}"
    return (f"no periodic orbit{' ' + what if what else ''} here: the smallest residual is "
            f"{r:.2e} (accepted: {tol:.2e} at the orbit's scale {scale:.4g}) at a distance "
            f"{dist}{fold}; Newton's residuals {last} after "
            f"{len(trace.residuals)} iterations")


def shoot_newton(evaluate: Callable, z0, *, rtol: float, scale: Callable, max_iter: int,
                 damp: Callable | None = None, what: str = "", diverge: int = 5,
                 noise: Callable | None = None, accuracy: float | None = None,
                 degenerate: Callable | None = None):
    """Newton's method on a square shooting problem, ended by the acceptance standard.

    Parameters
    ----------
    evaluate
        ``z -> (R, M, state)``: the residual (its first part ``phi_T(y0) - y0``, the rest
        conditions such as the phase), the square shooting matrix ``dR/dz`` and anything
        the caller wants back for the accepted iterate.
    z0
        The start.
    rtol
        The integrator's tolerance.
    scale
        ``z -> S``, the orbit's scale at ``z``.
    max_iter
        Bound on the iterations.
    damp
        ``(z, dz) -> lam`` in ``(0, 1]``, the fraction of the step taken (default 1).
    diverge
        Stop when the residual grew this many times less one in a row.
    noise
        ``state -> factor >= 1`` of the tolerances (default 1).
    accuracy
        A caller's bound on the last correction relative to the orbit's scale, on top of
        the standard (the accuracy of the orbit returned, not its existence).
    degenerate
        ``(z, R, state) -> bool``: the iterate is a closed orbit whose shooting matrix is
        singular (a non-trivial multiplier 1 to the floor: a conservative system), returned
        as it is for the caller's check of isolation.

    Returns
    -------
    ``(z, iterations, trace, state)``: the accepted iterate plus its last correction, with
    the ``state`` of its evaluation.

    Raises
    ------
    numerics.errors.ConvergenceError
        With :func:`no_orbit_message` when no iterate passes the standard, or when the
        shooting matrix is singular.
    """
    z = np.array(z0, dtype=float)
    start = z.copy()
    trace = NewtonTrace()
    why = f"Newton did not converge in {max_iter} iterations"
    for it in range(1, max_iter + 1):
        R, M, state = evaluate(z)
        res = float(np.max(np.abs(R)))
        trace.note(res, float(np.max(np.abs(z - start))), M)
        if degenerate is not None and degenerate(z, R, state):
            return z, it, trace, state
        try:
            dz = np.linalg.solve(M, -np.asarray(R, dtype=float))
        except np.linalg.LinAlgError:
            raise ConvergenceError(f"singular shooting matrix{' ' + what if what else ''} "
                                   "(a non-hyperbolic orbit, or the section is not "
                                   "transversal there); "
                                   f"{no_orbit_message(trace, rtol, scale(z), what)}") from None
        corr = float(np.max(np.abs(dz)))
        trace.correction(corr)
        nz = 1.0 if noise is None else noise(state)
        if accepted(res, corr, rtol, scale(z), nz) and (
                accuracy is None or corr <= accuracy * scale(z)):
            return z + dz, it, trace, state
        lam = 1.0 if damp is None else damp(z, dz)
        z = z + lam * dz
        h = trace.residuals
        if not np.all(np.isfinite(z)):
            why = f"Newton left the finite numbers after {it} iterations"
            break
        if len(h) >= diverge and all(b > a for a, b in zip(h[-diverge:], h[1 - diverge:])):
            why = f"Newton diverges: the residual grew {diverge - 1} times in a row"
            break
    last = z if np.all(np.isfinite(z)) else start
    raise ConvergenceError(f"{why}; {no_orbit_message(trace, rtol, scale(last), what)}")
