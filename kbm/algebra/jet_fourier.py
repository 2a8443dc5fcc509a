"""Jacobi-Anger series with Taylor jets in the amplitude: ``sin``, ``cos`` of ``c a cos psi``.

For ``F`` with ``sin(k x)``, ``cos(k x)`` the evaluated recursion
(:func:`kbm.derive_values`, on the jets of :mod:`kbm.algebra.coupled_jets` with one mode)
needs ``g(c x_0)`` and its derivatives along ``x_0 = a cos psi`` at given amplitudes ``a_q``,
each as a truncated Taylor series (a *jet*) in ``h = a - a_q``:

- ``sin(z cos psi) = 2 sum_{n>=0} (-1)**n J_{2n+1}(z) cos((2n+1) psi)`` and
  ``cos(z cos psi) = J_0(z) + 2 sum_{n>=1} (-1)**n J_{2n}(z) cos(2n psi)``
  (Abramowitz & Stegun 9.1.44-45), ``z = c a``;
- the jets of the Bessel values are exact: ``d^p/dz^p J_m = 2**-p sum_i (-1)**i C(p, i)
  J_{m-p+2i}`` (A&S 9.1.31), so ``d/da`` of the series is exact too.

The only approximation is the truncation in harmonics, ``|m| < M/2`` (the series is summed,
not sampled: no aliasing); the driver chooses ``M`` from the decay of ``|J_m(c a)|``.
"""

from __future__ import annotations

from math import comb, factorial

import numpy as np
import scipy.special

__all__ = ["bessel_jets", "jacobi_anger_jets"]


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


def jacobi_anger_jets(kind: str, c: float, a: np.ndarray, K: int, M: int) -> list[np.ndarray]:
    """``[g(c x_0), g'(c x_0), g''(c x_0), g'''(c x_0)]`` for ``g = sin`` (``kind = "sin"``)
    or ``cos`` along ``x_0 = a cos psi``, at the amplitudes ``a`` (1-D) on ``M`` equispaced
    phases: four arrays ``(K + 1, len(a), M)``, row ``p`` the coefficient of ``h**p``
    (harmonics below ``M/2``)."""
    a = np.asarray(a, dtype=float)
    H = M // 2 - 1
    jets = bessel_jets(H, c * a, c, K)  # (Q, K+1, H+1)
    m = np.arange(H + 1)
    phase = np.where(m % 4 < 2, 1.0, -1.0)  # (-1)**n for m = 2n or 2n + 1
    weight = 2.0 * phase
    weight[0] = 1.0
    odd = (m % 2 == 1)
    spec_s = np.zeros((K + 1, len(a), M // 2 + 1))
    spec_c = np.zeros_like(spec_s)
    spec_s[:, :, :H + 1] = np.where(odd, jets * weight, 0.0).transpose(1, 0, 2)
    spec_c[:, :, :H + 1] = np.where(~odd, jets * weight, 0.0).transpose(1, 0, 2)
    # a cosine series sum_m C_m cos(m psi) has rfft C_0 M and C_m M/2
    norm = np.full(M // 2 + 1, M / 2.0)
    norm[0] = M
    s = np.fft.irfft(spec_s * norm, n=M, axis=-1)
    co = np.fft.irfft(spec_c * norm, n=M, axis=-1)
    seq = [s, co, -s, -co]  # sin, sin', sin'', sin'''
    return seq if kind == "sin" else seq[1:] + seq[:1]
