"""Newton's method on the return map to ``x' = 0, x > 0``, and the check that its result is a cycle.

The unknowns are ``(x0, T)``; the residual ``(x(T) - x0, x'(T))`` and its Jacobian come
from one integration of the extended system (state and variational equations,
:func:`numerics.flow.flow`).  Newton does not care about the stability of the cycle:
started near an unstable cycle it converges to it.
"""

from __future__ import annotations

import numpy as np

from numerics.shooting.acceptance import RESIDUAL_FACTOR, noise_factor, orbit_scale, trivial_ok
from numerics.shooting.orbit import NEWTON_MAX_STEPS, shoot
from numerics.errors import ConvergenceError, NoCycleError
from numerics.flow import extended_state, flow

__all__ = ["newton", "check_nontrivial"]



def newton(cm, x0, T, method, rtol, atol, max_iter, floor):
    """Newton's method on ``(x(T) - x0, x'(T)) = 0`` for the unknowns ``(x0, T)``: the case
    ``N = 1`` of :func:`numerics.shooting.orbit.shoot` (section ``x' = 0``), its standard at
    this shooting's floor ``1e3 max(rtol, atol)`` (LSODA and scipy's implicit methods included),
    the tolerances raised with the monodromy matrix near a separatrix.

    Returns ``(x0, T, iterations, residuals)``.
    """
    budget = [NEWTON_MAX_STEPS, True]  # the bound, and whether it is still to be set
    tol = floor / RESIDUAL_FACTOR  # the standard's rtol: residuals up to ``floor`` times S

    def monodromy(y, T):
        steps: list[int] = []
        yT = flow(cm, extended_state(y[0]), T, 1, method, rtol, atol, max_steps=budget[0],
                  steps=steps)[-1]
        if budget[1] and steps:
            budget[1] = False
            # later iterates near the cycle need about as many steps as the first: many
            # more means Newton has wandered into a stiff region
            budget[0] = min(NEWTON_MAX_STEPS, max(5000, 50 * steps[0]))
        return yT[:2], np.array([[yT[2], yT[4]], [yT[3], yT[5]]]), yT

    def noise(yT):  # the integration error of R grows with the monodromy matrix
        return noise_factor(float(np.max(np.abs(yT[2:4]))), rtol)

    def damp(z, dz):
        # damp steps that would leave the section, reverse time, or change x0 or T by
        # more than half (a far start then walks instead of jumping into stiff regions)
        lam = min(1.0, 0.5 * max(1.0, abs(z[0])) / max(abs(dz[0]), 1e-300),
                  0.5 * z[1] / max(abs(dz[1]), 1e-300))
        while ((z[0] + lam * dz[0]) * z[0] <= 0 or z[1] + lam * dz[1] <= 0) and lam > 1e-3:
            lam /= 2
        return lam

    tight = max(rtol, atol)

    def degenerate(z, R, yT):
        # a closed orbit to the integrator's own tolerance whose non-trivial multiplier is 1
        # (Phi_11 on the section): the Newton matrix is singular and the correction
        # meaningless; the final pass refuses the orbit as not isolated (a conservative
        # system).  Near a fold Phi_11 is 1 as well, but the residual past it is ~ the
        # distance (6e-10 at 1e-9 past the fold of nu + x^2 - x^4/4 at mu = 0.1), far
        # above a closed orbit's (2e-13 for x'' + x^3 = 0 at rtol 1e-12)
        closed = bool(np.max(np.abs(R)) <= tight * orbit_scale(z[0]) * noise(yT))
        # an equilibrium on the section (x' = 0 and x'' = 0 there): the motion rests, every
        # T closes it and Newton can only wander; check_nontrivial names it
        rest = abs(cm.acc(z[1], z[0], 0.0)) <= tight * orbit_scale(z[0])
        return closed and (abs(yT[2] - 1.0) <= 100 * tight or rest)

    try:
        y, T1, it, trace, _ = shoot(monodromy, [x0, 0.0], T, section=1, rtol=tol,
                                    max_iter=max_iter, damp=damp, noise=noise,
                                    degenerate=degenerate, what="on the return map to x' = 0",
                                    rhs=lambda yT, T: (yT[1], cm.acc(T, yT[0], yT[1])))
    except ConvergenceError as exc:
        raise ConvergenceError(f"{exc}; residuals |(x(T) - x0, x'(T))| from x0 = {x0:.10g}, "
                               f"T = {T:.10g}") from None
    return float(y[0]), float(T1), it, trace.residuals


def check_nontrivial(cm, converged, meth, rtol, atol, scale) -> None:
    """Reject a 'cycle' that is an equilibrium or whose trivial multiplier is not 1 (test 3 of
    the standard, :func:`numerics.shooting.acceptance.trivial_ok`)."""
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
    if not trivial_ok(mults):
        raise ConvergenceError(f"the orbit found (x0 = {x0:.6g}, T = {T:.6g}) has no Floquet "
                               f"multiplier 1 ({mults[0]:.6g}, {mults[1]:.6g}): not a cycle")


