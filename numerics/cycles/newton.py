"""Newton's method on the return map to ``x' = 0, x > 0``, and the check that its result is a cycle.

The unknowns are ``(x0, T)``; the residual ``(x(T) - x0, x'(T))`` and its Jacobian come
from one integration of the extended system (state and variational equations,
:func:`numerics.flow.flow`).  Newton does not care about the stability of the cycle:
started near an unstable cycle it converges to it.
"""

from __future__ import annotations

import numpy as np

from numerics.cycles.acceptance import (RESIDUAL_FACTOR, TRIVIAL_TOL, accepted, orbit_scale,
                                        residual_tolerance)
from numerics.errors import ConvergenceError, NoCycleError
from numerics.flow import extended_state, flow

__all__ = ["NEWTON_MAX_STEPS", "newton", "check_nontrivial"]

#: bound on the compiled integrator's steps over one period inside Newton's method
NEWTON_MAX_STEPS = 5 * 10**4


def newton(cm, x0, T, method, rtol, atol, max_iter, floor):
    """Newton's method on ``(x(T) - x0, x'(T)) = 0`` for the unknowns ``(x0, T)``."""
    history: list[float] = []
    it = 0
    budget = NEWTON_MAX_STEPS
    while True:
        it += 1
        steps: list[int] = []
        yT = flow(cm, extended_state(x0), T, 1, method, rtol, atol, max_steps=budget,
                  steps=steps)[-1]
        if it == 1 and steps:
            # later iterates near the cycle need about as many steps as the first: many
            # more means Newton has wandered into a stiff region
            budget = min(NEWTON_MAX_STEPS, max(5000, 50 * steps[0]))
        r = np.array([yT[0] - x0, yT[1]])
        history.append(float(np.max(np.abs(r))))
        acc = cm.acc(T, yT[0], yT[1])
        J = np.array([[yT[2] - 1.0, yT[1]], [yT[3], acc]])
        try:
            dx, dT = np.linalg.solve(J, -r)
        except np.linalg.LinAlgError:
            raise ConvergenceError(f"singular Newton matrix at x0 = {x0:.10g}, T = {T:.10g} "
                                   "(non-hyperbolic cycle or x' = 0 is not a transversal "
                                   "section there)") from None
        # damp steps that would leave the section, reverse time, or change x0 or T by
        # more than half (a far start then walks instead of jumping into stiff regions)
        lam = min(1.0, 0.5 * max(1.0, abs(x0)) / max(abs(dx), 1e-300),
                  0.5 * T / max(abs(dT), 1e-300))
        while ((x0 + lam * dx) * x0 <= 0 or T + lam * dT <= 0) and lam > 1e-3:
            lam /= 2
        # the acceptance standard (numerics.cycles.acceptance) at the iterate, its
        # correction added, at the floor of this shooting, 1e3 max(rtol, atol) (LSODA and
        # scipy's implicit methods included); the integration error of R grows with the
        # monodromy matrix (near a separatrix)
        noise = max(1.0, float(np.max(np.abs(yT[2:4]))) * rtol / 1e-8)
        if accepted(history[-1], max(abs(dx), abs(dT)), floor / RESIDUAL_FACTOR,
                    orbit_scale(x0), noise):
            return x0 + dx, T + dT, it, history
        if history[-1] <= residual_tolerance(floor / RESIDUAL_FACTOR, orbit_scale(x0), noise) \
                and abs(yT[2] - 1.0) <= floor:
            # a closed orbit whose non-trivial multiplier is 1 to the floor (Phi_11 on the
            # section): the Newton matrix is singular and the correction meaningless; past a
            # fold a residual minimum has |Phi_11 - 1| ~ sqrt(distance), far above it.  The
            # final pass refuses the orbit as not isolated (a conservative system)
            return x0, T, it, history
        x0, T = x0 + lam * dx, T + lam * dT
        if len(history) >= 5 and all(b > a for a, b in zip(history[-5:], history[-4:])):
            raise ConvergenceError(
                f"Newton on the return map diverges: the residual |(x(T) - x0, x'(T))| grew "
                f"four times in a row ({', '.join(f'{h:.2e}' for h in history[-5:])}); "
                f"last x0 = {x0:.10g}, T = {T:.10g}")
        if it >= max_iter or not (np.isfinite(x0) and np.isfinite(T)):
            raise ConvergenceError(
                f"Newton on the return map did not converge in {it} iterations; residuals "
                f"|(x(T) - x0, x'(T))|: {', '.join(f'{h:.2e}' for h in history[-6:])}; "
                f"last x0 = {x0:.10g}, T = {T:.10g}")


def check_nontrivial(cm, converged, meth, rtol, atol, scale) -> None:
    """Reject a 'cycle' that is an equilibrium or whose trivial multiplier is not 1."""
    x0, T, it, history = converged
    if abs(x0) < 1e-6 * max(1.0, abs(scale)):
        raise ConvergenceError(f"Newton converged to the equilibrium (x0 = {x0:.3g}), not to a "
                               "cycle")
    ys = flow(cm, extended_state(x0), T, 64, meth, rtol, atol)
    spread = float(np.ptp(ys[:, 0]))
    if spread < 1e-6 * max(1.0, abs(x0)):
        raise NoCycleError(f"no limit cycle: the motion settles to rest at x = {x0:.6g} (an "
                           f"equilibrium of the potential; x varies by {spread:.2e} over "
                           f"T = {T:.4g}); start elsewhere (x_start) to look for a cycle")
    yT = ys[-1]
    mults = np.linalg.eigvals(np.array([[yT[2], yT[4]], [yT[3], yT[5]]]))
    if np.min(np.abs(mults - 1.0)) > TRIVIAL_TOL:
        raise ConvergenceError(f"the orbit found (x0 = {x0:.6g}, T = {T:.6g}) has no Floquet "
                               f"multiplier 1 ({mults[0]:.6g}, {mults[1]:.6g}): not a cycle")


