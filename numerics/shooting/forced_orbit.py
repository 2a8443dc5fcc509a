"""True periodic responses of a forced oscillator: shooting at the fixed period, Floquet.

The response of period ``T = 2 pi p/nu`` is a fixed point of the stroboscopic map
``y0 -> y(T)``: Newton's method on ``y(T) - y0 = 0`` with the Jacobian
``Phi(T) - I`` from the variational equations.  The Floquet multipliers are the
eigenvalues of the monodromy matrix ``Phi(T)`` (no trivial multiplier: the period is
imposed); their product is checked against Liouville's ``exp(int_0^T div f dt)``.  The
response's amplitude at the frequency ``(q/p) nu`` — the quantity the KBM amplitude ``a``
predicts — is harmonic ``q`` of the discrete Fourier transform of ``x`` over the period.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from numerics.shooting.orbit import peak, shoot
from numerics.errors import ConvergenceError
from numerics.flow.forced_system import ForcedSystem

__all__ = ["ForcedOrbit", "periodic_response", "orbit_at", "N_SAMPLES"]

#: samples of ``x`` per forcing period for the amplitudes
N_SAMPLES = 128


@dataclass(frozen=True)
class ForcedOrbit:
    """A periodic response of the forced system.

    Attributes
    ----------
    sigma, period
        The detuning and the period ``2 pi p/nu``.
    y0
        ``(x(0), x'(0))``.
    multipliers
        The Floquet multipliers (eigenvalues of the monodromy matrix).
    liouville
        ``|det Phi(T) - exp(int div f)|``, a check of the multipliers.
    amplitude
        Amplitude of the component at the frequency ``(q/p) nu`` (KBM's ``a``).
    phase
        Its phase ``phi`` with ``x ~ a cos((q/p) nu t + phi)``.
    amplitude_max
        ``max |x(t)|`` over the period.
    """

    sigma: float
    period: float
    y0: tuple[float, float]
    multipliers: tuple[complex, complex]
    liouville: float
    amplitude: float
    phase: float
    amplitude_max: float

    @property
    def stable(self) -> bool:
        """Both multipliers inside the unit circle."""
        return max(abs(m) for m in self.multipliers) < 1


def orbit_at(system: ForcedSystem, y0, sigma: float, yT: np.ndarray | None = None) -> ForcedOrbit:
    """The :class:`ForcedOrbit` through ``y0`` (a converged shooting solution)."""
    q = system.resonance.q
    p = system.resonance.p
    n = N_SAMPLES * p
    ys = system.flow(y0, sigma, n_out=n)
    x = ys[:-1, 0]
    c = np.fft.rfft(x) / n
    amp = 2 * abs(c[q])
    # x = a cos(q 2 pi t/T + phi): the DFT coefficient is (a/2) e^{i phi}
    phase = float(np.angle(c[q]))
    Phi = np.array([[ys[-1, 2], ys[-1, 4]], [ys[-1, 3], ys[-1, 5]]])
    mult = np.linalg.eigvals(Phi)
    liou = abs(float(np.linalg.det(Phi)) - math.exp(ys[-1, 6]))
    return ForcedOrbit(float(sigma), system.period(sigma), (float(y0[0]), float(y0[1])),
                       (complex(mult[0]), complex(mult[1])), liou, float(amp), phase,
                       peak(np.abs(x)))


def periodic_response(system: ForcedSystem, sigma: float, guess, *, tol: float = 1e-11,
                      max_iter: int = 30) -> ForcedOrbit:
    """The periodic response near ``guess = (x(0), x'(0))`` at detuning ``sigma``.

    The forced case of :func:`numerics.shooting.orbit.shoot`; Newton's iterate is accepted
    by the standard of :mod:`numerics.shooting.acceptance` at the system's integrator
    tolerance, with its last correction below ``tol (1 + |y|)`` (``2 tol max(1, |y|)``).

    Raises
    ------
    numerics.errors.ConvergenceError
        If Newton's method does not converge (the residuals are in the message).
    """
    def monodromy(y, T):
        yT = system.flow(y, sigma)[-1]
        return yT[:2], np.array([[yT[2], yT[4]], [yT[3], yT[5]]]), None

    try:
        y, _, _, _, _ = shoot(monodromy, guess, system.period(sigma), section=None,
                              rtol=system.rtol, max_iter=max_iter, accuracy=2 * tol,
                              what="of the drive's period")
    except ConvergenceError as exc:
        raise ConvergenceError(f"no periodic response found at sigma = {sigma:.6g} from "
                               f"{tuple(guess)}: {exc} (a multiplier 1 makes the shooting "
                               "matrix singular: a fold)") from None
    return orbit_at(system, y, sigma)
