"""The LU of the stationary Kramers matrix in orthonormal Hermite functions, order by order
(:class:`HermitePentadiagonalLU`, what :mod:`._stationary_orthonormal` factorises).

For a damping linear in the velocity times a function of the position (the SEDF's
``mu (beta x^2 - 1) x'``, van der Pol's ``mu (1 - x^2) x'``) the Galerkin operator of
:func:`._orthonormal.orthonormal_terms` couples the Hermite order ``n`` to ``n +- 1``
through ``-s xi d/dx`` (the dense Chebyshev differentiation matrix) and ``g(x) d/dxi``,
and to ``n`` and ``n +- 2`` only through the friction ``a(x)`` and the diffusion, which
are diagonal in the points.  :class:`._blocks.BlockTridiagonalLU` groups two orders into
dense blocks of ``2 m`` rows and spends about ``19 m^3`` operations per order (an LU of
``2 m``, a solve with ``2 m`` right-hand sides and a product of ``2 m`` matrices per
pair).

Eliminating one order at a time from the top, the order ``k`` meets only ``k - 1`` (a
dense coupling) and ``k - 2``, whose coupling to ``k`` is still the original diagonal:
the elimination of ``k + 1`` changes the blocks of the orders ``k`` and ``k - 1`` only
(block Gaussian elimination without pivoting across orders, as
:class:`._blocks.BlockTridiagonalLU`; Golub and Van Loan, *Matrix Computations*, 4th ed.,
sec. 4.5).  Per order: the inverse of the Schur complement ``S`` (LAPACK getrf/getri),
``S^-1 A(k, k-1)`` and the two products of the update
``A(k-1, .) -= A(k-1, k) S^-1 [A(k, k-1), A(k, k-2)]`` (``S^-1 A(k, k-2)`` only scales
the columns of ``S^-1``: ``A(k, k-2)`` is diagonal), about ``8 m^3`` operations, and
``3 m^2`` numbers kept (the block-tridiagonal form keeps ``6 m^2``).

Why the inverse and not the solves of an LU, though the LU needs fewer operations
(measured with one BLAS thread, OpenBLAS 0.3.31, ``m = 521``): the column scaling needs
``A(k-1, k) S^-1`` whole, so the LU route is two solves with ``m`` right-hand sides and
one product, and the triangular solves run at half the rate of a product (getrs 12-16 ms,
getrf 3.4 ms, a product 4.4 ms, the inverse 14 ms): about 34 ms per order against 27 ms.
Of one solve at 258 functions x 1041 points (SEDF at rest, mu = 0.01, D = 0.005) the
inverses take 40 %, the three products 41 %, the element-wise updates 8 % (written in
place) and the sweeps of inverse iteration 10 % (memory-bound: four blocks read per
order and sweep).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sps
from scipy.linalg import get_lapack_funcs, lu_factor, lu_solve

from ._single_products import single_matvec

__all__ = ["HermitePentadiagonalLU", "pentadiagonal_applies"]


def _diagonals(terms, n: int):
    """For each term ``(H, X)``: the diagonals ``H.diagonal(d)``, ``d = -2 .. 2``, padded to
    ``n`` (entry ``i`` the coupling of the row ``i``, ``i + d``)."""
    out = []
    for H, X in terms:
        H = sps.csr_matrix(H)
        diags = {}
        for d in range(-2, 3):
            v = np.zeros(n)
            dv = H.diagonal(d)
            if d >= 0:
                v[:dv.size] = dv
            else:
                v[-d:-d + dv.size] = dv
            diags[d] = v
        out.append((diags, np.asarray(X, float)))
    return out


def _inverse(a: np.ndarray) -> np.ndarray:
    """``a^-1`` by LAPACK's ``getrf`` and ``getri`` (the same bits as
    :func:`scipy.linalg.inv`, which calls them too, without its structure test and
    condition estimate: an ill-conditioned complement, vdp at mu = 1e-6, D = 1e-6 with
    rcond ~ 1e-26, is judged by the solve's refinements, ``hermite_change`` and
    ``chebyshev_change``, not by a warning per order; measured 20-25 % less time at
    ``m = 521`` in single and double precision), C-contiguous for the sweeps' products.

    Raises
    ------
    numpy.linalg.LinAlgError
        When ``a`` is singular (a zero pivot)."""
    getrf, getri, lwork = get_lapack_funcs(("getrf", "getri", "getri_lwork"), (a,))
    lu, piv, info = getrf(a, overwrite_a=True)
    if info == 0:
        work = int(np.real(lwork(a.shape[0])[0]))
        out, info = getri(lu, piv, lwork=max(work, a.shape[0]), overwrite_lu=True)
    if info != 0:
        raise np.linalg.LinAlgError("a singular Schur complement in the order-by-order LU")
    return np.ascontiguousarray(out)


def pentadiagonal_applies(terms) -> bool:
    """Whether the terms couple Hermite orders at most two apart, the couplings at distance
    0 and 2 diagonal in the points (one-dimensional ``X``)."""
    for H, X in terms:
        coo = sps.coo_matrix(H)
        dist = np.abs(coo.row - coo.col)[coo.data != 0]
        if dist.size and int(dist.max()) > 2:
            return False
        if np.ndim(X) == 2 and np.any(dist % 2 == 0):
            return False
    return True


class HermitePentadiagonalLU:
    """The order-by-order LU factors of ``sum_j kron(H_j, X_j)`` (module docstring), with
    the rows ``pinned`` (positions within every order) replaced by identity rows.

    Parameters
    ----------
    terms : list of (scipy.sparse matrix, numpy.ndarray)
        As :func:`._orthonormal.orthonormal_terms`; :func:`pentadiagonal_applies` must hold.
    m : int
        Chebyshev points.
    pinned : sequence of int
    single : bool
        Eliminate in single precision (the inverses and products at about twice the rate)
        and keep the factors in single precision (half the memory, ``12 N m^2`` bytes); the
        sweeps multiply them with double-precision vectors, summed in double
        (:func:`._single_products.single_matvec`): then :meth:`solve` is a preconditioner,
        within about ``1e-3`` relative at the SEDF's largest grids, for :mod:`._bordered`,
        not a solve.

    Raises
    ------
    numpy.linalg.LinAlgError
        When an order's Schur complement is singular (no pivoting across orders).
    """

    def __init__(self, terms, m: int, pinned=(), single: bool = False):
        n = sps.csr_matrix(terms[0][0]).shape[0]
        self.m, self.n = m, n
        self._dtype = np.float32 if single else np.float64
        diags = _diagonals(terms, n)
        pinned = np.asarray(pinned, int)

        self._terms = [(sps.csr_matrix(H), X) for (H, _), (_, X) in zip(terms, diags)]
        if single:  # the dense blocks built in single precision (matvec keeps the doubles)
            diags = [(dg, X.astype(np.float32) if X.ndim == 2 else X) for dg, X in diags]
        self._diags, self._pinned = diags, pinned
        coupling = self._coupling
        self._inv, self._x1, self._p, self._q2 = [None] * n, [None] * n, [None] * n, [None] * n
        self._d2 = [None] * n
        # the current blocks of the frontier: (k, k), (k, k - 1), (k - 1, k), (k - 1, k - 1)
        # and (k - 1, k - 2), all dense
        akk = coupling(n - 1, 0, True)
        ak1 = coupling(n - 1, -1, True) if n > 1 else None
        a1k = coupling(n - 2, 1, True) if n > 1 else None
        a11 = coupling(n - 2, 0, True) if n > 1 else None
        a12 = coupling(n - 2, -1, True) if n > 2 else None
        # the products, written in place (no new array per order)
        tmp = np.empty((m, m), self._dtype)
        for k in range(n - 1, -1, -1):
            if k == 0:  # the nearly singular last complement (inverse iteration's): an LU
                lu = lu_factor(akk, overwrite_a=True, check_finite=False)
                if not np.all(np.isfinite(lu[0])) or np.min(np.abs(np.diag(lu[0]))) == 0:
                    raise np.linalg.LinAlgError("a singular Schur complement in the "
                                                "order-by-order LU")
                self._lu = (np.asarray(lu[0], float), lu[1])
                break
            sinv = _inverse(akk)
            if not np.all(np.isfinite(sinv)):
                raise np.linalg.LinAlgError("a singular Schur complement in the order-by-order LU")
            x1 = sinv @ ak1  # S^-1 A(k, k-1)
            a11 -= np.matmul(a1k, x1, out=tmp)
            self._keep(k, sinv, x1, a1k)
            if k >= 2:
                d2 = coupling(k, -2, False)  # A(k, k-2), diagonal
                q2 = coupling(k - 2, 2, False)  # A(k-2, k), diagonal
                # S^-1 A(k, k-2), in S's array when the inverse did not overwrite it
                x2 = np.multiply(sinv, d2, out=None if np.shares_memory(sinv, akk) else akk)
                a12 -= np.matmul(a1k, x2, out=tmp)
                a21 = coupling(k - 2, 1, True)  # A(k-2, k-1)
                a21 -= np.multiply(q2[:, None], x1, out=tmp)
                # A(k-2, k-2): its original block is diagonal, so -q2 x2 plus that diagonal
                a22 = np.multiply(x2, -q2[:, None])
                a22.ravel()[::m + 1] += coupling(k - 2, 0, False)
                self._d2[k], self._q2[k] = np.asarray(d2, float), np.asarray(q2, float)
                a23 = coupling(k - 2, -1, True) if k >= 3 else None
            else:
                a21 = a22 = a23 = None
            akk, ak1, a1k, a11, a12 = a11, a12, a21, a22, a23
        self.shape = (n * m, n * m)

    def _coupling(self, k: int, d: int, dense: bool) -> np.ndarray:
        """The original block ``(k, k + d)``: dense, or its diagonal (``dense=False``).
        The first dense term is written into the block, not added to zeros (one pass
        over ``m^2`` numbers fewer, the same sums); with ``single`` the dense blocks are
        summed in single precision (half the bytes, no conversion of the block)."""
        m, pinned = self.m, self._pinned
        out = None
        for dg, X in self._diags:
            c = dg[d][k]
            if c == 0.0:
                continue
            if X.ndim == 2:
                c = X.dtype.type(c)  # in X's precision
                if out is None:
                    out = np.multiply(X, c)
                else:
                    out += c * X
            elif dense:
                if out is None:
                    out = np.zeros((m, m), self._dtype)
                out.ravel()[::m + 1] += c * X
            elif out is None:
                out = c * X
            else:
                out += c * X
        if out is None:
            out = np.zeros((m, m), self._dtype) if dense else np.zeros(m)
        out = out.astype(self._dtype, copy=False)
        if pinned.size:
            if dense:
                out[pinned, :] = 0.0
                if d == 0:
                    out[pinned, pinned] = 1.0
            else:
                out[pinned] = 1.0 if d == 0 else 0.0
        return out

    def _keep(self, k: int, sinv: np.ndarray, x1: np.ndarray, p: np.ndarray) -> None:
        """Keep the factors of the order ``k``: ``S^-1``, ``S^-1 A(k, k-1)`` and the
        eliminated ``A(k-1, k)`` (in memory here; on disk in
        :class:`._pentadiagonal_disk.DiskPentadiagonalLU`), in the elimination's precision
        (none of the three is written again by the elimination)."""
        self._inv[k], self._x1[k], self._p[k] = sinv, x1, p

    def _forward_factors(self, k: int):
        """``(S^-1, A(k-1, k))`` of the order ``k``, in the forward sweep's order (the
        factorisation's, from the top)."""
        return self._inv[k], self._p[k]

    def _back_factors(self, k: int):
        """``(S^-1 A(k, k-1), S^-1)`` of the order ``k``, in the back substitution's order
        (from the bottom)."""
        return self._x1[k], self._inv[k]

    def matvec(self, x: np.ndarray) -> np.ndarray:
        """``A x`` from the terms: ``sum_j H_j X x_j`` with ``x`` as orders x points (the
        Kronecker product's action), the pinned rows the identity's."""
        xr = np.asarray(x, float).reshape(self.n, self.m)
        out = np.zeros_like(xr)
        for H, X in self._terms:
            out += (H @ xr) @ X.T if X.ndim == 2 else (H @ xr) * X
        if self._pinned.size:
            out[:, self._pinned] = xr[:, self._pinned]
        return out.reshape(-1)

    def solve(self, rhs: np.ndarray, refine: bool = True) -> np.ndarray:
        """``A^{-1} rhs`` with one step of iterative refinement (Golub and Van Loan,
        sec. 3.5.3): the inverses of the Schur complements lose ``cond(S_k)`` times the
        rounding (a coarse SEDF grid: backward error 1.5e-10 with ``cond(S_1)`` = 1e6,
        1e-16 refined); ``refine=False``: the sweeps alone (an inverse iteration's inner
        solve, which its own iteration corrects)."""
        x = self._sweeps(rhs)
        return x + self._sweeps(np.asarray(rhs, float) - self.matvec(x)) if refine else x

    def _sweeps(self, rhs: np.ndarray) -> np.ndarray:
        """``A^{-1} rhs`` by the factors: the forward sweep from the top order down, then
        the back substitution upward."""
        m, n = self.m, self.n
        mv = single_matvec  # a @ x summed in double; numpy's product for double factors
        b = np.array(rhs, float).reshape(n, m)
        y = np.empty((n, m))
        for k in range(n - 1, -1, -1):
            if k == 0:
                y[k] = lu_solve(self._lu, b[k], check_finite=False)
            else:
                sinv, p = self._forward_factors(k)
                y[k] = mv(sinv, b[k])
                b[k - 1] -= mv(p, y[k])
            if k >= 2:
                b[k - 2] -= self._q2[k] * y[k]
        x = np.empty((n, m))
        for k in range(n):
            r = y[k]
            if k >= 1:
                x1, sinv = self._back_factors(k)
                r = r - mv(x1, x[k - 1])
            if k >= 2:
                r = r - mv(sinv, self._d2[k] * x[k - 2])
            x[k] = r
        return x.reshape(-1)
