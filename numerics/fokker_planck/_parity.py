"""The stationary Kramers equation of a model symmetric under ``(x, v) -> (-x, -v)`` folded
onto ``x >= 0`` (what :func:`._stationary_orthonormal.orthonormal_stationary` solves when
:func:`reflection_symmetric` holds).

When the force is odd, ``g(-x) = -g(x)``, and the damping ``mu h(x, v) = sum_k a_k(x) v^k``
is odd under the reflection, ``a_k(-x) = (-1)^(k+1) a_k(x)`` (the SEDF's
``mu (beta x^2 - 1) v`` and van der Pol's ``mu (1 - x^2) v``), the Kramers operator commutes
with ``R P(x, v) = P(-x, -v)``, and so does its collocation on points symmetric about 0
(``x_{m-1-j} = -x_j``, the Chebyshev matrix ``D_{m-1-i, m-1-j} = -D_{ij}``).  Its
stationary density, the one eigenvector of the eigenvalue nearest zero, is then even under
``R``; since ``h_n(-xi) = (-1)^n h_n(xi)``, its coefficients have the parity of their order,
``c_n(-x) = (-1)^n c_n(x)`` (:mod:`._folded` folds the escape's matrix by the same
parity).

Folded: the unknowns are ``c_n`` at the points ``x_j >= 0`` (``j <= J``, ``x_J = 0`` for an
even number of intervals) and the equations those at the same points.  A dense term
``kron(H, X)`` (the derivative in ``x``) becomes two, ``kron(H E_even, X^+)`` and
``kron(H E_odd, X^-)`` with ``E_even``/``E_odd`` the projections on the even and odd
columns and ``X^p_{ij} = X_{ij} + p X_{i, m-1-j}`` for ``j < J``, ``X^p_{iJ} = X_{iJ}``; a
term diagonal in the points keeps its first ``J + 1`` values.  For odd orders the value at
``x = 0`` stays an unknown, with the equations at ``x = 0``: on even densities those
equations hold identically (``g(0) = 0``, the derivative of an even function vanishes
there), so the even density solves the folded system with those values zero, and
:func:`unfold` sets them to their exact 0.  On even densities the folded system is the
whole one's rows at ``x >= 0`` (tests/test_fokker_planck_parity.py, hypothesis), and
both give the same moments to rounding (SEDF 128 x 266: 1.4e-11 in the coefficients) at
an eighth of the factorisation's work (``(m/2)^3`` per order) and a quarter of its memory
(SEDF 128 x 266: 0.99 s to 0.24 s).  The Clenshaw-Curtis weights fold to
``w_j + w_{m-1-j}`` (``w_J`` once).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sps

__all__ = ["reflection_symmetric", "fold_terms", "fold_weights", "unfold"]


def reflection_symmetric(split, xs: np.ndarray, rtol: float = 1e-13) -> bool:
    """Whether ``x -> -x, v -> -v`` maps the model and the points ``xs`` (decreasing, an odd
    number of them) onto themselves: ``xs`` antisymmetric, ``g`` odd, each damping
    coefficient ``a_k`` of parity ``(-1)^(k+1)`` at the points (module docstring)."""
    from ._model import velocity_terms

    xs = np.asarray(xs, float)
    if xs.size % 2 == 0 or xs.size < 3:
        return False
    scale = float(np.max(np.abs(xs)))
    if np.max(np.abs(xs + xs[::-1])) > rtol * scale:
        return False
    g = split.numpy_functions()[0]
    pairs = [(np.asarray(g(xs), float), -1.0)]
    pairs += [(np.asarray(a(xs), float), (-1.0) ** (k + 1)) for k, a in velocity_terms(split)]
    for f, p in pairs:
        size = float(np.max(np.abs(f)))
        if size > 0 and np.max(np.abs(f[::-1] - p * f)) > rtol * size:
            return False
    return True


def fold_terms(terms, m: int) -> list:
    """The terms ``(H, X)`` of :func:`._orthonormal.orthonormal_terms` on ``m`` symmetric
    points folded onto the first ``m // 2 + 1`` (module docstring)."""
    half = m // 2 + 1
    mid = m // 2
    out = []
    for H, X in terms:
        H = sps.csr_matrix(H)
        X = np.asarray(X, float)
        if X.ndim == 1:
            out.append((H, X[:half].copy()))
            continue
        n = H.shape[1]
        par = np.where(np.arange(n) % 2 == 0, 1.0, 0.0)
        for p, sel in ((1.0, par), (-1.0, 1.0 - par)):
            Hp = sps.csr_matrix(H @ sps.diags(sel))
            Hp.eliminate_zeros()
            if Hp.nnz == 0:
                continue
            Xp = X[:half, :half].copy()
            Xp[:, :mid] += p * X[:half, ::-1][:, :mid]
            out.append((Hp, Xp))
    return out


def fold_weights(w: np.ndarray) -> np.ndarray:
    """Quadrature weights of an even function on the folded points: ``w_j + w_{m-1-j}``
    for ``j < J``, ``w_J`` at ``x = 0``."""
    w = np.asarray(w, float)
    mid = w.size // 2
    out = w[:mid + 1].copy()
    out[:mid] += w[::-1][:mid]
    return out


def unfold(c: np.ndarray, m: int) -> np.ndarray:
    """The coefficients ``c_n`` (orders x folded points) on all ``m`` points:
    ``c_n(-x) = (-1)^n c_n(x)``; the odd orders' value at ``x = 0`` is set to its exact 0."""
    c = np.asarray(c, float)
    n, half = c.shape
    mid = m // 2
    out = np.empty((n, m))
    out[:, :half] = c
    sign = np.where(np.arange(n) % 2 == 0, 1.0, -1.0)[:, None]
    out[:, half:] = sign * c[:, :mid][:, ::-1]
    out[1::2, mid] = 0.0
    return out
