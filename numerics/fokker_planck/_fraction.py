"""The escape matrix of a linearly damped model, eliminated Hermite order by Hermite order
(Risken's matrix continued fraction in LU form) and folded by parity for an even potential.

For ``x'' = -g(x) - gamma x' + sqrt(2 D) xi`` with Hermite functions of scale
``sigma^2 = kT = D/gamma`` the Kramers operator with a sink ``kappa(x)`` couples the order
``n`` only to ``n +- 1`` (Risken, *The Fokker-Planck Equation*, 2nd ed., eqs. 10.51-10.53):

* ``(n, n + 1)``: ``-sigma sqrt(n + 1) d/dx``;
* ``(n, n - 1)``: ``-sqrt(n) (sigma d/dx + g(x)/sigma)``;
* ``(n, n)``: ``-n gamma - kappa(x)``, a diagonal.

So the blocks are known in closed form and the elimination needs one LU and two triangular
solves with ``m`` right-hand sides per order, no global matrix and no block assembly from
sparse terms.  It runs **upward**, ``T_n = D_n - L_n T_{n-1}^{-1} U_{n-1}`` from the first
block of the orders 0 and 1 together (``D_0 = -kappa`` alone is singular in the well): the
factors of a truncation at ``N`` orders are then the first ``N`` of every larger one, so
the Hermite ladder factorises its largest truncation only, and the rate of each rung is a
few solves with the leading factors.  ``L_n T^{-1}`` is two triangular solves from the right
(OpenBLAS's right-side ``trsm`` is about twice as fast as ``getrs``' left-side ones at these
sizes).  The solves run in one compiled sweep (:mod:`._sweeps`).

Upward elimination leaves a round-off of about 1e-11 of the rate (downward: 1e-13, the
tail blocks carry ``-n gamma``); the rates of the two agree to 3e-11 at mu = 0.02 with
2048 Hermite functions (docs/noise.rst), five orders below the ladder's 1e-6, and the
eigenvalue iteration stops at 1e-10.

**Parity.**  For an even potential, a symmetric sink and linear damping the slowest mode
is even under ``(x, v) -> (-x, -v)``: the coefficients are kept on ``x >= 0`` only
(:mod:`._parity`, the odd orders without ``x = 0``), which halves the blocks and cuts the
work of the elimination eightfold.

The rate is the smallest eigenvalue of ``-(A)`` in the metric that leaves out the pinned
rows (``c_n(+-L) = 0`` for ``n >= 2``): the largest eigenvalue of ``A^{-1} K``, by
Arnoldi's method (its largest Ritz value), which the gap to the next decay rate (an
intra-well relaxation, ``O(gamma)`` against the rate's ``exp(-E_b/kT)``) makes converge in
a few solves, two or three from the mode of the previous rung.
"""

from __future__ import annotations

import math

import numpy as np

from ._parity import parity_maps

__all__ = ["EscapeFraction"]


class EscapeFraction:
    """The escape matrix ``A = L_Kramers - kappa`` of a linearly damped model, factorised
    by elimination from the lowest Hermite orders up.

    Parameters
    ----------
    Dx : numpy.ndarray
        The differentiation matrix on the position points (``m x m``).
    g, kappa : numpy.ndarray
        The force ``G'`` and the sink at the points.
    sigma, gamma : float
        The Hermite scale ``sqrt(kT)`` and the friction.
    n_orders : int
        Hermite functions factorised now (``>= 2``; :meth:`extend` adds more).
    fold : bool
        Keep ``x >= 0`` only (an even potential and sink on a symmetric grid).
    pinned : tuple of int
        Points whose rows are ``c_n = 0`` for ``n >= 2`` (the two ends).
    capacity : int, optional
        Hermite orders to hold room for (default ``n_orders``; :meth:`extend` beyond it
        copies the factors once).
    buffer : numpy.ndarray, optional
        A flat float array to hold the factors in when it is large enough (the storage of
        a factorisation no longer needed, :meth:`storage`): its pages are mapped already,
        where fresh ones cost the kernel a zero fill (about 1 s of system time for the
        three factorisations of the escape at mu = 0.02).  Its old values are never read.

    Raises
    ------
    numpy.linalg.LinAlgError
        When a Schur complement is singular.
    """

    def __init__(self, Dx, g, kappa, sigma: float, gamma: float, n_orders: int, fold: bool,
                 pinned=None, capacity: int | None = None, buffer=None):
        m = Dx.shape[0]
        self.maps = parity_maps(m, fold)
        self.fold, self.gamma = bool(fold), float(gamma)
        pinned = (0, m - 1) if pinned is None else pinned
        mm = self.maps[0][0].size
        # [up, lo] x parity x [unpinned, pinned] bases of the blocks (k, k + 1) / sqrt(k + 1)
        # and (k, k - 1) / sqrt(k), zero-padded to mm x mm
        self._basis = np.zeros((2, 2, 2, mm, mm))
        self._diag, self._pin = [], []
        for p in (0, 1):
            idx, _ = self.maps[p]
            Fq = self.maps[(1 - p) if fold else p][1]
            Dq = Dx[idx] if Fq is None else Dx[idx] @ Fq
            Gq = (np.diag(g) if Fq is None else g[:, None] * Fq)[idx]
            pin = np.flatnonzero(np.isin(idx, pinned))
            for j, B in enumerate((-sigma * Dq, -(sigma * Dq + Gq / sigma))):
                self._basis[j, p, :, :B.shape[0], :B.shape[1]] = B
                self._basis[j, p, 1, pin] = 0.0
            self._diag.append(np.asarray(kappa, float)[idx])
            self._pin.append(pin)
        self._blocks = {}
        self._basis_t = np.ascontiguousarray(self._basis.transpose(0, 1, 2, 4, 3))
        self.n, self.sizes, self._lu0, self._last = 0, [], None, None
        cap = max(int(n_orders), int(capacity or 0), 2)
        size = cap * mm * mm
        self._lu = (buffer[:size].reshape(cap, mm, mm)
                    if buffer is not None and buffer.size >= size else np.zeros((cap, mm, mm)))
        self._piv = np.zeros((cap, mm), dtype=np.int64)
        self.extend(n_orders)

    def storage(self) -> np.ndarray:
        """The factors' storage, flat (the ``buffer`` of a next factorisation)."""
        return self._lu.reshape(-1)

    def _block(self, j: int, k: int) -> np.ndarray:
        """The basis ``j`` (0: up, 1: lo) of the rows of order ``k``, cut to the sizes
        (Fortran order, for BLAS)."""
        key = (j, self._par(k), int(k >= 2))
        if key not in self._blocks:
            p = self._par(k)
            cols = self.maps[self._par(k + 1 if j == 0 else k - 1)][0].size
            self._blocks[key] = np.asfortranarray(self._basis[key][:self.maps[p][0].size,
                                                                   :cols])
        return self._blocks[key]

    def extend(self, n_orders: int) -> None:
        """Factorise up to ``n_orders`` Hermite orders (the orders already factorised are
        kept: the elimination runs upward, so a truncation's factors are the first ones of
        every larger truncation)."""
        from scipy.linalg import blas, lapack

        n_orders = int(n_orders)
        if n_orders < 2:
            raise ValueError(f"n_orders = {n_orders}: the escape matrix needs >= 2 Hermite "
                             "orders")
        if n_orders > self._lu.shape[0]:
            grow = max(n_orders, self._lu.shape[0] * 3 // 2)
            lu, piv = self._lu, self._piv
            self._lu = np.zeros((grow,) + lu.shape[1:])
            self._lu[:lu.shape[0]] = lu
            self._piv = np.zeros((grow, piv.shape[1]), dtype=np.int64)
            self._piv[:piv.shape[0]] = piv
            del lu, piv
        for k in range(self.n, n_orders):
            self.sizes.append(self.maps[self._par(k)][0].size)
            if k == 0:
                continue
            if k == 1:  # the first block: orders 0 and 1 together (D_0 = -kappa is singular)
                m0, m1 = self.sizes
                S = np.zeros((m0 + m1,) * 2, order="F")
                S[:m0, :m0] = self._D(0)
                S[:m0, m0:] = self._block(0, 0)
                S[m0:, :m0] = self._block(1, 1)
                S[m0:, m0:] = self._D(1)
            else:
                # T_k = D_k - k L T_{k-1}^{-1} U (the bases L, U): L T^{-1} by two triangular
                # solves from the right (T = P L U), U with its rows interchanged by P^T
                lu, piv = self._last
                Lk, Uk = self._block(1, k), self._block(0, k - 1)
                if k == 2:  # the first block holds order 0 too: L_2 and U_1 padded
                    m0 = self.sizes[0]
                    Lk = np.asfortranarray(np.hstack([np.zeros((Lk.shape[0], m0)), Lk]))
                    Uk = np.asfortranarray(np.vstack([np.zeros((m0, Uk.shape[1])), Uk]))
                Z = blas.dtrsm(1.0, lu, Lk, side=1, lower=0)
                Z = blas.dtrsm(1.0, lu, Z, side=1, lower=1, diag=1, overwrite_b=True)
                S = blas.dgemm(-float(k), Z, lapack.dlaswp(Uk, piv), beta=1.0,
                               c=self._D(k), overwrite_c=True)
            lu, piv, info = lapack.dgetrf(S, overwrite_a=True)
            if info != 0 or not np.all(np.isfinite(np.diagonal(lu))):
                raise np.linalg.LinAlgError("a singular Schur complement in the escape "
                                            f"matrix at Hermite order {k}")
            self._last = (lu, piv)
            if k == 1:
                self._lu0 = (lu, piv)
            else:
                s = lu.shape[0]
                self._lu[k, :s, :s] = lu.T  # transposed for the sweeps (._sweeps)
                self._piv[k, :s] = piv
        self.n = max(self.n, n_orders)

    def _par(self, k: int) -> int:
        return k % 2 if self.fold else 0

    def _D(self, k: int) -> np.ndarray:
        p = self._par(k)
        S = np.zeros((self._diag[p].size,) * 2, order="F")
        np.fill_diagonal(S, -(k * self.gamma) - self._diag[p])
        if k >= 2:
            pin = self._pin[p]
            S[pin, pin] = 1.0
        return S

    def keep(self, n: int | None = None) -> list:
        """The mass matrix's diagonal per order (the first ``n``): 0 on the pinned rows."""
        n = self.n if n is None else int(n)
        out = [np.ones(s) for s in self.sizes[:n]]
        for k in range(2, n):
            out[k][self._pin[self._par(k)]] = 0.0
        return out

    def _solve_rows(self, Y: np.ndarray, n: int) -> np.ndarray:
        """``A^{-1}`` of the first ``n`` orders on the rows of ``Y`` (``n x mm``, the order
        ``k`` in the leading ``sizes[k]`` entries of row ``k``, zeros after), in place."""
        from scipy.linalg import lapack

        from ._sweeps import backward, forward

        if not 2 <= n <= self.n:
            raise ValueError(f"n = {n}: {self.n} Hermite orders are factorised")
        m0, m1 = self.sizes[0], self.sizes[1]
        sizes = np.asarray(self.sizes[:n], dtype=np.int64)
        par = np.array([self._par(k) for k in range(n)], dtype=np.int64)
        y0, _ = lapack.dgetrs(*self._lu0, np.concatenate([Y[0, :m0], Y[1, :m1]]))
        Y[0, :m0], Y[1, :m1] = y0[:m0], y0[m0:]
        forward(self._lu, self._piv, self._basis_t, sizes, par, Y, n)
        backward(self._lu, self._piv, self._basis_t, sizes, par, Y, n)
        if n > 2:
            w = math.sqrt(2) * (self._block(0, 1) @ Y[2, :sizes[2]])
            y0 -= lapack.dgetrs(*self._lu0, np.concatenate([np.zeros(m0), w]))[0]
            Y[0, :m0], Y[1, :m1] = y0[:m0], y0[m0:]
        return Y

    def _rows(self, vecs: list, n: int) -> np.ndarray:
        Y = np.zeros((n, self._lu.shape[1]))
        for k in range(n):
            Y[k, :self.sizes[k]] = vecs[k]
        return Y

    def solve(self, rhs: list, n: int | None = None) -> list:
        """``A^{-1} rhs`` of the truncation at the first ``n`` orders (default all), ``rhs``
        a list of per-order vectors."""
        n = self.n if n is None else int(n)
        Y = self._solve_rows(self._rows(rhs, n), n)
        return [Y[k, :s].copy() for k, s in enumerate(self.sizes[:n])]

    def slowest(self, tol: float = 1e-10, max_iter: int = 40, start=None,
                n: int | None = None) -> float:
        """The smallest decay rate ``-lambda`` of ``A c = lambda K c`` (the truncation at the
        first ``n`` orders, default all): Arnoldi's method on ``A^{-1} K`` (shift-invert at
        0), until the largest Ritz value changes by less than ``tol`` (above the
        elimination's round-off, 1e-11); the gap to the next decay rate (an intra-well
        relaxation, ``O(gamma)``) makes that a few solves.  scipy's restarted Arnoldi when
        it does not settle in ``max_iter``.

        ``start``: a mode of another truncation on the same points (its orders padded with
        zeros or cut; the escape ladder's previous rung, the other sink, another grid
        interpolated: two or three solves instead of six), else the marginal ``c_0 = 1``.
        The mode found (the Ritz vector) is :attr:`mode`."""
        n = self.n if n is None else int(n)
        K = self._rows(self.keep(n), n)
        X = np.zeros_like(K)
        X[0, :self.sizes[0]] = 1.0
        sizes = self.sizes[:n]
        if start is not None and all(np.shape(a) == (s,) for a, s in zip(start, sizes)):
            X[:] = 0.0
            for k, a in enumerate(start[:n]):
                X[k, :sizes[k]] = a
        V = [X / math.sqrt(float(np.vdot(X, X)))]
        H = np.zeros((max_iter + 1, max_iter))
        old = None
        for j in range(max_iter):
            w = self._solve_rows(K * V[j], n)
            for _ in range(2):  # Gram-Schmidt, repeated once
                for i in range(j + 1):
                    h = float(np.vdot(V[i], w))
                    H[i, j] += h
                    w -= h * V[i]
            H[j + 1, j] = math.sqrt(float(np.vdot(w, w)))
            ritz, vecs = np.linalg.eig(H[:j + 1, :j + 1])
            i = int(np.argmax(np.abs(ritz)))
            theta = complex(ritz[i])
            done = old is not None and abs(theta - old) <= tol * abs(theta)
            if done or H[j + 1, j] <= 1e-14 * abs(theta):
                y = vecs[:, i] / vecs[np.argmax(np.abs(vecs[:, i])), i]
                mode = sum(float(c.real) * v for c, v in zip(y, V))
                mode /= math.sqrt(float(np.vdot(mode, mode)))
                self.mode = [mode[k, :s].copy() for k, s in enumerate(sizes)]
                return -1.0 / theta.real
            old = theta
            V.append(w / H[j + 1, j])
        self.mode = None
        return self._arnoldi(self.keep(n), n)

    def _arnoldi(self, K, n: int) -> float:
        import scipy.sparse.linalg as spla

        cuts = np.cumsum([0] + self.sizes[:n])
        flat_k = np.concatenate(K)

        def matvec(v):
            v = flat_k * np.asarray(v).ravel()
            return np.concatenate(self.solve([v[cuts[k]:cuts[k + 1]] for k in range(n)], n))

        op = spla.LinearOperator((cuts[-1], cuts[-1]), matvec=matvec, dtype=float)
        # a fixed start (c = 1 on the kept rows): ARPACK's own is drawn from a seed kept
        # between calls, which made the rate depend on the process's earlier Arnoldi runs
        theta = spla.eigs(op, k=3, which="LM", return_eigenvectors=False, tol=1e-12,
                          v0=flat_k.copy())
        lam = 1.0 / theta
        return float(-lam[np.argsort(np.abs(lam))][0].real)

