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
    transposed.  Four columns per pass over ``b`` (each entry still loses the columns'
    terms one by one, in the order of the column loop: the same roundings)."""
    for i in range(s):
        j = piv[i]
        if j != i:
            t = b[i]
            b[i] = b[j]
            b[j] = t
    j = 0
    while j + 4 <= s:  # L: columns j .. j + 3, their triangle first
        c0, c1, c2, c3 = lut[j], lut[j + 1], lut[j + 2], lut[j + 3]
        b0 = b[j]
        b1 = b[j + 1] - c0[j + 1] * b0
        b2 = b[j + 2] - c0[j + 2] * b0 - c1[j + 2] * b1
        b3 = b[j + 3] - c0[j + 3] * b0 - c1[j + 3] * b1 - c2[j + 3] * b2
        b[j + 1], b[j + 2], b[j + 3] = b1, b2, b3
        for i in range(j + 4, s):
            b[i] = b[i] - c0[i] * b0 - c1[i] * b1 - c2[i] * b2 - c3[i] * b3
        j += 4
    for j in range(j, s):
        bj = b[j]
        col = lut[j]
        for i in range(j + 1, s):
            b[i] -= col[i] * bj
    j = s - 1
    while j >= 3:  # U: columns j .. j - 3, their triangle first
        c0, c1, c2, c3 = lut[j], lut[j - 1], lut[j - 2], lut[j - 3]
        b0 = b[j] / c0[j]
        b1 = (b[j - 1] - c0[j - 1] * b0) / c1[j - 1]
        b2 = (b[j - 2] - c0[j - 2] * b0 - c1[j - 2] * b1) / c2[j - 2]
        b3 = (b[j - 3] - c0[j - 3] * b0 - c1[j - 3] * b1 - c2[j - 3] * b2) / c3[j - 3]
        b[j], b[j - 1], b[j - 2], b[j - 3] = b0, b1, b2, b3
        for i in range(j - 3):
            b[i] = b[i] - c0[i] * b0 - c1[i] * b1 - c2[i] * b2 - c3[i] * b3
        j -= 4
    for j in range(j, -1, -1):
        col = lut[j]
        bj = b[j] / col[j]
        b[j] = bj
        for i in range(j):
            b[i] -= col[i] * bj


@njit(cache=True)
def _matvec(bt, rows, cols, y, out):
    """``out[:rows] = B y[:cols]``, ``bt`` the transpose of ``B``; four columns per pass
    (the terms added in the order of the column loop: the same roundings)."""
    for i in range(rows):
        out[i] = 0.0
    j = 0
    while j + 4 <= cols:
        c0, c1, c2, c3 = bt[j], bt[j + 1], bt[j + 2], bt[j + 3]
        y0, y1, y2, y3 = y[j], y[j + 1], y[j + 2], y[j + 3]
        for i in range(rows):
            out[i] = out[i] + c0[i] * y0 + c1[i] * y1 + c2[i] * y2 + c3[i] * y3
        j += 4
    for j in range(j, cols):
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
