"""The factorisation of the spectral-element Kramers matrix of :mod:`._elements` by static
condensation (:class:`CondensedLU`): every element's interior unknowns eliminated first,
independently of the other elements, then the interface system, block tridiagonal in the
interface nodes with dense ``N x N`` blocks (``N`` Hermite functions).

Why this order and not the order by order LU of :mod:`._pentadiagonal`.  Order by order,
each Hermite order's Schur complement is dense in all ``m`` points whatever the sparsity
in ``x``: ``8 N m^3`` operations.  Ordered by element, an element's interior (``q = p - 1``
points of degree ``p`` times ``N`` orders) couples only to its two end nodes; it is banded
in the Hermite index (orders ``n`` and ``n'`` meet only for ``|n - n'| <= b``, ``b = 2``
for a damping linear in the velocity), so it is eliminated in groups of ``b`` orders with
dense ``b q x b q`` blocks (a block tridiagonal LU from the top order down, as
:mod:`._pentadiagonal`, batched over the elements).  Its coupling to the end nodes is
``N`` columns per end, so the Schur complement of an element on its ends takes a solve
with ``2 N`` right-hand sides, ``12 b q^2 N^2`` operations, and the interface system
(``E - 1`` nodes of ``N`` unknowns) ``16 N^3`` per node (below): ``E (16 N^3 + 24 q^2 N^2)``
in all instead of ``8 N (E p)^3`` (Karniadakis and Sherwin, *Spectral/hp Element Methods*, 2nd
ed., sec. 4.2.3; Golub and Van Loan, *Matrix Computations*, 4th ed., sec. 4.5).

The interface system is factorised by LAPACK's band LU with partial pivoting
(``dgbtrf``, band ``2 N - 1`` either side: ``16 N^3`` operations per node where the block
LU without pivoting takes ``6 N^3``).  Without pivoting its Schur complements are those
of the half-line ``[-L, x_k]`` with every velocity of ``c(x_k, v)`` prescribed, which is
not well posed for a kinetic equation (only the incoming half of the velocities is): on
the SEDF at rest, mu = 0.1, D = 0.05, 256 functions on 56 elements of degree 11, their
pivots fell to 1e-16 of the largest, the solve's residual was 1e16 times the right-hand
side and ``<x^2>`` came out 2.33900 (not converged) against 2.3285219 pivoted; a
block LU eliminated toward the deepest well from both ends did no better.  Each
element alone is short enough: its order-group complements stay within ``||T^-1|| < 70``
there, so the interiors are eliminated without pivoting across groups.
"""

from __future__ import annotations

import numpy as np
from numpy.lib.stride_tricks import as_strided
from scipy.linalg.lapack import dgbtrf, dgbtrs

__all__ = ["CondensedLU"]


class CondensedLU:
    """The static-condensation LU of the element operator (module docstring).

    Parameters
    ----------
    inner : tuple of numpy.ndarray
        ``(Ad, Au, Al)``: the interior blocks of every element in groups of ``b`` orders,
        shapes ``(G, E, bq, bq)``, ``(G - 1, E, bq, bq)`` (group ``g`` to ``g + 1``) and
        ``(G - 1, E, bq, bq)`` (``g + 1`` to ``g``); the unknown ``(r, i)`` of a group is
        order ``g b + r`` at the element's interior point ``i``.
    couple_in : numpy.ndarray
        ``(G, bq, 2 N)``: the interior rows' coupling to the element's two end nodes
        (the same in every element), columns ``(side, n)``; the column ``(side, n)`` is
        nonzero only in the orders ``n - 1`` and ``n + 1``.
    couple_out : callable
        ``couple_out(y, els)``: the end rows' coupling to interior values ``y`` of shape
        ``(G, E', bq, R)`` of the elements ``els`` (a slice), returning ``(E', 2, N, R)``.
    ends : callable
        ``ends(els)``: the end nodes' own blocks of the elements ``els``,
        ``(E', 2 N, 2 N)``.
    band : int
        ``b``, the orders per group.
    chunk : int
        Elements whose end couplings are solved at once (memory: ``chunk`` times
        ``G bq 2 N`` numbers).
    first_pins : sequence of int, optional
        ``None`` (default): the node 0 is pinned whole, as the node ``E``; else the node 0
        is solved for but for these orders, pinned to 0 (the fold of :mod:`._parity` at
        ``x = 0``: the odd orders).
    """

    def __init__(self, inner, couple_in: np.ndarray, couple_out, ends, band: int,
                 chunk: int = 2, first_pins=None):
        Ad, Au, Al = inner
        G, E, bq, _ = Ad.shape
        N = couple_in.shape[-1] // 2
        self.E, self.G, self.bq, self.N, self.b = E, G, bq, N, int(band)
        self._couple_in, self._couple_out = couple_in, couple_out
        # the interiors: T_g from the top group down, kept as inverses
        tinv = np.empty_like(Ad)
        pk = np.empty_like(Au)  # Au[g - 1] T_g^-1, the forward sweep's factor
        t = Ad[G - 1].copy()
        for g in range(G - 1, -1, -1):
            tinv[g] = np.linalg.inv(t)
            if g == 0:
                break
            np.matmul(Au[g - 1], tinv[g], out=pk[g - 1])
            t = Ad[g - 1] - pk[g - 1] @ Al[g - 1]
        self._tinv, self._pk, self._al = tinv, pk, Al
        # the interface system of the nodes lo .. E - 1 in LAPACK's band storage
        lo = 1 if first_pins is None else 0
        kl = ku = 2 * N - 1
        self._kl, self._lo = kl, lo
        ab = np.zeros((2 * kl + ku + 1, (E - lo) * N), order="F")
        s0, s1 = ab.strides  # Fortran order: s0 the item, s1 the column

        def add(kr: int, kc: int, block: np.ndarray) -> None:
            """``A[node kr, node kc] += block`` (pinned nodes skipped): entry ``(n, n')``
            is ``ab[kl + ku + (kr - kc) N + n - n', (kc - lo) N + n']``, a view of ``ab``
            with strides ``(s0, s1 - s0)``."""
            if lo <= kr <= E - 1 and lo <= kc <= E - 1:
                start = ab[kl + ku + (kr - kc) * N:, (kc - lo) * N:]
                as_strided(start, (N, N), (s0, s1 - s0), writeable=True)[...] += block

        buf = np.empty((G, min(chunk, E), bq, 2 * N))
        for e0 in range(0, E, chunk):
            e1 = min(E, e0 + chunk)
            y = buf[:, :e1 - e0]
            y[...] = couple_in[:, None]
            self._interior(slice(e0, e1), y, triangular=True)
            S = ends(slice(e0, e1)) - couple_out(y, slice(e0, e1)).reshape(e1 - e0, 2 * N,
                                                                             2 * N)
            for j, e in enumerate(range(e0, e1)):
                for a in (0, 1):
                    for c in (0, 1):
                        add(e + a, e + c, S[j, a * N:(a + 1) * N, c * N:(c + 1) * N])
        del buf, y
        self._pins = np.asarray([] if first_pins is None else first_pins, int)
        for i in self._pins:  # the row and the column of a pinned order: the identity's
            for j in range(max(0, i - ku), min(ab.shape[1], i + kl + 1)):
                ab[kl + ku + i - j, j] = 0.0  # row i
            ab[kl:, i] = 0.0  # column i
            ab[kl + ku, i] = 1.0
        lu, piv, info = dgbtrf(ab, kl, ku, overwrite_ab=True)
        if info != 0:
            raise np.linalg.LinAlgError("a singular interface system in the element LU")
        self._band, self._piv = lu, piv

    def _interior(self, els: slice, rhs: np.ndarray, triangular: bool = False) -> None:
        """``rhs <- A_II^-1 rhs`` for the elements ``els``, ``rhs`` of shape
        ``(G, E', bq, R)``: the forward sweep from the top group, the back substitution
        up.  ``triangular``: ``rhs`` is :attr:`couple_in` (its column ``(side, n)`` is zero
        above the group of ``n + 1``, and stays zero there in the forward sweep)."""
        tinv, pk, al = self._tinv[:, els], self._pk[:, els], self._al[:, els]
        G, N, b = self.G, self.N, self.b
        flat = np.empty(rhs[0].size)  # the products' buffer (no new array per group)
        tmp = flat.reshape(rhs.shape[1:])
        for g in range(G - 1, 0, -1):
            if triangular:  # the columns n >= b g - 1 of each side
                n0 = max(0, b * g - 1)
                part = flat[:rhs[0, ..., :N - n0].size].reshape(rhs.shape[1:-1] + (N - n0,))
                for s in (0, N):
                    cols = slice(s + n0, s + N)
                    rhs[g - 1][..., cols] -= np.matmul(pk[g - 1], rhs[g][..., cols], out=part)
            else:
                rhs[g - 1] -= np.matmul(pk[g - 1], rhs[g], out=tmp)
        rhs[0] = np.matmul(tinv[0], rhs[0], out=tmp)
        for g in range(1, G):
            rhs[g] -= np.matmul(al[g - 1], rhs[g - 1], out=tmp)
            rhs[g] = np.matmul(tinv[g], rhs[g], out=tmp)

    def solve(self, inner_rhs: np.ndarray, node_rhs: np.ndarray):
        """The solution of the whole system for the interior right-hand sides
        ``(G, E, bq)`` and the nodes' ``(E + 1, N)`` (the pinned rows ignored: 0 there):
        ``(interior values (G, E, bq), node values (E + 1, N))``."""
        E, N = self.E, self.N
        y = np.array(inner_rhs, float)[..., None]
        self._interior(slice(None), y)
        r = np.array(node_rhs, float)
        out = self._couple_out(y, slice(None))[..., 0]  # (E, 2, N)
        r[:E] -= out[:, 0]
        r[1:] -= out[:, 1]
        z = np.zeros((E + 1, N))
        kl = self._kl
        lo = self._lo
        rhs = r[lo:E].reshape(-1, 1)
        rhs[self._pins] = 0.0
        sol, info = dgbtrs(self._band, kl, kl, rhs, self._piv)
        z[lo:E] = sol.reshape(E - lo, N)
        ends = np.concatenate([z[:E], z[1:]], axis=1)  # (E, 2N): each element's two ends
        G, bq = self.G, self.bq
        inner = np.array(inner_rhs, float) - (self._couple_in.reshape(G * bq, 2 * N)
                                              @ ends.T).reshape(G, bq, E).transpose(0, 2, 1)
        inner = inner[..., None]
        self._interior(slice(None), inner)
        return inner[..., 0], z
