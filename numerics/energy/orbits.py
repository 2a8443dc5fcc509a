"""Conservative orbits sampled uniformly in time, for many energies at once.

The orbit of energy ``E`` of ``x'' + g(x) = 0`` is written ``x = X(E, theta)``,
``x' = V(E, theta)`` with the angle ``theta = 2 pi t/T(E)``, ``theta = 0`` at the
right turning point ``x+(E)`` (so ``X`` is even and ``V`` odd in ``theta``).  All
energies are integrated in one vectorised DOP853 solve in the scaled time
``tau = t/T(E)`` over ``0 <= tau <= 1``; samples on a uniform ``theta`` grid make
``theta``-derivatives FFTs.

References
----------
S. Coppola and R. H. Rand, Acta Mechanica 81 (1990), section 2 (the
generating solution of the strongly nonlinear averaging).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

from .portrait import Annulus

__all__ = ["SampledOrbits", "sample_orbits"]


@dataclass(frozen=True, eq=False)
class SampledOrbits:
    """Orbits ``X[i, j] = X(E_i, theta_j)``, ``V[i, j]``, ``theta_j = 2 pi j/n``.

    Attributes
    ----------
    energy : numpy.ndarray
        The energies, shape ``(nE,)``.
    theta : numpy.ndarray
        The angles, shape ``(ntheta,)``.
    X, V : numpy.ndarray
        Displacement and velocity, shape ``(nE, ntheta)``.
    period : numpy.ndarray
        ``T(E)`` used for the time scaling.
    closure : float
        ``max |x(T) - x+| + |v(T)|`` over the energies: the integration error.
    """

    energy: np.ndarray
    theta: np.ndarray
    X: np.ndarray
    V: np.ndarray
    period: np.ndarray
    closure: float

    def harmonics(self, n: int = 16) -> np.ndarray:
        """Complex coefficients ``c_m`` of ``X = sum_m c_m e^{i m theta}``, ``m = 0..n-1``.

        Returns
        -------
        numpy.ndarray
            Shape ``(nE, n)``; the first-harmonic amplitude is ``2 |c_1|``.
        """
        c = np.fft.rfft(self.X, axis=-1) / self.X.shape[-1]
        return c[:, :n]


def sample_orbits(annulus: Annulus, energies, n_theta: int = 128, *, rtol: float = 1e-13,
                  period=None) -> SampledOrbits:
    """Sample the conservative orbits of ``annulus`` at ``energies`` uniformly in time.

    Parameters
    ----------
    annulus : numerics.energy.portrait.Annulus
        The period annulus the energies lie in.
    energies : array_like
        Energies strictly inside the annulus.
    n_theta : int
        Samples per period.
    rtol : float
        Tolerance of the DOP853 integration (``atol = rtol * max|x+|``).
    period : array_like, optional
        ``T(E)`` if already known (else from :meth:`Annulus.quadrature`).

    Returns
    -------
    SampledOrbits
    """
    g = annulus._fun[0]
    E = np.atleast_1d(np.asarray(energies, float))
    T = annulus.period(E) if period is None else np.asarray(period, float)
    _, xp = annulus.turning_points(E)
    nE = len(E)

    def rhs(_, y):
        return np.concatenate([T * y[nE:], -T * g(y[:nE])])

    theta = 2 * np.pi * np.arange(n_theta) / n_theta
    scale = max(1.0, float(np.max(np.abs(xp))))
    sol = solve_ivp(rhs, (0.0, 1.0), np.concatenate([xp, np.zeros(nE)]), method="DOP853",
                    t_eval=np.append(theta / (2 * np.pi), 1.0), rtol=rtol, atol=rtol * scale)
    y = sol.y
    X, V = y[:nE, :-1], y[nE:, :-1]
    closure = float(np.max(np.abs(y[:nE, -1] - xp) + np.abs(y[nE:, -1]) / (2 * np.pi / T)))
    return SampledOrbits(E, theta, X, V, T, closure)
