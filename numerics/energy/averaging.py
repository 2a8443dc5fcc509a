"""Strongly nonlinear averaging to order ``N`` in energy-angle variables.

With the conservative orbit ``x = X(E, theta)``, ``x' = V(E, theta)``
(:mod:`numerics.energy.orbits`), ``x'' = -g(x) + mu h(x, x')`` becomes

``dE/dt = mu f(E, theta)``, ``f = h(X, V) V``;
``dtheta/dt = omega(E) + mu k(E, theta)``, ``k = -omega(E) X_E h(X, V)``.

The near-identity transformation ``E = eps + sum mu**n e_n(eps, phi)``,
``theta = phi + sum mu**n t_n(eps, phi)`` with ``deps/dt = sum mu**n M_n(eps)``,
``dphi/dt = omega(eps) + sum mu**n Theta_n(eps)`` is computed numerically: the
power series in ``mu`` have ``(nE, ntheta)`` grid arrays as coefficients (a
Chebyshev grid in ``E`` on an interval around the cycle, a uniform grid in
``theta``); ``f``, ``k``, ``omega`` and ``X`` are composed with them by Taylor
expansion with spectral derivatives (Chebyshev differentiation in ``E``, FFT
in ``theta``).  Order ``n`` gives the homological equations

``omega d e_n/dphi = R_n - M_n``, ``omega d t_n/dphi = S_n + omega' e_n - Theta_n``

solved harmonic by harmonic.  The gauge fixing the ``phi``-means of ``e_n``,
``t_n``: the order-``n`` part of ``x(eps, phi) = X(E, theta)`` has no first
harmonic (``n >= 1``), so ``eps`` and ``phi`` are the energy and phase of the
first harmonic of the motion, as ``a`` and ``psi`` are in KBM (where ``u_n``
has no first harmonic); ``Theta_n`` gets ``omega'(eps) mean(e_n)``.  For
linear ``g = omega0**2 x``, ``M_n = omega0**2 a A_n(a)`` with
``eps = omega0**2 a**2/2`` and ``Theta_n = B_n``.

References
----------
N. N. Bogoliubov and Y. A. Mitropolsky, *Asymptotic Methods in the Theory of
Non-Linear Oscillations*, the chapter on systems close to non-linear
conservative ones; S. Coppola and R. H. Rand, Acta Mechanica 81 (1990);
S. B. Yuste and J. D. Bejarano, Int. J. Control 49 (1989).
"""

from __future__ import annotations

from dataclasses import dataclass
from math import factorial

import numpy as np
from numpy.polynomial import chebyshev as C

from .orbits import sample_orbits
from .portrait import Annulus

__all__ = ["AveragedEnergy", "average"]


def _cheb_diff(n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Chebyshev points of the first kind on [-1, 1], values->coefficients, d/du matrix."""
    u = np.cos(np.pi * (np.arange(n) + 0.5) / n)
    Vinv = np.linalg.inv(C.chebvander(u, n - 1))
    D = C.chebvander(u, n - 2) @ C.chebder(Vinv, axis=0)
    return u, Vinv, D


@dataclass(frozen=True, eq=False)
class AveragedEnergy:
    """The averaged equations ``deps/dt = sum mu**n M_n``, ``dphi/dt = omega + sum mu**n Theta_n``.

    Attributes
    ----------
    annulus : Annulus
    mu : float
    order : int
    interval : tuple of float
        ``(eps_lo, eps_hi)`` where the Chebyshev interpolants hold.
    M, Theta : numpy.ndarray
        Chebyshev coefficients (in ``u = (2 eps - lo - hi)/(hi - lo)``) of
        ``M_n`` and ``Theta_n``, shape ``(order + 1, nE)`` (row 0: zero and ``omega``).
    x : numpy.ndarray
        Chebyshev coefficients in ``u`` of the order-``n`` parts of
        ``x(eps, phi)`` on the uniform ``phi`` grid, shape ``(order + 1, nE, ntheta)``.
    error : float
        Estimated relative error: the size of the last two Chebyshev
        coefficients of ``M`` and ``x``, and of the highest ``theta`` harmonics,
        relative to the largest (the truncation of the spectral representation,
        not the error of the mu-expansion).
    """

    annulus: Annulus
    mu: float
    order: int
    interval: tuple
    M: np.ndarray
    Theta: np.ndarray
    x: np.ndarray
    error: float

    def _u(self, eps):
        lo, hi = self.interval
        return (2 * np.asarray(eps, float) - lo - hi) / (hi - lo)

    def rate(self, eps, order: int | None = None, derivative: int = 0):
        """``sum_{n<=order} mu**n M_n(eps)`` (or its ``derivative``-th eps-derivative)."""
        N = self.order if order is None else order
        c = sum(self.mu**n * self.M[n] for n in range(1, N + 1))
        lo, hi = self.interval
        for _ in range(derivative):
            c = C.chebder(c) * 2 / (hi - lo)
        return C.chebval(self._u(eps), c)

    def frequency(self, eps, order: int | None = None):
        """``omega(eps) + sum_{n<=order} mu**n Theta_n(eps)``."""
        N = self.order if order is None else order
        c = sum(self.mu**n * self.Theta[n] for n in range(0, N + 1))
        return C.chebval(self._u(eps), c)

    def waveform(self, eps: float, order: int | None = None) -> np.ndarray:
        """``x(eps, phi_j) = sum_{n<=order} mu**n x_n(eps, phi_j)`` on the ``phi`` grid."""
        N = self.order if order is None else order
        c = sum(self.mu**n * self.x[n] for n in range(0, N + 1))
        return np.tensordot(C.chebvander(float(self._u(eps)), c.shape[0] - 1)[0], c, axes=(0, 0))

    def roots(self, order: int | None = None) -> np.ndarray:
        """Roots of the averaged rate inside the interval."""
        N = self.order if order is None else order
        c = sum(self.mu**n * self.M[n] for n in range(1, N + 1))
        r = C.chebroots(c)
        r = np.real(r[(np.abs(r.imag) < 1e-9) & (np.abs(r.real) <= 1)])
        lo, hi = self.interval
        return np.sort(lo + (hi - lo) * (r + 1) / 2)


def average(annulus: Annulus, mu: float, order: int, interval: tuple[float, float], *,
            n_energy: int = 24, n_theta: int = 256) -> AveragedEnergy:
    """Averaged equations to ``order`` on ``interval`` (inside ``annulus``).

    Parameters
    ----------
    annulus : Annulus
        The period annulus (from :func:`numerics.energy.portrait.phase_portrait`).
    mu : float
        The small parameter.
    order : int
        ``N >= 1``: the powers of ``mu`` kept.
    interval : tuple of float
        Energies ``(lo, hi)`` strictly inside the annulus around the cycle.
    n_energy, n_theta : int
        Chebyshev nodes in energy and samples per period (use an even ``n_theta``
        large enough for the products of the harmonics).

    Returns
    -------
    AveragedEnergy
    """
    h = annulus._fun[3]
    lo, hi = map(float, interval)
    u, Vinv, Du = _cheb_diff(n_energy)
    D = Du * 2 / (hi - lo)
    E = lo + (hi - lo) * (u + 1) / 2
    orb = sample_orbits(annulus, E, n_theta)
    X, V, T = orb.X, orb.V, orb.period
    omega = 2 * np.pi / T
    m = np.fft.rfftfreq(n_theta, 1.0 / n_theta)

    def dE(F):
        return np.tensordot(D, F, axes=(1, 0))

    def dth(F):
        return np.fft.irfft(1j * m * np.fft.rfft(F, axis=-1), n_theta, axis=-1)

    def solve(R):  # omega dU/dphi = R - mean(R), zero mean
        Rh = np.fft.rfft(R, axis=-1)
        Rh[..., 0] = 0
        Rh[..., 1:] /= 1j * m[1:] * omega[:, None]
        return np.fft.irfft(Rh, n_theta, axis=-1)

    hXV = h(X, V)
    Xe = dE(X)
    fields = {"f": hXV * V, "k": -omega[:, None] * Xe * hXV, "X": X,
              "w": np.repeat(omega[:, None], n_theta, axis=1)}
    cache: dict = {}

    def deriv(name, p, q):
        key = (name, p, q)
        if key not in cache:
            if p == q == 0:
                cache[key] = fields[name]
            elif q > 0:
                cache[key] = dth(deriv(name, p, q - 1))
            else:
                cache[key] = dE(deriv(name, p - 1, 0))
        return cache[key]

    N = order
    shape = (N + 1, n_energy, n_theta)
    e, t = np.zeros(shape), np.zeros(shape)

    def mul(a, b):
        c = np.zeros(shape)
        for n in range(N + 1):
            for j in range(n + 1):
                c[n] += a[j] * b[n - j]
        return c

    def powers(s, K):
        out = [np.zeros(shape)]
        out[0][0] = 1.0
        for _ in range(K):
            out.append(mul(out[-1], s))
        return out

    def compose(name, K, theta_dep=True):
        pe, pt = powers(e, K), powers(t, K if theta_dep else 0)
        out = np.zeros(shape)
        for p in range(K + 1):
            for q in range(K + 1 - p if theta_dep else 1):
                out += (deriv(name, p, q)[None] / (factorial(p) * factorial(q))
                        * mul(pe[p], pt[q]))
        return out

    Mg = np.zeros((N + 1, n_energy))
    Th = np.zeros((N + 1, n_energy))
    Th[0] = omega
    wp = dE(omega)
    c1 = np.cos(orb.theta) * 2 / n_theta
    s1 = np.sin(orb.theta) * 2 / n_theta
    Xth = dth(X)
    a11, a12, a21, a22 = Xe @ c1, Xth @ c1, Xe @ s1, Xth @ s1
    det = a11 * a22 - a12 * a21
    for n in range(1, N + 1):
        cross_e = sum(dE(e[j]) * Mg[n - j][:, None] + dth(e[j]) * Th[n - j][:, None]
                      for j in range(1, n))
        R = compose("f", n - 1)[n - 1] - cross_e
        Mg[n] = R.mean(axis=-1)
        e[n] = solve(R)
        cross_t = sum(dE(t[j]) * Mg[n - j][:, None] + dth(t[j]) * Th[n - j][:, None]
                      for j in range(1, n))
        S = compose("w", n, theta_dep=False)[n] + compose("k", n - 1)[n - 1] - cross_t
        Th[n] = S.mean(axis=-1)
        t[n] = solve(S)
        Y = compose("X", n)[n]
        b1, b2 = -(Y @ c1), -(Y @ s1)
        ebar = (b1 * a22 - a12 * b2) / det
        tbar = (a11 * b2 - a21 * b1) / det
        e[n] += ebar[:, None]
        t[n] += tbar[:, None]
        Th[n] += wp * ebar
    xs = compose("X", N)
    Mc, Tc = Vinv @ Mg.T, Vinv @ Th.T
    xc = np.tensordot(Vinv, xs, axes=(1, 1))  # (nE, N+1, ntheta)
    spec = np.abs(np.fft.rfft(X, axis=-1))
    tail = [np.max(np.abs(Mc[-2:, 1:])) / max(np.max(np.abs(Mc[:, 1:])), 1e-300),
            np.max(np.abs(xc[-2:])) / np.max(np.abs(xc)),
            np.max(spec[:, -4:]) / np.max(spec)]
    return AveragedEnergy(annulus, float(mu), N, (lo, hi), Mc.T.copy(), Tc.T.copy(),
                          np.moveaxis(xc, 1, 0).copy(), float(max(tail)))


def _extrema(x: np.ndarray) -> tuple[float, float]:
    """Max and min of the trigonometric interpolant of samples ``x`` (Newton on the series)."""
    n = len(x)
    c = np.fft.rfft(x) / n
    m = np.arange(len(c))
    w = np.where((m == 0) | ((n % 2 == 0) & (m == n // 2)), 1.0, 2.0)
    out = []
    for j in (int(np.argmax(x)), int(np.argmin(x))):
        p = 2 * np.pi * j / n
        for _ in range(8):
            e = w * c * np.exp(1j * m * p)
            d1, d2 = np.real(np.sum(1j * m * e)), np.real(np.sum(-(m**2) * e))
            if d2 == 0:
                break
            p -= d1 / d2
        out.append(float(np.real(np.sum(w * c * np.exp(1j * m * p)))))
    return out[0], out[1]
