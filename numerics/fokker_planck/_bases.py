"""The two bases of the Kramers equation's discretisation: Hermite functions of the velocity
and Chebyshev points in the position.

Velocity: ``phi_n(u) = He_n(u) w(u)/sqrt(n!)``, ``w = exp(-u^2/2)/sqrt(2 pi)``, ``u = v/sigma``
(Risken, *The Fokker-Planck Equation*, 2nd ed., sec. 10.3, eqs. 10.38-10.45).  With
``P = sum_n c_n(x) phi_n(u)/sigma``, ``c_0`` is the marginal density of ``x`` and
``sigma c_1`` the probability current.  The recurrences ``u He_n = He_{n+1} + n He_{n-1}``
and ``(He_n w)' = -He_{n+1} w`` give ``u phi_n = sqrt(n+1) phi_{n+1} + sqrt(n) phi_{n-1}``
and ``d phi_n/du = -sqrt(n+1) phi_{n+1}``.

Position: Chebyshev-Gauss-Lobatto points, the differentiation matrix and the Clenshaw-Curtis
weights (L. N. Trefethen, *Spectral Methods in MATLAB*, SIAM 2000, programs 6 and 30).
"""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sps

__all__ = ["hermite_matrices", "cheb", "cheb_mapped", "cheb_centred", "clenshaw_curtis",
           "hermite_functions", "band_masses"]


def hermite_matrices(n: int, extra: int):
    """``(U, Du)``: multiplication by ``u`` and ``d/du`` on ``phi_0 .. phi_{n+extra-1}``
    (sparse, acting on coefficient vectors)."""
    m = n + extra
    k = np.arange(m - 1)
    up = np.sqrt(k + 1.0)
    U = sps.diags([up, up], [-1, 1], shape=(m, m), format="csr")
    Du = sps.diags([-up], [-1], shape=(m, m), format="csr")
    return U, Du


def cheb(n: int, L: float):
    """``(x, D)``: ``n + 1`` Chebyshev-Gauss-Lobatto points on ``[-L, L]`` (decreasing) and
    the differentiation matrix."""
    k = np.arange(n + 1)
    t = np.cos(np.pi * k / n)
    c = np.where((k == 0) | (k == n), 2.0, 1.0) * (-1.0) ** k
    dt = t[:, None] - t[None, :]
    D = np.outer(c, 1 / c) / (dt + np.eye(n + 1))
    D -= np.diag(D.sum(axis=1))
    return L * t, D / L


def cheb_mapped(n: int, L: float, alpha: float):
    """``(x, D)``: the points of :func:`cheb` moved by the map ``x = L arcsin(alpha t) /
    arcsin(alpha)`` of Kosloff and Tal-Ezer (J. Comput. Phys. 104 (1993) 457), and the
    differentiation matrix ``diag(dt/dx) D_t``.  ``alpha -> 1`` spreads the points evenly
    (the Chebyshev points crowd the ends, where the escape's density is nil); ``alpha = 0``
    is :func:`cheb`.  The map is analytic inside the ellipse through ``t = +-1/alpha``."""
    t, Dt = cheb(n, 1.0)
    if alpha == 0:
        return L * t, Dt / L
    s = math.asin(alpha)
    return L * np.arcsin(alpha * t) / s, (s / (L * alpha) * np.sqrt(1 - (alpha * t) ** 2))[:, None] * Dt


def cheb_centred(n: int, L: float, alpha: float, centres, widths, weight=1.0):
    """``(x, D)``: the points of :func:`cheb_mapped` moved again toward ``centres``: with
    ``s`` the Kosloff-Tal-Ezer coordinate (in ``[-1, 1]``), ``x`` solves ``phi(x) = s`` for

        phi(x) = -1 + 2 (psi(x) - psi(-L)) / (psi(L) - psi(-L)),
        psi(x) = x/L + sum_i weight_i arctan((x - c_i)/w_i),

    a map of Bayliss and Turkel's kind (J. Comput. Phys. 101 (1992) 349) that spends about
    ``pi weight_i/(1 + pi sum weight)`` of the points within a few ``w_i`` of ``c_i``
    (``weight`` one number or one per centre); the
    differentiation matrix is ``diag(dt/dx) D_t``.  ``psi`` is analytic but at
    ``c_i +- i w_i``, so the convergence stays spectral.  The escape's layer is sharpest at
    the saddles (:mod:`.escape`), where these points crowd."""
    t, Dt = cheb(n, 1.0)
    c = np.asarray(centres, float)
    w = np.asarray(widths, float)
    q = np.broadcast_to(np.asarray(weight, float), c.shape)

    def psi(x):
        return x / L + (q * np.arctan((x[..., None] - c) / w)).sum(axis=-1)

    def dpsi(x):
        return 1 / L + (q * w / (w * w + (x[..., None] - c) ** 2)).sum(axis=-1)

    if alpha == 0:
        s, ds_dt = t, np.ones_like(t)
    else:
        a = math.asin(alpha)
        s, ds_dt = np.arcsin(alpha * t) / a, alpha / (a * np.sqrt(1 - (alpha * t) ** 2))
    lo, hi = psi(np.array([-L, L]))
    target = lo + (s + 1) * (hi - lo) / 2  # psi(x) = target, psi increasing
    a_, b_ = np.full_like(t, -L), np.full_like(t, L)
    for _ in range(64):  # bisection: to the last bit of [-L, L] (deterministic)
        mid = 0.5 * (a_ + b_)
        up = psi(mid) < target
        a_, b_ = np.where(up, mid, a_), np.where(up, b_, mid)
    x = 0.5 * (a_ + b_)
    if sorted(zip(c, w, q)) == sorted(zip(-c, w, q)):  # psi odd: x exactly antisymmetric
        x = 0.5 * (x - x[::-1])
    x[0], x[-1] = L, -L
    dt_dx = dpsi(x) * 2 / (hi - lo) / ds_dt
    return x, dt_dx[:, None] * Dt


def clenshaw_curtis(n: int, L: float) -> np.ndarray:
    """Clenshaw-Curtis weights on the ``n + 1`` points of :func:`cheb`."""
    theta = np.pi * np.arange(n + 1) / n
    w = np.zeros(n + 1)
    v = np.ones(n - 1)
    inner = theta[1:-1]
    if n % 2 == 0:
        w[0] = w[n] = 1.0 / (n * n - 1)
        for k in range(1, n // 2):
            v -= 2 * np.cos(2 * k * inner) / (4 * k * k - 1)
        v -= np.cos(n * inner) / (n * n - 1)
    else:
        w[0] = w[n] = 1.0 / (n * n)
        for k in range(1, (n - 1) // 2 + 1):
            v -= 2 * np.cos(2 * k * inner) / (4 * k * k - 1)
    w[1:-1] = 2 * v / n
    return w * L


def hermite_functions(n: int, u) -> np.ndarray:
    """``He_k(u)/sqrt(k!)`` for ``k < n`` at ``u`` (rows ``k``), by the stable recurrence."""
    u = np.asarray(u, float)
    out = np.zeros((n,) + u.shape)
    out[0] = 1.0
    if n > 1:
        out[1] = u
    for k in range(1, n - 1):
        out[k + 1] = (u * out[k] - math.sqrt(k) * out[k - 1]) / math.sqrt(k + 1)
    return out


def band_masses(n: int, U) -> np.ndarray:
    """``int_{-U}^{U} phi_k(u) du`` for ``k < n`` (rows) at each ``U >= 0``: ``erf(U/sqrt 2)``
    for ``k = 0``, ``-2 He_{k-1}(U) w(U)/sqrt(k!)`` for even ``k``, ``0`` for odd ``k``."""
    from scipy.special import erf

    U = np.asarray(U, float)
    h = hermite_functions(max(n - 1, 1), U)
    w = np.exp(-0.5 * U * U) / math.sqrt(2 * math.pi)
    out = np.zeros((n,) + U.shape)
    out[0] = erf(U / math.sqrt(2))
    for k in range(2, n, 2):
        out[k] = -2 * h[k - 1] * w / math.sqrt(k)
    return out
