"""A block-tridiagonal LU factorisation of the Kramers matrix in the Hermite index.

The Kramers operator in Hermite functions of the velocity couples the order ``n`` only to
``n +- 1`` for linear damping (``v d/dx`` and ``g d/dv``; the damping and diffusion are
diagonal), and to ``n +- b`` with ``b = k_max + 1`` for a damping with velocity powers up
to ``k_max``.  Grouping ``b`` consecutive orders makes the matrix block tridiagonal with
dense blocks of ``b (n_cheb + 1)`` rows; block Gaussian elimination (the block Thomas
algorithm; in the continued-fraction form Risken, *The Fokker-Planck Equation*, 2nd ed.,
sec. 9.2 and ch. 10, the matrix continued fraction) factorises it in ``O(N m^3)`` work
and ``N m^2`` memory, ``N`` Hermite orders and ``m`` Chebyshev points, and each solve costs
``O(N m^2)``.  A general sparse LU of the same matrix fills in far more (the Chebyshev
blocks are dense) and was the cost of the escape rate's Hermite ladder.

Each Schur complement ``S_k = D_k - L_k S_{k-1}^{-1} U_{k-1}`` is factorised with partial
pivoting inside the block (LAPACK ``getrf``); no pivoting runs across blocks, which the
escape matrix (the Kramers operator with a sink, shifted off its spectrum) does not need:
the rates agree with the sparse LU's to round-off (docs/noise.rst).
"""

from __future__ import annotations

import functools

import numpy as np
import scipy.sparse as sps

__all__ = ["BlockTridiagonalLU", "TermBlocks", "hermite_bandwidth", "one_blas_thread",
           "on_one_blas_thread"]

def one_blas_thread():
    """Context manager: the BLAS on one thread (:func:`threadpoolctl.threadpool_limits`; the
    blocks are small, a few hundred rows, and threads spinning for them on a loaded machine
    made ``lu_factor`` 100 times slower); the previous counts come back on exit."""
    from threadpoolctl import threadpool_limits

    return threadpool_limits(limits=1, user_api="blas")


def on_one_blas_thread(func):
    """Decorator: ``func`` runs inside :func:`one_blas_thread`.  On the entry points of the
    Kramers solutions (and the solutions' products) it makes their bits independent of the
    BLAS's thread count: OpenBLAS splits a ``gemm`` or ``gemv`` among its threads and the
    split changes the rounding (SEDF mu = 0.01, ``kbm noise --json``: ``P(E)`` moved by
    2e-15 and its stated ``change_peak`` by 4e-10 relative between ``OPENBLAS_NUM_THREADS``
    1 and 2, from products outside the solves' own ``one_blas_thread``)."""

    @functools.wraps(func)
    def pinned(*args, **kwargs):
        with one_blas_thread():
            return func(*args, **kwargs)

    return pinned


def hermite_bandwidth(A, m: int, rtol: float = 1e-14) -> int:
    """The largest ``|n - n'|`` of an entry ``A[n m + i, n' m + j]`` above ``rtol`` times
    the largest: for linear damping with ``sigma^2 = kT`` the friction's and diffusion's
    ``n -> n + 2`` parts cancel up to round-off, which is not a coupling."""
    coo = sps.coo_matrix(A)
    big = np.abs(coo.data) > rtol * (np.max(np.abs(coo.data)) if coo.nnz else 0.0)
    if not big.any():
        return 0
    return int(np.max(np.abs(coo.row[big] // m - coo.col[big] // m)))


class TermBlocks:
    """The blocks of ``sum_j kron(H_j, X_j)`` (:func:`..kramers.kramers_terms`), assembled
    on demand, with the escape's changes: ``shift`` subtracted on the diagonal and the
    rows ``pinned`` (positions within each Hermite order ``>= first_pinned``) replaced by
    identity rows.

    Parameters
    ----------
    terms : list of (scipy.sparse matrix, numpy.ndarray)
    m : int
        Chebyshev points.
    shift : numpy.ndarray, optional
        Length ``m``.
    pinned : sequence of int
    first_pinned : int
    """

    def __init__(self, terms, m: int, shift=None, pinned=(), first_pinned: int = 2):
        self.terms = [(sps.csr_matrix(H), np.asarray(X, float)) for H, X in terms]
        self.m = m
        self.n_orders = self.terms[0][0].shape[0]
        self.shift = None if shift is None else np.asarray(shift, float)
        self.pinned = np.asarray(pinned, int)
        self.first_pinned = int(first_pinned)

    def block(self, n0: int, n1: int, k0: int, k1: int) -> np.ndarray:
        """The dense block of Hermite orders ``n0 <= n < n1`` by ``k0 <= k < k1``."""
        m = self.m
        out = np.zeros(((n1 - n0) * m, (k1 - k0) * m))
        diag = np.arange(m)
        for H, X in self.terms:
            sub = sps.coo_matrix(H[n0:n1, k0:k1])
            for i, j, v in zip(sub.row, sub.col, sub.data):
                if X.ndim == 2:
                    out[i * m:(i + 1) * m, j * m:(j + 1) * m] += v * X
                else:
                    out[i * m + diag, j * m + diag] += v * X
        for n in range(max(n0, k0), min(n1, k1)):
            r, c = (n - n0) * m, (n - k0) * m
            if self.shift is not None:
                out[r + diag, c + diag] -= self.shift
            if n >= self.first_pinned and self.pinned.size:
                out[r + self.pinned, :] = 0.0
                out[r + self.pinned, c + self.pinned] = 1.0
        for n in range(n0, n1):  # pinned rows are zero off the diagonal block
            if n >= self.first_pinned and self.pinned.size and not k0 <= n < k1:
                out[(n - n0) * m + self.pinned, :] = 0.0
        return out

    def bandwidth(self, rtol: float = 1e-14) -> int:
        """:func:`hermite_bandwidth` of the assembled matrix, from the order pairs that
        the terms couple beyond ``n +- 1`` (cancellations to round-off ignored)."""
        pairs = set()
        for H, _ in self.terms:
            coo = sps.coo_matrix(H)
            pairs |= {(int(i), int(j)) for i, j in zip(coo.row, coo.col) if abs(i - j) > 1}
        big = max(float(np.max(np.abs(X))) * float(np.max(np.abs(H.data), initial=0.0))
                  for H, X in self.terms)
        b = 1
        for i, j in sorted(pairs):
            if abs(i - j) > b and np.max(np.abs(self.block(i, i + 1, j, j + 1))) > rtol * big:
                b = abs(i - j)
        return b


class BlockTridiagonalLU:
    """The block LU factors of a matrix that is block tridiagonal in groups of ``b``
    Hermite orders (``m`` rows each).

    Parameters
    ----------
    A : scipy.sparse matrix or TermBlocks
        Square, of size ``N m``, with Hermite bandwidth ``<= b``; entries farther from the
        diagonal (round-off, :func:`hermite_bandwidth`) are left out.  A
        :class:`TermBlocks` is assembled block by block (no global sparse matrix: its
        dense Chebyshev blocks were most of the memory).
    m : int
        Rows per Hermite order (the Chebyshev points).
    b : int, optional
        Hermite orders per block (default the bandwidth of ``A``, at least 1).

    Raises
    ------
    numpy.linalg.LinAlgError
        When a Schur complement is singular (the matrix needs pivoting across blocks).
    """

    def __init__(self, A, m: int, b: int | None = None):
        from scipy.linalg import lu_factor

        if isinstance(A, TermBlocks):
            size = A.n_orders * m
            b = max(1, A.bandwidth() if b is None else int(b))

            def get(r0, r1, c0, c1):
                return A.block(r0 // m, r1 // m, c0 // m, c1 // m)
        else:
            A = sps.csr_matrix(A)
            size = A.shape[0]
            b = max(1, hermite_bandwidth(A, m) if b is None else int(b))

            def get(r0, r1, c0, c1):
                return A[r0:r1, c0:c1].toarray()
        edges = list(range(0, size, b * m)) + [size]
        # eliminated from the highest Hermite orders down (their blocks carry the damping
        # -n gamma; the n = 0 block has none): the spans in elimination order
        self.spans = [(edges[k], edges[k + 1]) for k in range(len(edges) - 1)][::-1]
        self.shape = (size, size)
        self._lower, self._upper, self._lu = [], [], []
        prev_lu = None
        for k, (r0, r1) in enumerate(self.spans):
            S = get(r0, r1, r0, r1)
            if k > 0:
                q0, q1 = self.spans[k - 1]
                Lk = get(r0, r1, q0, q1)
                S -= Lk @ self._solve_block(prev_lu, self._upper[-1])
                self._lower.append(Lk)
            if k < len(self.spans) - 1:
                q0, q1 = self.spans[k + 1]
                self._upper.append(get(r0, r1, q0, q1))
            prev_lu = lu_factor(S, check_finite=False)
            if not np.all(np.isfinite(prev_lu[0])) or np.min(np.abs(np.diag(prev_lu[0]))) == 0:
                raise np.linalg.LinAlgError("a singular Schur complement in the block LU")
            self._lu.append(prev_lu)

    @staticmethod
    def _solve_block(lu, rhs):
        from scipy.linalg import lu_solve

        return lu_solve(lu, rhs, check_finite=False)

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        """``A^{-1} rhs`` by the forward and backward block sweeps."""
        sp_ = self.spans
        nb = len(sp_)
        y = [None] * nb
        for k, (r0, r1) in enumerate(sp_):
            r = rhs[r0:r1]
            if k > 0:
                r = r - self._lower[k - 1] @ y[k - 1]
            y[k] = self._solve_block(self._lu[k], r)
        x = np.empty(rhs.shape, dtype=np.result_type(rhs, float))
        x[sp_[-1][0]:sp_[-1][1]] = y[-1]
        for k in range(nb - 2, -1, -1):
            q0, q1 = sp_[k + 1]
            x[sp_[k][0]:sp_[k][1]] = y[k] - self._solve_block(self._lu[k],
                                                              self._upper[k] @ x[q0:q1])
        return x
