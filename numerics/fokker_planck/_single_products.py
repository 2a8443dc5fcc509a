"""The product of a single-precision matrix with a double-precision vector, accumulated in
double precision (:func:`single_matvec`): the sweeps of the single-precision order-by-order
LU (:mod:`._pentadiagonal`, ``single``), whose factors are kept in single precision.

Each entry ``sum_j a_ij x_j`` multiplies the single-precision ``a_ij`` (exact in double)
by the double ``x_j`` and sums in double, so the product is that of the matrix converted
to double to the rounding of a double sum (the order of the sum is the compiler's: its
vector lanes); the factors take half the memory and the memory-bound sweep reads half the
bytes.  Single-precision vectors too (BLAS ``sgemv``) would round every sweep to single
precision, which made the preconditioned GMRES of :mod:`._bordered` take 160-260
iterations at 258 x 593 (the SEDF at rest, mu = 0.01) instead of 6-7.

Measured (one thread, 258 matrices of 521 x 521, AMD EPYC, load about 4 on 2 cores):
0.060-0.067 s for the 258 products against 0.098-0.109 s with the matrices in double
(numpy's ``dgemv``), about ``sgemv``'s 0.067 s.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["single_matvec"]


@njit(cache=True, fastmath={"reassoc", "contract"})
def _matvec(a, x, out):
    """``out = a x``: each row's sum in double, in the compiler's lanes (``reassoc``)."""
    rows, cols = a.shape
    for i in range(rows):
        row = a[i]
        s = 0.0
        for j in range(cols):
            s += np.float64(row[j]) * x[j]
        out[i] = s


def single_matvec(a: np.ndarray, x: np.ndarray) -> np.ndarray:
    """``a @ x`` for a single-precision ``a`` (``m x n``) and a double-precision ``x``,
    summed in double precision (module docstring); any other ``a`` by numpy's product.

    Parameters
    ----------
    a : numpy.ndarray
        The matrix, ``float32`` for this kernel.
    x : numpy.ndarray
        The vector of ``n`` entries.

    Returns
    -------
    numpy.ndarray
        ``m`` double-precision entries.
    """
    if a.dtype != np.float32:
        return a @ x
    out = np.empty(a.shape[0])
    _matvec(np.ascontiguousarray(a), np.ascontiguousarray(x, dtype=np.float64), out)
    return out
