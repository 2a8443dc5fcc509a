"""The escape matrix in orthonormal Hermite functions folded by parity: the escape rate of a
linearly damped model at low friction (:func:`.escape.kramers_escape`).

Why orthonormal functions for linear damping too: in Risken's pair of bases the scale of
the velocity must be ``sigma = sqrt(kT)`` (at another scale the Maxwellian
``exp(-v^2/2 kT)`` is no function of the pair's space below ``sigma/sqrt 2``), and the
functions then needed grow like ``omega_b/gamma`` (the layer of width
``sigma (gamma/omega_b)^(1/2)`` along the separatrix, :mod:`.escape`): 2896 functions at
the CDC's mu = 0.02, Delta = 3, kT = 0.35.  The orthonormal functions of
:mod:`._orthonormal` at the scale ``s`` of :func:`._orthonormal.velocity_scale` resolve the
layer and reach the Maxwellian's tail with ``pi V/delta`` functions, which grow like
``(omega_b/gamma)^(1/2)``: at mu = 0.02 ``s = 0.149`` against ``sigma = 0.592``, and 128
functions give the rate of the pair basis' 4096 on the same 262 intervals to 1e-13
(docs/noise.rst).  Linear damping then couples the order ``n`` to ``n +- 2`` (the friction
and the diffusion at a scale other than ``sqrt(kT)``), so the block LU
(:class:`._blocks.BlockTridiagonalLU`) groups two orders.

**Parity.**  For an even potential, a symmetric sink and linear damping the slowest mode
is even under ``(x, v) -> (-x, -v)``: each order keeps the points ``x >= 0`` only
(:mod:`._parity`), and the elimination costs an eighth.  The odd orders have one point
fewer on a grid with a point at 0; their blocks are padded by one decoupled row and column
(an identity row outside the mass matrix: no eigenvalue of the escape).
"""

from __future__ import annotations

import numpy as np

from ._blocks import TermBlocks, one_blas_thread
from ._folded_orders import FoldedOrderLU, dominant_ritz
from ._orthonormal import orthonormal_terms
from ._parity import parity_maps

__all__ = ["FoldedTermBlocks", "FoldedLU", "FoldedRungs", "carried_mode"]


class FoldedTermBlocks(TermBlocks):
    """The blocks of :class:`._blocks.TermBlocks` (every order's ends pinned, ``shift``
    subtracted) restricted to the even-odd parity of the slowest mode: ``mm`` rows per
    order, the points ``x >= 0`` of :func:`._parity.parity_maps` (even orders first
    row ``x = L``), odd orders padded by a decoupled last row where they have one point
    fewer.

    Parameters
    ----------
    terms : list of (scipy.sparse matrix, numpy.ndarray)
        ``sum_j kron(H_j, X_j)`` on all ``m`` points (:func:`._orthonormal.orthonormal_terms`).
    m : int
        The points of the full grid (symmetric, decreasing).
    shift : numpy.ndarray
        Length ``m``: the sink, symmetric.
    """

    def __init__(self, terms, m: int, shift):
        super().__init__(terms, m, shift, (0, m - 1), 0)
        self.maps = parity_maps(m, True)
        self.sizes = [idx.size for idx, _ in self.maps]
        self.mm = max(self.sizes)
        self._folded, self._applied = {}, {}
        self._reach = max(int(np.max(np.abs(H.tocoo().row - H.tocoo().col), initial=0))
                          for H, _ in self.terms)

    def _fold(self, t: int, p: int, q: int):
        """The term ``t``'s position matrix from the parity ``q`` (columns) to ``p`` (rows),
        and its diagonal when it is one (else ``None``)."""
        key = (t, p, q)
        if key not in self._folded:
            X = self.terms[t][1]
            idx, _ = self.maps[p]
            F = self.maps[q][1]
            B = X[idx] @ F if X.ndim == 2 else X[idx, None] * F[idx]
            d = np.diagonal(B).copy()
            diag = (d if B.shape[0] == B.shape[1] and np.array_equal(B, np.diag(d))
                    else None)
            self._folded[key] = (B, diag)
        return self._folded[key]

    def _entries(self, n0: int, n1: int, k0: int, k1: int):
        """``(i, j, v, B, diag)``: the terms' entries ``v`` of the orders ``(n, k)`` in the
        ranges, at the rows ``i`` and columns ``j`` of the block."""
        mm = self.mm
        for t, (H, _) in enumerate(self.terms):
            for n in range(n0, n1):
                lo, hi = H.indptr[n], H.indptr[n + 1]
                for k, v in zip(H.indices[lo:hi], H.data[lo:hi]):
                    if k0 <= k < k1:
                        B, diag = self._fold(t, n % 2, k % 2)
                        yield (n - n0) * mm, (k - k0) * mm, float(v), B, diag

    def block(self, n0: int, n1: int, k0: int, k1: int) -> np.ndarray:
        """The dense folded block of Hermite orders ``n0 <= n < n1`` by ``k0 <= k < k1``
        (Fortran order, for LAPACK)."""
        mm = self.mm
        out = np.zeros(((n1 - n0) * mm, (k1 - k0) * mm), order="F")
        for i, j, v, B, diag in self._entries(n0, n1, k0, k1):
            if diag is None:
                out[i:i + B.shape[0], j:j + B.shape[1]] += v * B
            else:
                a = np.arange(diag.size)
                out[i + a, j + a] += v * diag
        for n in range(n0, n1):
            p, r = n % 2, (n - n0) * mm
            out[r, :] = 0.0  # the pinned end x = L (x = -L is its mirror)
            if k0 <= n < k1:
                c = (n - k0) * mm
                a = np.arange(1, self.sizes[p])
                out[r + a, c + a] -= self.shift[self.maps[p][0][1:]]
                out[r, c] = 1.0
                if self.sizes[p] < mm:  # the padding: decoupled
                    out[r + mm - 1, c + mm - 1] = 1.0
        return out

    def apply(self, n0: int, n1: int, k0: int, k1: int, y: np.ndarray) -> np.ndarray:
        """``block(n0, n1, k0, k1) @ y`` for a block off the diagonal (``n1 <= k0`` or
        ``k1 <= n0``), from the few position matrices that every block shares (no block
        formed: the sweeps then read the LU factors only)."""
        out = np.zeros((n1 - n0) * self.mm)
        key = (n0, n1, k0, k1)
        if key not in self._applied:  # the sweeps apply each block once per solve
            self._applied[key] = list(self._entries(n0, n1, k0, k1))
        for i, j, v, B, diag in self._applied[key]:
            if diag is None:
                out[i:i + B.shape[0]] += v * (B @ y[j:j + B.shape[1]])
            else:
                out[i:i + diag.size] += v * diag * y[j:j + diag.size]
        out[::self.mm] = 0.0  # the pinned rows
        return out

    def bandwidth(self, rtol: float = 1e-14) -> int:
        """The largest ``|n - k|`` whose coupling (the terms summed) exceeds ``rtol`` times
        the largest entry (cancellations to round-off ignored, as in
        :meth:`._blocks.TermBlocks.bandwidth`), from the first 16 orders: the Galerkin
        products of ``xi`` and ``d/dxi`` couple every order alike."""
        big = max(float(np.max(np.abs(X))) * float(np.max(np.abs(H.data), initial=0.0))
                  for H, X in self.terms)
        b = 1
        for n in range(min(self.n_orders, 16)):
            for k in range(max(0, n - self._reach), min(self.n_orders, n + self._reach + 1)):
                if abs(n - k) > b and np.max(np.abs(self.block(n, n + 1, k, k + 1))) > rtol * big:
                    b = abs(n - k)
        return b

    def keep(self) -> np.ndarray:
        """The mass matrix's diagonal: 1 but on the pinned and padding rows."""
        out = np.zeros((self.n_orders, self.mm))
        for n in range(self.n_orders):
            out[n, 1:self.sizes[n % 2]] = 1.0
        return out.reshape(-1)


class FoldedLU:
    """The block LU of :class:`FoldedTermBlocks` in groups of ``b`` orders, eliminated from
    the lowest orders up (``T_k = D_k - L_k T_{k-1}^{-1} U_{k-1}``, ``L_k T^{-1}`` by two
    triangular solves from the right, as in :mod:`._fraction`): the factors of a truncation
    at ``N`` orders are the first ones of every larger truncation (the Galerkin blocks of
    the first ``N`` orders do not depend on the truncation), so the Hermite ladder
    factorises its largest rung only.

    Parameters
    ----------
    A : FoldedTermBlocks
        Built for the largest truncation to come (:meth:`extend` up to ``A.n_orders``).
    n_orders : int
        Orders factorised now (a multiple of ``b``).
    b : int
        Orders per block (the bandwidth of ``A``).

    Raises
    ------
    numpy.linalg.LinAlgError
        When a Schur complement is singular.
    """

    def __init__(self, A: FoldedTermBlocks, n_orders: int, b: int):
        self.A, self.b = A, int(b)
        self._lu = []
        self.n = 0
        self.extend(n_orders)

    def extend(self, n_orders: int) -> None:
        """Factorise up to ``n_orders`` orders (a multiple of ``b``, at most
        ``A.n_orders``); the orders factorised already are kept."""
        from scipy.linalg import blas, lapack

        A, b = self.A, self.b
        if n_orders % b or n_orders > A.n_orders:
            raise ValueError(f"n_orders = {n_orders}: a multiple of {b} up to {A.n_orders}")
        for k in range(len(self._lu), n_orders // b):
            n0 = k * b
            S = A.block(n0, n0 + b, n0, n0 + b)
            if k > 0:  # S -= L_k T_{k-1}^{-1} U_{k-1}, T = P L U: U's rows interchanged
                lu, piv = self._lu[-1]
                Z = blas.dtrsm(1.0, lu, A.block(n0, n0 + b, n0 - b, n0), side=1, lower=0)
                Z = blas.dtrsm(1.0, lu, Z, side=1, lower=1, diag=1, overwrite_b=True)
                U = lapack.dlaswp(A.block(n0 - b, n0, n0, n0 + b), piv)
                S = blas.dgemm(-1.0, Z, U, beta=1.0, c=S, overwrite_c=True)
            lu, piv, info = lapack.dgetrf(S, overwrite_a=True)
            if info != 0 or not np.all(np.isfinite(np.diagonal(lu))):
                raise np.linalg.LinAlgError("a singular Schur complement in the folded escape "
                                            f"matrix at Hermite order {n0}")
            self._lu.append((lu, piv))
        self.n = max(self.n, n_orders)

    def solve(self, rhs: np.ndarray, n: int) -> np.ndarray:
        """``A^{-1} rhs`` of the truncation at the first ``n`` orders (``rhs`` of length
        ``n mm``): the forward and backward block sweeps."""
        from scipy.linalg import lapack

        A, b = self.A, self.b
        nb = n // b
        y = np.array(rhs, float).reshape(nb, b * A.mm)
        for k in range(nb):
            r = y[k] if k == 0 else y[k] - A.apply(k * b, k * b + b, k * b - b, k * b, y[k - 1])
            y[k] = lapack.dgetrs(*self._lu[k], r)[0]
        for k in range(nb - 2, -1, -1):
            w = A.apply(k * b, k * b + b, k * b + b, k * b + 2 * b, y[k + 1])
            y[k] -= lapack.dgetrs(*self._lu[k], w)[0]
        return y.reshape(-1)


class FoldedRungs:
    """:func:`._orthonormal.orthonormal_slowest` folded by parity (the module docstring; the
    points ``points(nc)`` symmetric and the model and the sink even), for the ladder of
    :func:`._orthonormal.nonlinear_escape` (its ``slowest``): one :class:`FoldedLU` per
    scale, grid and sink, extended up the Hermite ladder.

    Parameters
    ----------
    capacity : int
        The largest Hermite truncation to come (the terms are built for it once).
    by_order : bool, optional
        Factorise order by order (:class:`._folded_orders.FoldedOrderLU`, 2.15 times fewer
        operations) where the Hermite bandwidth is 2, instead of in pairs of orders
        (:class:`FoldedLU`; the rates agree to rounding).
    start : tuple, optional
        The :attr:`mode` of another instance (another grid or sink): the first Arnoldi
        start of :class:`._folded_orders.FoldedOrderLU`'s factors, interpolated to these
        points (:func:`carried_mode`), where the velocity scale is the same.

    Attributes
    ----------
    mode : tuple or None
        ``(s, x, vector)`` of the last slowest mode: the scale, the points of each
        parity's rows and the Ritz vector.
    """

    def __init__(self, capacity: int, by_order: bool = False, start: tuple | None = None):
        self.capacity = int(capacity)
        self.by_order = bool(by_order)
        self._key, self._lu, self._keep, self._vec = None, None, None, None
        self._start, self.mode = start, None
        self._xs, self._nh, self._left = None, 0, None

    @staticmethod
    def numbers(nh: int, nc: int) -> int:
        """The numbers the factors keep: an LU of ``(b mm)^2`` per ``b`` orders
        (``b = 2``, ``mm = nc/2 + 1`` folded points)."""
        return 2 * nh * (nc // 2 + 1) ** 2

    def __call__(self, split, D: float, s: float, points, nh: int, nc: int, sink) -> float:
        """The smallest decay rate in ``nh`` orthonormal Hermite functions of ``v/s`` on the
        ``nc + 1`` points of ``points(nc)`` with the sink ``sink(xs)``, by shift-invert
        Arnoldi on the block LU from a fixed start."""
        import scipy.sparse.linalg as spla

        xs, Dx = points(nc)
        kappa = np.asarray(sink(xs), float)
        key = (float(s), int(nc), kappa.tobytes())
        with one_blas_thread():
            if key != self._key or nh > self._lu.A.n_orders:
                self._key, self._lu, self._vec = None, None, None  # the last factors freed first
                self._left = None
                cap = max(self.capacity, nh)
                A = FoldedTermBlocks(orthonormal_terms(split, D, s, xs, Dx, cap), xs.size,
                                     kappa)
                b = A.bandwidth()
                self._lu = (FoldedOrderLU(A, 0) if self.by_order and b == 2
                            else FoldedLU(A, 0, b))
                self._keep = A.keep()
                self._key = key
            lu = self._lu
            nh = -(-int(nh) // lu.b) * lu.b
            if nh > lu.n:
                lu.extend(nh)
            keep = self._keep[:nh * lu.A.mm]
            rows = [xs[idx] for idx, _ in lu.A.maps]
            if isinstance(lu, FoldedOrderLU):  # from the last slowest mode on these factors
                if self._vec is None:
                    v0 = keep.copy()
                    if self._start is not None and self._start[0] == float(s):
                        guess = keep * carried_mode(self._start, rows, lu.A.mm, nh)
                        v0 = guess if np.any(guess) else v0
                else:
                    v0 = np.zeros(keep.size)
                    n = min(v0.size, self._vec.size)
                    v0[:n] = self._vec[:n]
                theta, vec = dominant_ritz(lambda v: lu.solve(keep * v, nh), v0)
                if theta is not None:
                    self._vec, self._xs, self._nh = vec, xs, nh
                    self.mode = (float(s), rows, vec)
                    return float(-(1.0 / theta).real)
            self._nh = 0  # no mode for slope()
            op = spla.LinearOperator((keep.size,) * 2,
                                     matvec=lambda v: lu.solve(keep * v, nh), dtype=float)
            # one Ritz value from six vectors: the gap to the next decay rate (an intra-well
            # relaxation, O(gamma) against the rate's exp(-E_b/kT)) makes that seven
            # solves, where k = 3 took 21 (the same rate to 1e-18 at mu = 0.02)
            theta = spla.eigs(op, k=1, ncv=6, which="LM", return_eigenvectors=False,
                              tol=1e-12, v0=keep.copy())
        return float(-(1.0 / theta[0]).real)

    def slope(self, dsink) -> float | None:
        """``dr/dt`` of the last rate where the sink changes by ``dsink(xs)`` per unit
        ``t`` on the same points: the first-order change of a simple eigenvalue of ``A x =
        mu K x``, ``d mu = y^T dA x / y^T K x`` with ``y`` the left slowest mode (Arnoldi
        on ``A^{-T} K``, the same factors) and ``dA = -d kappa`` on every order's unpinned
        rows (Kato, *Perturbation Theory for Linear Operators*, II.2; Wilkinson, *The
        Algebraic Eigenvalue Problem*, 2.8); ``None`` where the last rate was not from
        the order-by-order factors or the left mode did not converge."""
        lu, nh = self._lu, self._nh
        if not isinstance(lu, FoldedOrderLU) or nh == 0:
            return None
        keep, x = self._keep[:nh * lu.A.mm], self._vec
        v0 = keep * x  # or the last left mode on these factors (a larger truncation's)
        if self._left is not None:
            v0 = np.zeros(keep.size)
            n = min(v0.size, self._left.size)
            v0[:n] = self._left[:n]
        with one_blas_thread():
            theta, y = dominant_ritz(lambda v: lu.solve_transposed(keep * v, nh), v0)
        if theta is None:
            return None
        self._left = y
        dk = np.asarray(dsink(self._xs), float)
        dK = np.zeros((nh, lu.A.mm))
        for n in range(nh):
            idx = lu.A.maps[n % 2][0]
            dK[n, 1:idx.size] = dk[idx[1:]]
        return float(np.sum(y * dK.reshape(-1) * x) / np.sum(y * keep * x))


def carried_mode(mode: tuple, rows: list, mm: int, nh: int) -> np.ndarray:
    """The vector of :attr:`FoldedRungs.mode` ``(s, x, vector)`` on the rows ``rows`` (the
    points of each parity's rows, decreasing from ``x = L``) with ``mm`` rows per order and
    ``nh`` orders: each order linearly interpolated in ``x`` (held at the ends), the orders
    beyond the mode's zero.  A start for the Arnoldi of another grid or sink: close to its
    slowest mode, it takes fewer solves (the stopping test is unchanged)."""
    _, x0, vec = mode
    m0 = max(x.size for x in x0)
    old = vec.reshape(-1, m0)
    out = np.zeros((nh, mm))
    for n in range(min(nh, old.shape[0])):
        x, y = x0[n % 2], old[n, :x0[n % 2].size]
        out[n, :rows[n % 2].size] = np.interp(rows[n % 2], x[::-1], y[::-1])
    return out.reshape(-1)
