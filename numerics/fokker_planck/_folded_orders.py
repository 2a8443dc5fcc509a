"""The LU of the folded escape matrix order by order, from the lowest order up
(:class:`FoldedOrderLU`, what :class:`._folded.FoldedRungs` factorises with ``by_order``:
the sink ladders' rungs of :func:`._sink.absorbing_limit`).

For linear damping in orthonormal Hermite functions of ``v/s`` at a scale other than
``sqrt(kT)`` the Galerkin operator couples the order ``n`` to ``n +- 1`` through
``-s xi d/dx`` (the dense Chebyshev differentiation matrix) and ``g(x) d/dxi``, and to
``n`` and ``n +- 2`` only through the friction and the diffusion, diagonal in the points
(:mod:`._pentadiagonal`).  :class:`._folded.FoldedLU` groups two orders into dense blocks
of ``2 m`` rows (``m`` folded points per order) and spends about ``18.7 m^3`` operations
per order (an LU of ``2 m`` rows, two triangular solves with ``2 m`` right-hand sides
and a product of ``2 m`` matrices per pair).

Eliminating one order at a time from the lowest up, the order ``p`` meets only ``p + 1``
(a dense coupling, filled by the elimination of ``p - 1``) and ``p + 2``, whose coupling
to ``p`` is still the original diagonal: the elimination of ``p`` changes the blocks of
the orders ``p + 1`` and ``p + 2`` only (block Gaussian elimination without pivoting
across orders, partial pivoting inside each order's Schur complement, LAPACK ``getrf``;
Golub and Van Loan, *Matrix Computations*, 4th ed., sec. 4.5).  Per order: an LU of ``m``
rows, a solve with ``2 m`` right-hand sides and two products of ``m`` matrices, about
``8.7 m^3`` (2.15 times fewer), and ``3 m^2`` numbers kept (the pairs keep ``2 m^2`` per
order).  As in :class:`._folded.FoldedLU` the factors of a truncation at ``N`` orders are
the first ones of every larger truncation (the Galerkin blocks of the first ``N`` orders
do not depend on the truncation), so the Hermite ladder of a rung factorises its largest
truncation only.

What is kept per order: the inverse of its Schur complement (formed for the updates; by
``getrs`` on the identity, 2.3 times faster than scipy's raw ``lapack.dgetri`` at its
default workspace, which runs unblocked) with the couplings
``S(p, p+1)`` and ``S(p+1, p)``, ``3 m^2`` numbers as with the LU, and a solve is four
matrix-vector products per order (memory-bound: 116 against 150 us per order with
``getrs`` at 197 rows).  CDC Delta = 3, kT = 0.35, mu = 5 (the rungs of 101-197 rows,
3616 orders factorised, one thread): the factorisations 9.8 -> 6.2 s, the solves 3.6 ->
2.5 s (with the first start of each rung from the last rung's mode,
:func:`._folded.carried_mode`: 272 -> 234 solves); the rate moved by 6e-13 of itself.
"""

from __future__ import annotations

import numpy as np

__all__ = ["FoldedOrderLU"]


class FoldedOrderLU:
    """The order-by-order LU of :class:`._folded.FoldedTermBlocks` (module docstring),
    extended up the Hermite ladder; the interface of :class:`._folded.FoldedLU` with one
    order per block (``b = 1``).

    Parameters
    ----------
    A : FoldedTermBlocks
        Built for the largest truncation to come, of Hermite bandwidth 2 at most.
    n_orders : int
        Orders factorised now.

    Raises
    ------
    numpy.linalg.LinAlgError
        When an order's Schur complement is singular.
    """

    def __init__(self, A, n_orders: int):
        self.A, self.b = A, 1
        self.n = 0
        self._inv, self._lower, self._upper, self._l2, self._u2 = [], [], [], [], []
        self._sparse, self._held, self._eye, self._rows = {}, [], None, None
        self._state = None  # the frontier: S(p, p), S(p, p+1), S(p+1, p), S(p+1, p+1)
        self.extend(n_orders)

    def _entries_of(self, B: np.ndarray):
        """A dense position matrix ``B`` as ``(rows, columns, values)`` where it has few
        entries (a diagonal between orders of the two parities), else ``B`` padded to
        ``mm x mm`` in Fortran order (kept per matrix: every order shares them)."""
        key = id(B)
        if key not in self._sparse:
            mm = self.A.mm
            nz = np.nonzero(B)
            if nz[0].size <= 2 * mm:
                self._sparse[key] = nz + (B[nz],)
            else:
                full = np.zeros((mm, mm), order="F")
                full[:B.shape[0], :B.shape[1]] = B
                self._sparse[key] = full
            self._held.append(B)  # the id stays this matrix's
        return self._sparse[key]

    def _coupling(self, n: int, k: int) -> list:
        """``[(v, B, diag), ...]``: the terms' entries ``v`` coupling the orders ``(n, k)``
        with their folded position matrices (:meth:`._folded.FoldedTermBlocks._entries`,
        in its order), from the terms' rows held as Python lists (the sparse matrices'
        scalars cost a microsecond each: 18 000 blocks at CDC mu = 5)."""
        if self._rows is None:
            self._rows = [(H.indptr.tolist(), H.indices.tolist(), H.data.tolist())
                          for H, _ in self.A.terms]
        out = []
        for t, (ptr, cols, vals) in enumerate(self._rows):
            for i in range(ptr[n], ptr[n + 1]):
                if cols[i] == k:
                    out.append((vals[i],) + self.A._fold(t, n % 2, k % 2))
        return out

    def _block(self, n: int, k: int, dense: bool = True):
        """The folded block of the orders ``(n, k)`` (:meth:`._folded.FoldedTermBlocks.block`,
        Fortran order), or with ``dense=False`` its diagonal where every term's position
        matrix is diagonal (the couplings ``n = k`` and two orders apart; else the dense
        block).  The position matrices with few entries (a diagonal between orders of
        the two parities) are added by their entries."""
        A, mm = self.A, self.A.mm
        entries = self._coupling(n, k)
        if dense or any(diag is None for *_, diag in entries):
            out = None  # the first product written in place (the sums in block()'s order)
            for v, B, diag in entries:
                if diag is None:
                    B = self._entries_of(B)
                    if out is None and not isinstance(B, tuple):
                        out = np.multiply(B, v, out=np.empty((mm, mm), order="F"))
                        continue
                if out is None:
                    out = np.zeros((mm, mm), order="F")
                if diag is not None:
                    _diagonal(out)[:diag.size] += v * diag
                elif isinstance(B, tuple):
                    out[B[0], B[1]] += v * B[2]
                else:
                    out += v * B
            if out is None:
                out = np.zeros((mm, mm), order="F")
            out[0, :] = 0.0  # the pinned end x = L (x = -L is its mirror)
            if n == k:
                p = n % 2
                _diagonal(out)[1:A.sizes[p]] -= A.shift[A.maps[p][0][1:]]
                out[0, 0] = 1.0
                if A.sizes[p] < mm:  # the padding: decoupled
                    out[mm - 1, mm - 1] = 1.0
            return out
        out = np.zeros(mm)
        for v, _, diag in entries:
            out[:diag.size] += v * diag
        out[0] = 0.0  # the pinned end x = L
        if n == k:
            p = n % 2
            out[1:A.sizes[p]] -= A.shift[A.maps[p][0][1:]]
            out[0] = 1.0
            if A.sizes[p] < mm:  # the padding: decoupled
                out[mm - 1] = 1.0
        return out

    def extend(self, n_orders: int) -> None:
        """Factorise up to ``n_orders`` orders (at most ``A.n_orders``); the orders
        factorised already are kept."""
        from scipy.linalg import blas, lapack

        A, N = self.A, self.A.n_orders
        if n_orders > N:
            raise ValueError(f"n_orders = {n_orders}: at most {N}")
        mm = A.mm
        for p in range(len(self._inv), n_orders):
            if self._state is None:  # the first order: nothing eliminated yet
                P = self._block(0, 0)
                U1 = self._block(0, 1) if N > 1 else None
                L1 = self._block(1, 0) if N > 1 else None
                Q = self._block(1, 1) if N > 1 else None
            else:
                P, U1, L1, Q = self._state
            lu, piv, info = lapack.dgetrf(P, overwrite_a=True)
            if info != 0 or not np.all(np.isfinite(np.diagonal(lu))):
                raise np.linalg.LinAlgError("a singular Schur complement in the folded escape "
                                            f"matrix at Hermite order {p}")
            # S(p,p)^-1 by getrs on the identity (np.linalg.inv's way): scipy's raw
            # lapack.dgetri at its default workspace (lwork = m) runs unblocked, 2.3 times
            # slower (197 rows, one thread: 1.50 against 0.66 ms; with the optimal lwork
            # as scipy.linalg.inv, used by ._pentadiagonal, it is as fast as getrs)
            if self._eye is None or self._eye.shape[0] != mm:
                self._eye = np.eye(mm, order="F")
            inv = lapack.dgetrs(lu, piv, self._eye)[0]
            del lu
            u2 = self._block(p, p + 2, False) if p + 2 < N else None
            l2 = self._block(p + 2, p, False) if p + 2 < N else None
            self._inv.append(inv)
            self._upper.append(U1)
            self._lower.append(L1)
            self._u2.append(u2)
            self._l2.append(l2)
            if p + 1 >= N:
                self._state = None
                continue
            # W = S(p,p)^-1 [S(p,p+1), A(p,p+2)] (the updates of the orders p+1 and p+2) by
            # the inverse: A(p,p+2) is diagonal, so S^-1 A(p,p+2) scales its columns (the
            # solve with 2 mm right-hand sides cost twice as much; CDC mu = 5, rung 10:
            # the same rate to 2e-15, the same backward error of a solve)
            W = np.empty((mm, 2 * mm) if u2 is not None else (mm, mm), order="F")
            W1 = blas.dgemm(1.0, inv, U1, c=W[:, :mm], overwrite_c=True)
            if not np.shares_memory(W1, W):
                W[:, :mm] = W1
            if u2 is not None:
                if u2.ndim == 1:
                    np.multiply(inv, u2[None, :], out=W[:, mm:])
                else:
                    W[:, mm:] = inv @ u2
            W1 = W[:, :mm]
            P_next = blas.dgemm(-1.0, L1, W1, beta=1.0, c=np.asfortranarray(Q),
                                overwrite_c=True)
            if u2 is None:
                self._state = (P_next, None, None, None)
                continue
            W2 = W[:, mm:]
            U_next = blas.dgemm(-1.0, L1, W2, beta=1.0,
                                c=np.asfortranarray(self._block(p + 1, p + 2)),
                                overwrite_c=True)
            L_next = self._block(p + 2, p + 1)
            Q_next = self._block(p + 2, p + 2, False)
            if l2.ndim == 1:  # A(p+2, p) W in place (W is not needed after)
                W1 *= l2[:, None]
                L_next -= W1
                W2 *= -l2[:, None]
                if Q_next.ndim == 1:
                    _diagonal(W2)[:] += Q_next
                    Q_next = W2
                else:
                    Q_next += W2
            else:
                L_next -= l2 @ W1
                Q_next = (np.diag(Q_next) if Q_next.ndim == 1 else Q_next) - l2 @ W2
            self._state = (P_next, U_next, L_next, Q_next)
        self.n = max(self.n, n_orders)

    def solve(self, rhs: np.ndarray, n: int) -> np.ndarray:
        """``A^{-1} rhs`` of the truncation at the first ``n`` orders (``rhs`` of length
        ``n mm``): the forward sweep up the orders, then the back substitution down."""
        from scipy.linalg import blas

        mm = self.A.mm
        y = np.array(rhs, float).reshape(n, mm)
        gemv = blas.dgemv
        r = np.empty(mm)
        for p in range(n):  # y_p = S_p^-1 (r_p - S(p,p-1) y_{p-1} - A(p,p-2) y_{p-2})
            r[:] = y[p]
            if p >= 1:
                gemv(-1.0, self._lower[p - 1], y[p - 1], beta=1.0, y=r, overwrite_y=True)
            if p >= 2:
                l2 = self._l2[p - 2]
                r -= l2 * y[p - 2] if l2.ndim == 1 else l2 @ y[p - 2]
            y[p] = gemv(1.0, self._inv[p], r)
        for p in range(n - 2, -1, -1):  # x_p = y_p - S_p^-1 (S(p,p+1) x_{p+1} + A(p,p+2) x_{p+2})
            w = gemv(1.0, self._upper[p], y[p + 1])
            if p + 2 < n:
                u2 = self._u2[p]
                w += u2 * y[p + 2] if u2.ndim == 1 else u2 @ y[p + 2]
            y[p] = gemv(-1.0, self._inv[p], w, beta=1.0, y=y[p])
        return y.reshape(-1)

    def solve_transposed(self, rhs: np.ndarray, n: int) -> np.ndarray:
        """``A^{-T} rhs`` of the truncation at the first ``n`` orders: with ``A = (S + L)
        S^{-1} (S + U)`` (``S`` the Schur complements, ``L`` and ``U`` the couplings below
        and above them that :meth:`solve` applies), ``A^T = (S + U)^T S^{-T} (S + L)^T``:
        the same sweeps with the transposed blocks (the left slowest mode of
        :meth:`._folded.FoldedRungs.slope`)."""
        from scipy.linalg import blas

        mm = self.A.mm
        y = np.array(rhs, float).reshape(n, mm)
        gemv = blas.dgemv
        r = np.empty(mm)
        for p in range(n):  # (S + U)^T y = rhs, up the orders
            r[:] = y[p]
            if p >= 1:
                gemv(-1.0, self._upper[p - 1], y[p - 1], beta=1.0, y=r, overwrite_y=True,
                     trans=1)
            if p >= 2:
                u2 = self._u2[p - 2]
                r -= u2 * y[p - 2] if u2.ndim == 1 else u2.T @ y[p - 2]
            y[p] = gemv(1.0, self._inv[p], r, trans=1)
        for p in range(n - 2, -1, -1):  # S^{-T} (S + L)^T x = y, down the orders
            w = gemv(1.0, self._lower[p], y[p + 1], trans=1)
            if p + 2 < n:
                l2 = self._l2[p]
                w += l2 * y[p + 2] if l2.ndim == 1 else l2.T @ y[p + 2]
            y[p] = gemv(-1.0, self._inv[p], w, beta=1.0, y=y[p], trans=1)
        return y.reshape(-1)


def _diagonal(a: np.ndarray) -> np.ndarray:
    """The diagonal of a square array as a writable view."""
    return np.lib.stride_tricks.as_strided(a, shape=(min(a.shape),),
                                           strides=(a.strides[0] + a.strides[1],))


def dominant_ritz(op, v0: np.ndarray, tol: float = 1e-12, max_vectors: int = 12):
    """The Ritz pair of largest modulus of ``op`` (the shift-inverted escape matrix) by
    Arnoldi from ``v0`` (Gram-Schmidt twice), stopped at the first Krylov dimension where
    the pair's residual ``|h_{k+1,k} y_k|`` is within ``tol`` of the value: ARPACK's test
    (``scipy.sparse.linalg.eigs(k=1, ncv=6, tol=tol)``, which checks it once six vectors
    are built), checked after every product.  From a cold start it takes the same seven
    products as ARPACK; from the slowest mode of a larger truncation on the same factors
    (the truncation check of :func:`._sink.absorbing_limit`) two or three.

    Returns
    -------
    tuple
        ``(theta, vector)`` (the real part of the Ritz vector, unit norm), or
        ``(None, None)`` where ``max_vectors`` products did not converge.
    """
    V = np.zeros((max_vectors + 1, v0.size))
    V[0] = v0 / np.linalg.norm(v0)
    H = np.zeros((max_vectors + 1, max_vectors))
    for k in range(max_vectors):
        w = op(V[k])
        for _ in range(2):
            c = V[:k + 1] @ w
            H[:k + 1, k] += c
            w = w - c @ V[:k + 1]
        H[k + 1, k] = np.linalg.norm(w)
        vals, vecs = np.linalg.eig(H[:k + 1, :k + 1])
        i = int(np.argmax(np.abs(vals)))
        y = vecs[:, i] / np.linalg.norm(vecs[:, i])
        if abs(H[k + 1, k] * y[-1]) <= tol * abs(vals[i]) or H[k + 1, k] == 0.0:
            x = (y @ V[:k + 1]).real
            return vals[i], x / np.linalg.norm(x)
        V[k + 1] = w / H[k + 1, k]
    return None, None
