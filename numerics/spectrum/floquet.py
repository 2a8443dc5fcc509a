"""The small-noise linewidth of the true cycle from its phase response (adjoint Floquet).

For ``x' = v``, ``v' = f(x, v) + sqrt(2 D) xi`` with a stable cycle of period ``T``, the
asymptotic phase ``theta`` (``theta' = Omega = 2 pi/T`` without noise) obeys, to first order
in ``D``, ``d theta = Omega dt + Z_v(theta) sqrt(2 D) dW``, with ``Z = grad theta`` on the
cycle the periodic solution of the adjoint equation ``Z' = -J(t)^T Z`` normalised by
``Z . f = Omega`` (the phase response curve; Kuramoto 1984, sec. 3.2; Demir, Mehrotra and
Roychowdhury, IEEE Trans. Circuits Syst. I 47, 655 (2000)).  The phase therefore diffuses
with ``D_eff = D <Z_v^2>`` (time average over a period): the linewidth exact in ``mu`` and
of first order in ``D``, a reference independent of the averaging.  ``Z`` is found by
integrating the adjoint backwards over many periods, which damps every other component by
the cycle's nontrivial Floquet multiplier per period.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import sympy as sp

from kbm.parameters.bound import bind
from kbm.symbols import x, xdot

from ..errors import NoCycleError
from ..flow.template import acceleration_jacobian

__all__ = ["PhaseResponse", "phase_response"]


@dataclass(frozen=True)
class PhaseResponse:
    """The phase response of a stable cycle and its small-noise linewidth.

    Attributes
    ----------
    period, frequency : float
        ``T`` and ``Omega = 2 pi/T``.
    zv2 : float
        ``<Z_v^2>``: ``D_eff = D zv2``.
    normalisation_spread : float
        Relative spread of ``Z . f`` over the period (0 for an exact adjoint).
    """

    period: float
    frequency: float
    zv2: float
    normalisation_spread: float

    def linewidth(self, D: float) -> float:
        """``D <Z_v^2>``: the HWHM of the fundamental to first order in ``D``."""
        return D * self.zv2


def phase_response(model, params: dict, *, samples: int = 2048) -> PhaseResponse:
    """The phase response of the stable cycle of ``x'' + omega0^2 x = mu F(x, x')``.

    Raises
    ------
    kbm.errors.NonAutonomousError
        For a driven model (a stage velocity ``v != 0``, a forcing): no limit cycle.
    numerics.errors.NoCycleError
        No stable cycle found by shooting.

    Van der Pol at small ``mu``: ``<Z_v^2> -> 1/(2 a*^2) = 1/8`` (0.12507 at ``mu = 0.05``;
    ``tests/test_spectrum_line.py``).
    """
    from scipy.integrate import solve_ivp

    from numerics import limit_cycle

    bm = bind(model, dict(params))
    cyc = limit_cycle(bm)
    if not (cyc.success and cyc.stable):
        raise NoCycleError(f"no stable limit cycle of {bm.name} by shooting ({cyc.message}): "
                           "no line to speak of")
    subs = bm.subs()
    m = bm.model
    acc = m.acceleration().subs(subs)  # autonomous: limit_cycle refused a drive
    jx, jv = acceleration_jacobian(acc, m.name)
    fa, fx, fv = (sp.lambdify((x, xdot), e, modules=["numpy", "scipy"]) for e in (acc, jx, jv))
    T = float(cyc.period)
    y0 = [float(cyc.x[0]), float(cyc.xdot[0])]

    def rhs(t, y):
        return [y[1], float(fa(y[0], y[1]))]

    orbit = solve_ivp(rhs, (0.0, T), y0, rtol=1e-12, atol=1e-12, dense_output=True,
                      method="DOP853")

    def adjoint(t, z):
        xs, vs = orbit.sol(t)
        return [-float(fx(xs, vs)) * z[1], -(z[0] + float(fv(xs, vs)) * z[1])]

    rho = min(abs(float(np.abs(mlt))) for mlt in cyc.floquet_multipliers
              if abs(abs(mlt) - 1) > 1e-6) if len(cyc.floquet_multipliers) > 1 else 0.5
    periods = int(min(400, max(5, math.ceil(30 / max(-math.log(max(rho, 1e-12)), 1e-3)))))
    f0 = np.array(rhs(0.0, y0))
    z = f0 / float(f0 @ f0)
    for _ in range(periods):
        run = solve_ivp(adjoint, (T, 0.0), z, rtol=1e-11, atol=1e-13, dense_output=True,
                        method="DOP853")
        z = run.y[:, -1]
    ts = np.linspace(0.0, T, samples, endpoint=False)
    Z = run.sol(ts)
    Y = orbit.sol(ts)
    F = np.vstack([Y[1], fa(Y[0], Y[1]) * np.ones_like(ts)])
    zf = np.sum(Z * F, axis=0)
    omega = 2 * math.pi / T
    Z = Z * omega / zf.mean()
    return PhaseResponse(T, omega, float(np.mean(Z[1] ** 2)), float(np.ptp(zf) / abs(zf.mean())))
