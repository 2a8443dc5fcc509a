"""Jacobi-Anger series at given amplitudes, with exact derivatives in ``a`` (Taylor jets).

The evaluation path of the KBM recursion for ``F`` with ``sin(k x)``, ``cos(k x)`` at
*any* order.  The symbolic algebra (:mod:`~kbm.algebra.bessel_fourier`) keeps every
Bessel sum; here the parameters are numbers and each quantity is computed at a set
of amplitudes ``a_q`` as a truncated Taylor series (a *jet*) in ``h = a - a_q``:

- ``sin(k a cos psi)``, ``cos(k a cos psi)`` and their derivatives are the
  Jacobi-Anger series (Abramowitz & Stegun 9.1.44-45) with the Bessel values and
  their ``a``-derivatives ``d^p/dz^p J_m = 2**-p sum_i (-1)**i C(p, i) J_{m-p+2i}``
  (A&S 9.1.31), so ``d/da`` is exact: it shifts the jet;
- a series in ``psi`` is held by its values at ``M`` equispaced phases: products are
  pointwise, derivatives and the harmonic balance act on the FFT.

The only approximation is the truncation in harmonics, ``|m| < M/2``: the driver
(:mod:`kbm.pointwise`) chooses ``M`` from the decay of the Bessel functions
(``|J_m(k a)| < tol`` beyond) and checks the tails of the results.  A jet of degree
``K`` loses one degree with every ``d/da``; order ``N`` needs ``K = N - 1``.

:class:`JetAlgebra` offers the recursion's part of
:class:`~kbm.algebra.base.FourierAlgebra` (with ``trig``, for the
:class:`~kbm.algebra.lazy_series.Builder`); there is no symbolic display.
"""

from __future__ import annotations

from math import comb, factorial

import numpy as np
import scipy.special

from .grid_fourier import GridCoef, PhaseGrid, Samples

__all__ = ["JetSeries", "JetCoef", "JetAlgebra", "bessel_jets"]


def _jet_mul(f: np.ndarray, g: np.ndarray) -> np.ndarray:
    """Truncated Cauchy product along axis 1 (the jet degree); other axes broadcast."""
    K = f.shape[1]
    out = np.zeros(np.broadcast_shapes(f.shape, g.shape))
    for k in range(K):
        for i in range(k + 1):
            out[:, k] += f[:, i] * g[:, k - i]
    return out


class JetCoef(GridCoef):
    """A coefficient ``c(a)`` as jets at the amplitudes: shape ``(Q, K + 1)``."""

    __slots__ = ()


class JetSeries(Samples):
    """Samples in ``psi`` of jets at the amplitudes: shape ``(Q, K + 1, M)``; None is zero."""

    __slots__ = ()

    def __mul__(self, other: "JetSeries") -> "JetSeries":
        if self.values is None or other.values is None:
            return JetSeries(None)
        return JetSeries(_jet_mul(self.values, other.values))

    def scale(self, c) -> "JetSeries":
        """``c f`` for a number or a :class:`JetCoef`."""
        if self.values is None:
            return self
        if isinstance(c, JetCoef):
            return JetSeries(_jet_mul(self.values, c.values[:, :, None]))
        return JetSeries(self.values * float(c))


def bessel_jets(m_max: int, z: np.ndarray, scale: float, K: int) -> np.ndarray:
    """Taylor coefficients in ``h`` of ``J_m(scale (a + h))`` at ``z = scale a``.

    Returns an array ``(Q, K + 1, m_max + 1)``: entry ``[q, p, m]`` is
    ``scale**p/p! J_m^(p)(z_q)``, with ``J_m^(p) = 2**-p sum_i (-1)**i C(p, i)
    J_{m-p+2i}`` (A&S 9.1.31; ``J_{-n} = (-1)**n J_n``).
    """
    orders = np.arange(-K, m_max + K + 1)
    J = scipy.special.jv(orders[None, :], np.asarray(z, dtype=float)[:, None])  # (Q, L)
    out = np.zeros((len(z), K + 1, m_max + 1))
    m = np.arange(m_max + 1)
    for p in range(K + 1):
        acc = np.zeros((len(z), m_max + 1))
        for i in range(p + 1):
            acc += (-1) ** i * comb(p, i) * J[:, m - p + 2 * i + K]
        out[:, p, :] = acc * (scale**p / (2.0**p * factorial(p)))
    return out


class JetAlgebra(PhaseGrid):
    """Jacobi-Anger series with jet coefficients at the amplitudes ``a`` (numbers).

    Parameters
    ----------
    omega0
        The linear frequency.
    a
        The amplitudes ``a_q > 0`` (1-D).
    K
        Jet degree (``order - 1`` for the recursion to ``order``).
    M
        Phases (even); harmonics ``|m| < M/2`` are kept.
    """

    def __init__(self, omega0: float, a: np.ndarray, K: int, M: int):
        self._phases(omega0, M)
        self.a = np.asarray(a, dtype=float)
        self.K = int(K)
        # the jet of 1/a at each amplitude: (-1)**p / a**(p + 1)
        p = np.arange(self.K + 1)
        self._inv_a = (-1.0) ** p[None, :] / self.a[:, None] ** (p[None, :] + 1)

    def _shape(self) -> tuple[int, int, int]:
        return (len(self.a), self.K + 1, self.M)

    def at_amplitudes(self, f) -> np.ndarray:
        """The values of a series or coefficient at the amplitudes (degree 0 of the jets)."""
        return f.values[:, 0]

    # -- the recursion's vocabulary ----------------------------------------------------
    def zero(self) -> JetSeries:
        return JetSeries(None)

    def const(self, value) -> JetSeries:
        out = np.zeros(self._shape())
        out[:, 0, :] = float(value)
        return JetSeries(out)

    def coef(self, value) -> JetCoef:
        out = np.zeros((len(self.a), self.K + 1))
        out[:, 0] = float(value)
        return JetCoef(out)

    def x0(self) -> JetSeries:
        out = np.zeros(self._shape())
        out[:, 0, :] = self.a[:, None] * np.cos(self.psi)[None, :]
        if self.K >= 1:
            out[:, 1, :] = np.cos(self.psi)[None, :]
        return JetSeries(out)

    def dpsi(self, f: JetSeries) -> JetSeries:
        if f.values is None:
            return f
        spec = np.fft.rfft(f.values, axis=2) * self._ik
        return JetSeries(np.fft.irfft(spec, n=self.M, axis=2))

    def da(self, f: JetSeries) -> JetSeries:
        """Exact: the jet ``sum_p c_p h**p`` becomes ``sum_p (p + 1) c_{p+1} h**p``."""
        if f.values is None:
            return f
        out = np.zeros_like(f.values)
        p = np.arange(1, self.K + 1, dtype=float)
        out[:, :-1, :] = f.values[:, 1:, :] * p[None, :, None]
        return JetSeries(out)

    def secular(self, R: JetSeries) -> tuple[JetCoef, JetCoef]:
        if R.values is None:
            z = np.zeros((len(self.a), self.K + 1))
            return JetCoef(z), JetCoef(z.copy())
        rc, rs = self.harmonic1(R)
        A = -rs / (2 * self.w0)
        B = _jet_mul(-rc / (2 * self.w0), self._inv_a)
        return JetCoef(A), JetCoef(B)

    def trig(self, kind: str, c) -> list[JetSeries]:
        """``[g(c x_0), g'(c x_0), g''(c x_0), g'''(c x_0)]`` for ``g`` = sin or cos, as
        Jacobi-Anger series with Bessel jets (harmonics below ``M/2``)."""
        c = float(c)
        H = self.M // 2 - 1
        jets = bessel_jets(H, c * self.a, c, self.K)  # (Q, K+1, H+1)
        m = np.arange(H + 1)
        phase = np.where(m % 4 < 2, 1.0, -1.0)  # (-1)**n for m = 2n or 2n + 1
        weight = 2.0 * phase
        weight[0] = 1.0
        odd = (m % 2 == 1)
        spec_s = np.zeros((len(self.a), self.K + 1, self.M // 2 + 1))
        spec_c = np.zeros_like(spec_s)
        spec_s[:, :, :H + 1] = np.where(odd, jets * weight, 0.0)
        spec_c[:, :, :H + 1] = np.where(~odd, jets * weight, 0.0)
        # a cosine series sum_m C_m cos(m psi) has rfft C_0 M and C_m M/2
        norm = np.full(self.M // 2 + 1, self.M / 2.0)
        norm[0] = self.M
        s = JetSeries(np.fft.irfft(spec_s * norm, n=self.M, axis=2))
        co = JetSeries(np.fft.irfft(spec_c * norm, n=self.M, axis=2))
        seq = [s, co, -s, -co]  # sin, sin', sin'', sin'''
        return seq if kind == "sin" else seq[1:] + seq[:1]
