"""The escape matrix of a linearly damped model, eliminated Hermite order by Hermite order
(Risken's matrix continued fraction in LU form) and folded by parity for an even potential.

For ``x'' = -g(x) - gamma x' + sqrt(2 D) xi`` with Hermite functions of scale
``sigma^2 = kT = D/gamma`` the Kramers operator with a sink ``kappa(x)`` couples the order
``n`` only to ``n +- 1`` (Risken, *The Fokker-Planck Equation*, 2nd ed., eqs. 10.51-10.53):

* ``(n, n + 1)``: ``-sigma sqrt(n + 1) d/dx``;
* ``(n, n - 1)``: ``-sqrt(n) (sigma d/dx + g(x)/sigma)``;
* ``(n, n)``: ``-n gamma - kappa(x)``, a diagonal.

So the blocks are known in closed form and the elimination from the highest order down,
``S_n = D_n - U_n S_{n+1}^{-1} L_{n+1}``, needs one LU and one solve with ``m`` right-hand
sides per order, no global matrix and no block assembly from sparse terms.

**Parity.**  For an even potential (``g`` odd), the symmetric sink and linear damping the
operator commutes with ``(x, v) -> (-x, -v)``, and the slowest mode is invariant under it:
``c_n(-x) = (-1)^n c_n(x)``.  The coefficients are then kept on the points ``x >= 0`` only
(``c_n(0) = 0`` for odd ``n``), which halves the blocks and cuts the work of the
elimination eightfold; the folded operator is the restriction ``R A F`` of the full one,
``F`` the extension by parity.

The rate is the smallest eigenvalue of ``-(A)`` in the metric that leaves out the pinned
rows (``c_n(+-L) = 0`` for ``n >= 2``): inverse iteration ``c <- A^{-1} K c``, which the gap
to the next decay rate (an intra-well relaxation, ``O(gamma)`` against the rate's
``exp(-E_b/kT)``) makes converge in a few solves; shift-invert Arnoldi on the same solves
when it does not.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["EscapeFraction", "parity_maps"]


def parity_maps(m: int, fold: bool) -> list:
    """``[(idx, F)]`` for even and odd Hermite orders: the points kept and the extension
    ``F`` (``m x len(idx)``) from them to all ``m`` points of a symmetric grid (decreasing,
    ``x_{m-1-i} = -x_i``), even for even orders and odd for odd ones; without ``fold``
    every point is kept and ``F`` is the identity."""
    if not fold:
        return [(np.arange(m), None), (np.arange(m), None)]
    nc = m - 1
    h = nc // 2
    out = []
    for sign in (1.0, -1.0):
        idx = np.arange(h + 1 if (sign > 0 and nc % 2 == 0) else (nc + 1) // 2)
        F = np.zeros((m, idx.size))
        F[idx, np.arange(idx.size)] = 1.0
        mirror = nc - idx
        F[mirror, np.arange(idx.size)] += sign * (mirror != idx)
        out.append((idx, F))
    return out


class EscapeFraction:
    """The escape matrix ``A = L_Kramers - kappa`` of a linearly damped model, factorised
    by elimination from the highest Hermite order down.

    Parameters
    ----------
    Dx : numpy.ndarray
        The differentiation matrix on the position points (``m x m``).
    g, kappa : numpy.ndarray
        The force ``G'`` and the sink at the points.
    sigma, gamma : float
        The Hermite scale ``sqrt(kT)`` and the friction.
    n_orders : int
        Hermite functions.
    fold : bool
        Keep ``x >= 0`` only (an even potential and sink on a symmetric grid).
    pinned : tuple of int
        Points whose rows are ``c_n = 0`` for ``n >= 2`` (the two ends).

    Raises
    ------
    numpy.linalg.LinAlgError
        When a Schur complement is singular.
    """

    def __init__(self, Dx, g, kappa, sigma: float, gamma: float, n_orders: int, fold: bool,
                 pinned=None):
        from scipy.linalg import blas, lapack

        m = Dx.shape[0]
        self.maps = parity_maps(m, fold)
        self.fold, self.n, self.gamma = bool(fold), int(n_orders), float(gamma)
        pinned = (0, m - 1) if pinned is None else pinned
        # per row parity: [unpinned, pinned] bases of the blocks (k, k + 1) / sqrt(k + 1)
        # and (k, k - 1) / sqrt(k) (Fortran order, for LAPACK and BLAS)
        self._up, self._lo, self._diag, self._pin = [], [], [], []
        for p in (0, 1):
            idx, _ = self.maps[p]
            Fq = self.maps[(1 - p) if fold else p][1]
            Dq = Dx[idx] if Fq is None else Dx[idx] @ Fq
            Gq = (np.diag(g) if Fq is None else g[:, None] * Fq)[idx]
            pin = np.flatnonzero(np.isin(idx, pinned))
            pair = []
            for B in (-sigma * Dq, -(sigma * Dq + Gq / sigma)):
                Bp = B.copy()
                Bp[pin] = 0.0
                pair.append((np.asfortranarray(B), np.asfortranarray(Bp)))
            self._up.append(pair[0])
            self._lo.append(pair[1])
            self._diag.append(np.asarray(kappa, float)[idx])
            self._pin.append(pin)
        self.sizes = [self.maps[self._par(k)][0].size for k in range(self.n)]
        self._lu = [None] * self.n
        S = self._D(self.n - 1)
        for k in range(self.n - 1, -1, -1):
            lu, piv, info = lapack.dgetrf(S, overwrite_a=True)
            if info != 0 or not np.all(np.isfinite(np.diagonal(lu))):
                raise np.linalg.LinAlgError("a singular Schur complement in the escape "
                                            f"matrix at Hermite order {k}")
            self._lu[k] = (lu, piv)
            if k == 0:
                break
            W, _ = lapack.dgetrs(lu, piv, self._lo[self._par(k)][k >= 2])
            # S_{k-1} = D_{k-1} - U_{k-1} S_k^{-1} L_k, U and L scalar multiples of the bases
            S = blas.dgemm(-float(k), self._up[self._par(k - 1)][k - 1 >= 2],
                           W, beta=1.0, c=self._D(k - 1), overwrite_c=True)

    def _par(self, k: int) -> int:
        return k % 2 if self.fold else 0

    def _U(self, k: int) -> np.ndarray:
        """Block ``(k, k + 1)``."""
        return math.sqrt(k + 1) * self._up[self._par(k)][k >= 2]

    def _L(self, k: int) -> np.ndarray:
        """Block ``(k, k - 1)``."""
        return math.sqrt(k) * self._lo[self._par(k)][k >= 2]

    def _D(self, k: int) -> np.ndarray:
        p = self._par(k)
        S = np.zeros((self._diag[p].size,) * 2, order="F")
        np.fill_diagonal(S, -(k * self.gamma) - self._diag[p])
        if k >= 2:
            pin = self._pin[p]
            S[pin, pin] = 1.0
        return S

    def keep(self) -> list:
        """The mass matrix's diagonal per order: 0 on the pinned rows."""
        out = [np.ones(s) for s in self.sizes]
        for k in range(2, self.n):
            out[k][self._pin[self._par(k)]] = 0.0
        return out

    def solve(self, rhs: list) -> list:
        """``A^{-1} rhs``, ``rhs`` a list of per-order vectors."""
        from scipy.linalg import lapack

        n, up, lo, par = self.n, self._up, self._lo, self._par
        red = [None] * n
        red[n - 1] = rhs[n - 1]
        for k in range(n - 2, -1, -1):
            y, _ = lapack.dgetrs(*self._lu[k + 1], red[k + 1])
            red[k] = rhs[k] - math.sqrt(k + 1) * (up[par(k)][k >= 2] @ y)
        out = [None] * n
        out[0], _ = lapack.dgetrs(*self._lu[0], red[0])
        for k in range(1, n):
            r = red[k] - math.sqrt(k) * (lo[par(k)][k >= 2] @ out[k - 1])
            out[k], _ = lapack.dgetrs(*self._lu[k], r)
        return out

    def slowest(self, tol: float = 1e-13, max_iter: int = 40, start=None) -> float:
        """The smallest decay rate ``-lambda`` of ``A c = lambda K c``: inverse iteration
        until the Rayleigh quotient of ``A^{-1} K`` changes by less than ``tol``;
        shift-invert Arnoldi when it does not settle.

        ``start``: a mode of another truncation on the same points (its orders padded with
        zeros or cut; the escape ladder's previous rung or the other sink: about three
        solves instead of seven), else the marginal ``c_0 = 1``.  The mode found is
        :attr:`mode`."""
        K = self.keep()
        x = [np.ones(s) if k == 0 else np.zeros(s) for k, s in enumerate(self.sizes)]
        if start is not None and all(a.shape == b.shape for a, b in zip(start, x)):
            x[:len(start)] = [np.array(a, float) for a in start[:self.n]]
        old = None
        for _ in range(max_iter):
            y = self.solve([a * b for a, b in zip(K, x)])
            theta = sum(float(a @ b) for a, b in zip(x, y)) / sum(float(a @ a) for a in x)
            norm = math.sqrt(sum(float(a @ a) for a in y))
            x = [a / norm for a in y]
            if old is not None and abs(theta - old) <= tol * abs(theta):
                self.mode = x
                return -1.0 / theta
            old = theta
        self.mode = None
        return self._arnoldi(K)

    def _arnoldi(self, K) -> float:
        import scipy.sparse.linalg as spla

        cuts = np.cumsum([0] + self.sizes)
        flat_k = np.concatenate(K)

        def matvec(v):
            v = flat_k * np.asarray(v).ravel()
            return np.concatenate(self.solve([v[cuts[k]:cuts[k + 1]] for k in range(self.n)]))

        op = spla.LinearOperator((cuts[-1], cuts[-1]), matvec=matvec, dtype=float)
        theta = spla.eigs(op, k=3, which="LM", return_eigenvectors=False, tol=1e-12)
        lam = 1.0 / theta
        return float(-lam[np.argsort(np.abs(lam))][0].real)
