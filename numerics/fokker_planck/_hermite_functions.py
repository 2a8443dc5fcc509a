"""The orthonormal Hermite functions ``h_n(xi) = H_n(xi) exp(-xi^2/2)/(2^n n! sqrt(pi))^(1/2)``
of the stationary Kramers solve of a nonlinear damping (:mod:`._stationary_orthonormal`):
their values (:func:`hermite_function_values`), their integrals over the line
(:func:`hermite_integrals`) and over ``[-U, U]`` (:func:`orthonormal_band_masses`).

The integrals (generating function ``sum H_n t^n/n! = exp(2 xi t - t^2)``, whose integral
against ``exp(-xi^2/2)`` is ``sqrt(2 pi) exp(t^2)``):

* ``m_n = int h_n dxi = 0`` for odd ``n``, ``m_{2k} = sqrt(2) pi^(1/4) sqrt((2k)!)/(2^k k!)``
  (``m_{2k+2} = m_{2k} sqrt((2k+1)/(2k+2))``), so the marginal of ``x`` is
  ``sum_n m_n c_n(x)``;
* ``int xi^2 h_n dxi = (X^2 m)_n`` with ``X`` the tridiagonal multiplication by ``xi``, so
  ``<v^2> = s^2 int sum_n (X^2 m)_n c_n dx``;
* ``B_n(U) = int_{-U}^{U} h_n dxi``: ``B_0 = pi^(-1/4) sqrt(2 pi) erf(U/sqrt 2)``, odd
  ``B_n = 0``, and from ``h_n' = sqrt(n/2) h_{n-1} - sqrt((n+1)/2) h_{n+1}`` integrated over
  ``[-U, U]`` (``h_n`` odd for odd ``n``):
  ``B_{n+1} = sqrt(n/(n+1)) B_{n-1} - 2 sqrt(2/(n+1)) h_n(U)`` for odd ``n``
  (the factor ``sqrt(n/(n+1)) < 1``: stable upward).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["hermite_function_values", "hermite_integrals", "orthonormal_band_masses"]


def hermite_function_values(n: int, xi) -> np.ndarray:
    """``h_k(xi)`` for ``k < n`` (rows), by the recurrence
    ``h_{k+1} = sqrt(2/(k+1)) xi h_k - sqrt(k/(k+1)) h_{k-1}`` run on
    ``h_k exp(xi^2/2)`` with the scale carried as an exponent (no underflow at large
    ``|xi|``)."""
    xi = np.asarray(xi, float)
    out = np.empty((n,) + xi.shape)
    logscale = -0.5 * xi * xi  # log of the factor still to apply
    factor = np.exp(logscale)  # recomputed only when a rescaling changes it (the same bits)
    prev = np.zeros(xi.shape)
    cur = np.full(xi.shape, math.pi ** -0.25)
    mag = np.empty(xi.shape)
    for k in range(n):
        out[k] = cur * factor
        nxt = math.sqrt(2.0 / (k + 1)) * xi * cur - math.sqrt(k / (k + 1.0)) * prev
        if np.abs(nxt, out=mag).max(initial=0.0) > 1e150:
            big = mag > 1e150
            nxt = np.where(big, nxt * 1e-150, nxt)
            cur = np.where(big, cur * 1e-150, cur)
            logscale = np.where(big, logscale + 150 * math.log(10.0), logscale)
            factor = np.exp(logscale)
        prev, cur = cur, nxt
    return out


def hermite_integrals(n: int) -> tuple[np.ndarray, np.ndarray]:
    """``(m, q)``: ``m_k = int h_k dxi`` and ``q_k = int xi^2 h_k dxi`` for ``k < n``
    (module docstring)."""
    from ._orthonormal import orthonormal_matrices

    big = n + 2
    m = np.zeros(big)
    m[0] = math.sqrt(2.0) * math.pi ** 0.25
    for k in range(2, big, 2):
        m[k] = m[k - 2] * math.sqrt((k - 1.0) / k)
    X, _ = orthonormal_matrices(big)
    q = X @ (X @ m)
    return m[:n], q[:n]


def orthonormal_band_masses(n: int, U) -> np.ndarray:
    """``B_k(U) = int_{-U}^{U} h_k dxi`` for ``k < n`` (rows) at each ``U >= 0``."""
    from scipy.special import erf

    U = np.asarray(U, float)
    h = hermite_function_values(max(n - 1, 1), U)
    out = np.zeros((n,) + U.shape)
    out[0] = math.pi ** -0.25 * math.sqrt(2 * math.pi) * erf(U / math.sqrt(2))
    for k in range(1, n - 1, 2):
        out[k + 1] = math.sqrt(k / (k + 1.0)) * out[k - 1] - 2 * math.sqrt(2.0 / (k + 1)) * h[k]
    return out
