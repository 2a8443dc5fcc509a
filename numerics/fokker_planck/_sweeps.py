"""The forward and backward sweeps of the escape matrix's block LU (:mod:`._fraction`),
compiled by numba: one solve with the factors of every Hermite order, no Python call per
order.

The factors of the order ``k >= 2`` are LAPACK's ``getrf`` output, transposed: ``lut[k]``
(``lut[k, j, i]`` the entry ``(i, j)``, the leading ``sizes[k]`` rows and columns) and
``piv[k]`` (0-based row interchanges): ``P L U`` with ``L`` unit lower triangular.  The
couplings ``(k, k - 1)`` and ``(k, k + 1)`` are ``sqrt(k)`` and ``sqrt(k + 1)`` times the
bases ``basis_t[1, p, 1]`` and ``basis_t[0, p, 1]`` (transposed too) of the row parity
``p = par[k]`` (their pinned rows zero).  Every inner loop runs down a stored row, as an
``axpy`` (column-oriented substitution), which the compiler vectorises without reordering
any sum of one entry.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["forward", "backward"]


@njit(cache=True)
def _lu_solve(lut, piv, s, b):
    """``b <- (P L U)^{-1} b`` on the leading ``s`` entries (LAPACK ``getrs``), the factors
    transposed."""
    for i in range(s):
        j = piv[i]
        if j != i:
            t = b[i]
            b[i] = b[j]
            b[j] = t
    for j in range(s):
        bj = b[j]
        col = lut[j]
        for i in range(j + 1, s):
            b[i] -= col[i] * bj
    for j in range(s - 1, -1, -1):
        col = lut[j]
        bj = b[j] / col[j]
        b[j] = bj
        for i in range(j):
            b[i] -= col[i] * bj


@njit(cache=True)
def _matvec(bt, rows, cols, y, out):
    """``out[:rows] = B y[:cols]``, ``bt`` the transpose of ``B``."""
    for i in range(rows):
        out[i] = 0.0
    for j in range(cols):
        yj = y[j]
        col = bt[j]
        for i in range(rows):
            out[i] += col[i] * yj


@njit(cache=True)
def forward(lut, piv, basis_t, sizes, par, y, n):
    """``y[k] <- T_k^{-1} (y[k] - L_k y[k - 1])`` for ``k = 2 .. n - 1`` (``y[1]``: the
    first block's solution for the order 1)."""
    mm = y.shape[1]
    r = np.empty(mm)
    for k in range(2, n):
        s = sizes[k]
        _matvec(basis_t[1, par[k], 1], s, sizes[k - 1], y[k - 1], r)
        c = math.sqrt(k)
        for i in range(s):
            r[i] = y[k, i] - c * r[i]
        _lu_solve(lut[k], piv[k], s, r)
        for i in range(s):
            y[k, i] = r[i]


@njit(cache=True)
def backward(lut, piv, basis_t, sizes, par, y, n):
    """``y[k] <- y[k] - T_k^{-1} U_k y[k + 1]`` for ``k = n - 2 .. 2``."""
    mm = y.shape[1]
    w = np.empty(mm)
    for k in range(n - 2, 1, -1):
        s = sizes[k]
        _matvec(basis_t[0, par[k], 1], s, sizes[k + 1], y[k + 1], w)
        c = math.sqrt(k + 1)
        for i in range(s):
            w[i] = c * w[i]
        _lu_solve(lut[k], piv[k], s, w)
        for i in range(s):
            y[k, i] -= w[i]
