"""The fold of the Kramers operator onto ``x >= 0`` for a model symmetric under
``(x, v) -> (-x, -v)``: the symmetry tests and the restriction/extension maps of every
solver that folds (the stationary solve, :mod:`._stationary_orthonormal`; the escape,
:mod:`._fraction`, :mod:`._folded`, :mod:`._rungs`).

When the force is odd, ``g(-x) = -g(x)``, and the damping ``mu h(x, v) = sum_k a_k(x) v^k``
is odd under the reflection, ``a_k(-x) = (-1)^(k+1) a_k(x)`` (linear damping, the SEDF's
``mu (beta x^2 - 1) v``, van der Pol's ``mu (1 - x^2) v``), the Kramers operator (with an
escape sink: an even one) commutes with ``R P(x, v) = P(-x, -v)``, and so does its
collocation on points symmetric about 0 (``x_{m-1-j} = -x_j``, the Chebyshev matrix
``D_{m-1-i, m-1-j} = -D_{ij}``).  The stationary density and the slowest escape mode are
then even under ``R``; since ``h_n(-xi) = (-1)^n h_n(xi)``, their coefficients have the
parity of their order, ``c_n(-x) = (-1)^n c_n(x)``.  :func:`parity_maps` gives per parity
the points kept ``idx`` (``x >= 0``) and the extension ``F`` from them to all points; the
folded operator is the restriction ``R A F``: a dense position matrix ``X`` from the
orders of parity ``q`` to those of ``p`` becomes ``X[idx_p] @ F_q``
(``X_{ij} + q X_{i, m-1-j}`` for ``j < J``, ``X_{iJ}`` at ``x_J = 0``), a diagonal keeps
its values at ``idx_p``.

**The odd orders' value at x = 0**, exactly 0 on the even mode, is the one difference
between the two kinds of solver (``keep_zero``).  The escape drops it (one point fewer
than the even orders): its elimination (:class:`._fraction.EscapeFraction`) takes a size
per order, and its orthonormal blocks (:class:`._folded.FoldedTermBlocks`) pad the odd
orders by a decoupled row outside the mass matrix, which Arnoldi never sees.  The
stationary solve (:func:`fold_terms`) keeps it as an unknown, with the equations at
``x = 0``: its LUs (:class:`._pentadiagonal.HermitePentadiagonalLU`,
:class:`._blocks.TermBlocks`) take one number of points for every order, and its inverse
iteration has no mass matrix to hide a padding row.  Those equations hold identically on
even densities (``g(0) = 0``, an even function's derivative vanishes there), so the even
density solves the folded system with the values zero, and :func:`unfold` (the extension
that drops them) sets them to their exact 0.  On even densities the folded system is the
whole one's rows at ``x >= 0`` (tests/test_fokker_planck_parity.py, hypothesis), with the
same moments to rounding (SEDF 128 x 266: 1.4e-11 in the coefficients) at an eighth of the
factorisation's work and a quarter of its memory (SEDF 128 x 266: 0.99 s to 0.24 s).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sps

__all__ = ["parity_maps", "reflection_symmetric", "symmetric", "fold_terms", "fold_weights",
           "unfold"]


def parity_maps(m: int, fold: bool, keep_zero: bool = False) -> list:
    """``[(idx, F)]`` for even and odd Hermite orders: the points kept and the extension
    ``F`` (``m x len(idx)``) from them to all ``m`` points of a symmetric grid (decreasing,
    ``x_{m-1-i} = -x_i``), even for even orders and odd for odd ones; without ``fold``
    every point is kept and ``F`` is ``None`` (the identity).  ``keep_zero``: the odd
    orders keep the point ``x = 0`` too (its column of ``F`` is the unit vector there; the
    module docstring)."""
    if not fold:
        return [(np.arange(m), None), (np.arange(m), None)]
    nc = m - 1
    h = nc // 2
    out = []
    for sign in (1.0, -1.0):
        even = sign > 0 or keep_zero
        idx = np.arange(h + 1 if (even and nc % 2 == 0) else (nc + 1) // 2)
        F = np.zeros((m, idx.size))
        F[idx, np.arange(idx.size)] = 1.0
        mirror = nc - idx
        F[mirror, np.arange(idx.size)] += sign * (mirror != idx)
        out.append((idx, F))
    return out


def _has_parity(f, p: float, rtol: float = 1e-13) -> bool:
    """Whether ``f(-x) = p f(x)`` at symmetric points to ``rtol`` of ``max |f|``."""
    f = np.asarray(f, float)
    size = float(np.max(np.abs(f)))
    return not size > 0 or float(np.max(np.abs(f[::-1] - p * f))) <= rtol * size


def symmetric(g: np.ndarray, wells, xs: np.ndarray | None = None) -> bool:
    """Whether the force ``g`` at a grid's points is odd and the next wells' bottoms (the
    escape sink's centres) are symmetric, and, given ``xs`` (decreasing), the points are
    exactly antisymmetric: the escape's fold applies (linear damping)."""
    return (abs(wells[0] + wells[1]) <= 1e-12 * wells[1]
            and (xs is None or np.array_equal(xs, -xs[::-1])) and _has_parity(g, -1.0))


def reflection_symmetric(split, xs: np.ndarray, rtol: float = 1e-13) -> bool:
    """Whether ``x -> -x, v -> -v`` maps the model and the points ``xs`` (decreasing, an odd
    number of them) onto themselves: ``xs`` antisymmetric, ``g`` odd, each damping
    coefficient ``a_k`` of parity ``(-1)^(k+1)`` at the points (module docstring)."""
    from ._model import velocity_terms

    xs = np.asarray(xs, float)
    if xs.size % 2 == 0 or xs.size < 3:
        return False
    pairs = [(xs, -1.0), (split.numpy_functions()[0](xs), -1.0)]
    pairs += [(a(xs), (-1.0) ** (k + 1)) for k, a in velocity_terms(split)]
    return all(_has_parity(f, p, rtol) for f, p in pairs)


def _fold_columns(X: np.ndarray, idx: np.ndarray, sign: float) -> np.ndarray:
    """``X @ F`` along the last axis, ``F`` the extension of :func:`parity_maps` from the
    points ``idx`` with the parity ``sign`` (no dense ``F`` formed)."""
    mirror = X.shape[-1] - 1 - idx
    off = mirror != idx
    out = X[..., idx].copy()
    out[..., off] += sign * X[..., mirror[off]]
    return out


def fold_terms(terms, m: int) -> list:
    """The terms ``(H, X)`` of :func:`._orthonormal.orthonormal_terms` on ``m`` symmetric
    points folded onto the first ``m // 2 + 1`` (:func:`parity_maps` with ``keep_zero``):
    a dense ``kron(H, X)`` becomes ``kron(H E_even, X[idx] F_even)`` and
    ``kron(H E_odd, X[idx] F_odd)``, ``E_even``/``E_odd`` the projections on the even and
    odd columns; a diagonal keeps its values at ``idx``."""
    idx = parity_maps(m, True, keep_zero=True)[0][0]
    out = []
    for H, X in terms:
        H = sps.csr_matrix(H)
        X = np.asarray(X, float)
        if X.ndim == 1:
            out.append((H, X[idx].copy()))
            continue
        n = H.shape[1]
        par = np.where(np.arange(n) % 2 == 0, 1.0, 0.0)
        for sign, sel in ((1.0, par), (-1.0, 1.0 - par)):
            Hp = sps.csr_matrix(H @ sps.diags(sel))
            Hp.eliminate_zeros()
            if Hp.nnz == 0:
                continue
            out.append((Hp, _fold_columns(X[idx], idx, sign)))
    return out


def fold_weights(w: np.ndarray) -> np.ndarray:
    """Quadrature weights of an even function on the folded points, ``F_even^T w``:
    ``w_j + w_{m-1-j}`` for ``j < J``, ``w_J`` at ``x = 0``."""
    w = np.asarray(w, float)
    return _fold_columns(w, parity_maps(w.size, True)[0][0], 1.0)


def unfold(c: np.ndarray, m: int) -> np.ndarray:
    """The coefficients ``c_n`` (orders x folded points, :func:`fold_terms`) on all ``m``
    points: the extension ``F`` of :func:`parity_maps`, ``c_n(-x) = (-1)^n c_n(x)``; the
    odd orders' value at ``x = 0`` (carried by the folded solve) is dropped, i.e. set to
    its exact 0."""
    c = np.asarray(c, float)
    out = np.zeros((c.shape[0], m))
    for p, ((idx, _), sign) in enumerate(zip(parity_maps(m, True), (1.0, -1.0))):
        mirror = m - 1 - idx
        off = mirror != idx
        out[p::2, idx] = c[p::2, :idx.size]
        out[p::2, mirror[off]] = sign * c[p::2, :idx.size][:, off]
    return out
