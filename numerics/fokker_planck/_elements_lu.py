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
``N`` columns per end, nonzero in the orders ``n +- 1`` only, so the Schur complement of an
element on its ends takes a solve with ``2 N`` right-hand sides: the sweep down the groups
(``T_g^-1`` and the coupling to the next group) only on the columns ``n >= b g - 1`` that
are not yet zero, the sweep up on all, ``8 b q^2 N^2`` operations, then the end rows
(``q`` points per order, two orders) on the result.  The interface system (``E - 1`` nodes
of ``N`` unknowns) takes ``28/3 N^3`` per node (below): ``E (28/3 N^3 + 8 b q^2 N^2)`` in
all instead of ``8 N (E p)^3`` (Karniadakis and Sherwin, *Spectral/hp Element Methods*, 2nd
ed., sec. 4.2.3; Golub and Van Loan, *Matrix Computations*, 4th ed., sec. 4.5).

The interface system is factorised by the LU with partial pivoting of the block
tridiagonal matrix (Golub and Van Loan, sec. 4.3, band LU with pivoting): node ``k``'s
``N`` columns hold nonzeros in the rows of the nodes ``k`` and ``k + 1`` only, so each step
is LAPACK's ``dgetrf`` on that ``2 N x N`` panel, its row interchanges applied to those
rows' columns of the nodes ``k + 1`` and ``k + 2`` (the interchanges fill the second),
``dtrsm`` for the rows of ``U`` and one ``dgemm`` for node ``k + 1``'s rows:
``10/3 + 2 + 4 = 28/3 N^3`` operations per node.  Its pivots are searched among the same
rows as those of LAPACK's band LU ``dgbtrf`` with ``2 N - 1`` sub- and superdiagonals (the
factorisation before: about ``16 N^3`` per node on a band array of ``6 N^2`` numbers per
node, where the blocks keep ``4 N^2``).  Without pivoting its Schur complements are those
of the half-line ``[-L, x_k]`` with every velocity of ``c(x_k, v)`` prescribed, which is
not well posed for a kinetic equation (only the incoming half of the velocities is): on
the SEDF at rest, mu = 0.1, D = 0.05, 256 functions on 56 elements of degree 11, their
pivots fell to 1e-16 of the largest, the solve's residual was 1e16 times the right-hand
side and ``<x^2>`` came out 2.33900 (not converged) against 2.3285219 pivoted; a block LU
eliminated toward the deepest well from both ends did no better.  Each element alone is
short enough: its order-group complements stay within ``||T^-1|| < 70`` there, so the
interiors are eliminated without pivoting across groups.

Memory and time.  The elements' right-hand sides are kept transposed, ``(R, b q)`` per
group (the long side first: OpenBLAS ran ``(2 N x 24) (24 x 24)`` products about 1.4 times
as fast as ``(24 x 24) (24 x 2 N)``), in one buffer for ``chunk`` elements; the products
write into preallocated arrays, the interior blocks are factorised in place and the
interface blocks are assembled where they are factorised: new memory costs page faults,
system time (on this machine's VM about 3 s per GB touched the first time).  One solve of
:func:`._elements_solve.element_stationary` at the SEDF at rest, Delta = 3, folded (user
and system CPU, peak memory; before: the band LU ``dgbtrf``; interleaved, load 4-5):
mu = 0.005, 512 x 176 elements: 10.5-12.1 s + 2.6-3.6 s, 1.39 GB (before 15.5-16.8 s +
7.0-7.2 s, 1.96 GB); mu = 0.01, 364 x 100: 3.0-3.4 s + 0.6-0.9 s, 0.61 GB (3.8-4.2 s +
1.3-1.4 s, 0.81 GB); 258 x 80: 1.3-1.4 s + 0.1-0.7 s, 0.39 GB (1.7-1.8 s + 0.7-1.2 s,
0.48 GB).  The moments agree with the band LU's to 5e-16 and the coefficients to 3e-15.
The whole ``kbm noise sedf -p mu=0.005 -p Delta=3 -p beta=1 -p D=0.0025 --method
fokker-planck --trajectories 8 --t-end 40 --json`` (its element ladder ends at 512 x 176):
55 s user + 14 s system, 48 s wall, 1.70 GB (before 78 s + 25 s, 74 s, 2.33 GB; load 1.5).
Within the element ladder the largest arrays (the interiors' blocks, the interface blocks,
``y`` and ``z`` here) come from the buffer of :mod:`._workspace`, cheaper to touch and
reused by the next solve: 512 x 240 alone 15.2 s + 1.3 s against 14.9 s + 4.3 s fresh.
"""

from __future__ import annotations

import numpy as np
from scipy.linalg.blas import dgemm, dtrsm, dtrsv
from scipy.linalg.lapack import dgetrf

from ._workspace import empty, zeros

__all__ = ["CondensedLU"]


def _swaps(piv: np.ndarray, m: int) -> np.ndarray:
    """The row order ``perm`` of LAPACK's interchanges ``piv`` (0-based, applied in turn):
    row ``i`` of ``P A`` is row ``perm[i]`` of ``A``."""
    perm = np.arange(m)
    for i, j in enumerate(piv.tolist()):
        perm[i], perm[j] = perm[j], perm[i]
    return perm


class CondensedLU:
    """The static-condensation LU of the element operator (module docstring).

    Parameters
    ----------
    inner : tuple of numpy.ndarray
        ``(Ad, Au, Al)``: the interior blocks of every element in groups of ``b`` orders
        (``Ad`` and ``Al`` are overwritten by the factors), shapes ``(G, E, bq, bq)``,
        ``(G - 1, E, bq, bq)`` (row group ``g``, column group ``g + 1``) and
        ``(G - 1, E, bq, bq)`` (row ``g + 1``, column ``g``); the unknown ``(r, i)`` of a
        group is order ``g b + r`` at the element's interior point ``i``.
    couple_in : numpy.ndarray
        ``(G, bq, 2 N)``: the interior rows' coupling to the element's two end nodes
        (the same in every element), columns ``(side, n)``; the column ``(side, n)`` is
        nonzero only in the orders ``n - 1`` and ``n + 1``.
    couple_out : tuple
        ``(rows, diagonals)``: the end rows' coupling to the interior, ``H[n, m]
        rows[side, i]`` from order ``m`` at interior point ``i`` to order ``n`` at the end
        ``side``; ``rows`` of shape ``(2, q)``, ``H`` by its diagonals ``[(d, v)]``,
        ``H[n, n + d] = v[n]``.
    ends : callable
        ``ends(els)``: the end nodes' own blocks of the elements ``els`` (a slice) as a
        list of ``(a, c, rows, cols, vals)``, ``vals`` of shape ``(E', nnz)`` added at
        ``(rows, cols)`` of the block from the end ``c`` to the end ``a``.
    band : int
        ``b``, the orders per group.
    chunk : int
        Elements whose end couplings are solved at once (memory: ``chunk`` times
        ``G bq 2 N`` numbers; the same bits for any ``chunk``).
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
        b = int(band)
        self.E, self.G, self.bq, self.N, self.b = E, G, bq, N, b
        rows, self._diagonals = couple_out
        # the end rows per group, transposed: (r, i) -> (r, side)
        self._pick = np.kron(np.eye(b), np.asarray(rows, float).T)  # (bq, 2 b)
        # C_in transposed, its columns interleaved: row 2 n + side of cin[g]
        self._cin = np.ascontiguousarray(
            couple_in.reshape(G, bq, 2, N).transpose(0, 3, 2, 1).reshape(G, 2 * N, bq))
        # the interiors from the top group down, in place of the blocks (they are
        # consumed): Ad[g] <- T_g^-T, Al[g - 1] <- -(T_g^-1 A[g, g - 1])^T; Au kept
        t = Ad[G - 1].copy()
        for g in range(G - 1, -1, -1):
            ti = np.linalg.inv(t)
            Ad[g] = ti.swapaxes(-1, -2)
            if g == 0:
                break
            mg = np.matmul(ti, Al[g - 1])
            Al[g - 1] = -mg.swapaxes(-1, -2)
            np.subtract(Ad[g - 1], np.matmul(Au[g - 1], mg, out=t), out=t)
        self._tinv, self._m = Ad, Al
        self._au = Au.swapaxes(-1, -2)  # A[g - 1, g]^T, a view
        # the interface system of the nodes lo .. E - 1 by blocks
        lo = 1 if first_pins is None else 0
        nn = E - lo
        self._lo, self._nn = lo, nn
        # per node k, every block transposed (the elements' Schur complements come so):
        # _lu[k] is D_k^T, then LAPACK's LU of the panel's top in _lu[k].T; _l21[k] is
        # A[k + 1, k]^T, then L's rows below in _l21[k].T; _u12[k][:N] is A[k, k + 1]^T,
        # then U's rows right of the diagonal block in _u12[k].reshape(N, 2 N)
        self._lu = zeros((nn, N, N))  # (from the ladder's buffer, ._workspace)
        self._l21 = zeros((nn, N, N))
        self._u12 = zeros((nn, 2 * N, N))
        chunk = max(1, min(int(chunk), E))
        y = empty((G, chunk, 2 * N, bq))
        self._work = np.empty((chunk, 2 * N, bq))
        z = empty((chunk, 2 * N, G * b, 2))
        tmp = np.empty((N, N))
        for e0 in range(0, E, chunk):
            e1 = min(E, e0 + chunk)
            ys, zs = y[:, :e1 - e0], z[:e1 - e0]
            self._interior(slice(e0, e1), ys, zs, triangular=True)
            for j, e in enumerate(range(e0, e1)):
                self._schur(e, zs[j].reshape(N, 2, G * b, 2), tmp)
            for a, c, r, s, vals in ends(slice(e0, e1)):
                for j, e in enumerate(range(e0, e1)):
                    self._ends(e, a, c, r, s, vals[j])
        del y, z, tmp, ys, zs
        self._pins = np.asarray([] if first_pins is None else first_pins, int)
        if self._pins.size:  # the row and the column of a pinned order: the identity's
            i = self._pins
            self._lu[0][:, i] = 0.0
            self._lu[0][i, :] = 0.0
            self._lu[0][i, i] = 1.0
            self._u12[0][:N, i] = 0.0
            self._l21[0][i, :] = 0.0
        self._factor()

    def _node(self, e: int) -> int:
        """The index of node ``e`` among the unknown nodes (-1: pinned)."""
        return e - self._lo if self._lo <= e <= self.E - 1 else -1

    def _schur(self, e: int, Z: np.ndarray, tmp: np.ndarray) -> None:
        """Subtract element ``e``'s ``C_out A_II^-1 C_in`` from the interface blocks;
        ``Z[n', c, m, a]``: the end ``a``'s rows of order ``m`` on the column ``(c, n')``
        (before ``H``).  Block ``(a, c)`` transposed: ``[n', n] = sum_d v_d[n]
        Z[n', c, n + d, a]``."""
        N = self.N
        k0, k1 = self._node(e), self._node(e + 1)
        targets = []
        if k0 >= 0:
            targets.append((0, 0, self._lu[k0]))  # D^T
        if k1 >= 0:
            targets.append((1, 1, self._lu[k1]))
        if k0 >= 0 and k1 >= 0:
            targets.append((0, 1, self._u12[k0][:N]))  # A[e, e + 1]^T
            targets.append((1, 0, self._l21[k0]))  # A[e + 1, e]^T
        for a, c, out in targets:
            for d, v in self._diagonals:
                n0, n1 = max(0, -d), min(N, N - d)
                part = tmp[:, :n1 - n0]
                np.multiply(Z[:, c, n0 + d:n1 + d, a], v[n0:n1], out=part)
                out[:, n0:n1] -= part

    def _ends(self, e: int, a: int, c: int, r, s, vals) -> None:
        """Add the end block ``(a, c)`` of element ``e`` (its entries ``vals`` at
        ``(r, s)``)."""
        k0, k1 = self._node(e), self._node(e + 1)
        if a == c:
            k = k0 if a == 0 else k1
            if k >= 0:
                self._lu[k][s, r] += vals
        elif k0 >= 0 and k1 >= 0:
            (self._u12[k0][:self.N] if a == 0 else self._l21[k0])[s, r] += vals

    def _factor(self) -> None:
        """The block LU with partial pivoting of the interface system (module
        docstring), in place of its blocks."""
        N, nn = self.N, self._nn
        self._perm = []
        pan = np.empty((2 * N, N), order="F")
        # the rows of the nodes k and k + 1 on the columns of k + 1 and k + 2, in C order
        # (row interchanges are contiguous copies; BLAS works on their transposes)
        rr, r2 = np.empty((2 * N, 2 * N)), np.empty((2 * N, 2 * N))
        rr[:N, :N] = self._u12[0][:N].T
        for k in range(nn):
            if k == nn - 1:
                lu, piv, info = dgetrf(self._lu[k].T, overwrite_a=1)
                if info < 0 or not np.shares_memory(lu, self._lu[k]):
                    raise RuntimeError("dgetrf did not factorise in place")
                self._check(info)
                self._perm.append(_swaps(piv, N))
                break
            pan[:N] = self._lu[k].T
            pan[N:] = self._l21[k].T
            lu, piv, info = dgetrf(pan, overwrite_a=1)
            if info < 0 or not np.shares_memory(lu, pan):
                raise RuntimeError("dgetrf did not factorise in place")
            self._check(info)
            perm = _swaps(piv, 2 * N)
            self._perm.append(perm)
            self._lu[k].T[...] = pan[:N]
            self._l21[k].T[...] = pan[N:]
            rr[:N, N:] = 0.0
            rr[N:, :N] = self._lu[k + 1].T
            rr[N:, N:] = self._u12[k + 1][:N].T
            np.take(rr, perm, axis=0, out=r2)
            # U's rows: L11^-1 (top rows), as (top)^T L11^-T
            u = dtrsm(1.0, self._lu[k].T, r2[:N].T, side=1, lower=1, trans_a=1, diag=1,
                      overwrite_b=1)
            # node k + 1's rows less L21 U, as (bottom)^T - U^T L21^T
            w = dgemm(-1.0, r2[:N].T, self._l21[k].T, beta=1.0, c=r2[N:].T, trans_b=1,
                      overwrite_c=1)
            if not (np.shares_memory(u, r2) and np.shares_memory(w, r2)):
                raise RuntimeError("dtrsm/dgemm did not work in place")
            self._u12[k].reshape(N, 2 * N)[...] = r2[:N]
            self._lu[k + 1].T[...] = r2[N:, :N]
            rr[:N, :N] = r2[N:, N:]

    @staticmethod
    def _check(info: int) -> None:
        if info != 0:
            raise np.linalg.LinAlgError("a singular interface system in the element LU")

    def _interior(self, els: slice, y: np.ndarray, z: np.ndarray,
                  triangular: bool = False) -> None:
        """``y <- A_II^-1 y`` for the elements ``els``, ``y`` of shape ``(G, E', R, bq)``
        (the right-hand sides transposed: row ``j`` of ``y[g, e]`` is column ``j``), and
        the end rows' values ``z`` ``(E', R, G b, 2)``: ``z[e, j, m, side]`` the sum over
        the interior points of order ``m`` with ``rows[side]``.  The sweep down from the top
        group (``T_g^-1``, then the coupling to the group below), the sweep up.
        ``triangular``: ``y`` is set here, group by group, to the interleaved ``C_in^T``
        (:attr:`_cin`): its rows ``2 n + side`` are zero in the groups above that of
        ``n + 1`` and stay zero there in the sweep down."""
        tinv, au, m = self._tinv[:, els], self._au[:, els], self._m[:, els]
        G, b = self.G, self.b
        R = y.shape[2]
        tmp = self._work if R == self._work.shape[1] and y.shape[1] <= self._work.shape[0] \
            else np.empty(y.shape[1:])
        tmp = tmp[:y.shape[1]]
        flat = z.reshape(-1, G * b * 2)

        def first(g: int) -> int:  # the first row not known to be zero in group g
            return max(0, 2 * (b * g - 1)) if triangular else 0

        if triangular:
            y[G - 1][:, first(G - 1):] = self._cin[G - 1][first(G - 1):]
        for g in range(G - 1, -1, -1):  # down: T_g^-1, the group below less A[g - 1, g] z_g
            c = first(g)
            x, part = y[g][:, c:], tmp[:, c:]
            x[...] = np.matmul(x, tinv[g], out=part)
            if g and triangular:  # rows below first(g - 1) never read: left as they are
                y[g - 1][:, first(g - 1):c] = self._cin[g - 1][first(g - 1):c]
                np.subtract(self._cin[g - 1][c:], np.matmul(x, au[g - 1], out=part),
                             out=y[g - 1][:, c:])
            elif g:
                y[g - 1] -= np.matmul(x, au[g - 1], out=part)
        for g in range(G):  # up: x_g = z_g + x_{g - 1} (-M_g)^T, z_g zero above first(g)
            if g:
                c = first(g)
                np.matmul(y[g - 1][:, :c], m[g - 1], out=y[g][:, :c])
                y[g][:, c:] += np.matmul(y[g - 1][:, c:], m[g - 1], out=tmp[:, c:])
            np.matmul(y[g].reshape(-1, self.bq), self._pick,
                      out=flat[:, 2 * b * g:2 * b * (g + 1)])

    def _apply_h(self, z: np.ndarray) -> np.ndarray:
        """``(H z)[e, n, side] = sum_d v_d[n] z[e, n + d, side]`` for ``z`` of shape
        ``(E', G b, 2)``: ``(E', N, 2)``."""
        N = self.N
        out = np.zeros(z.shape[:1] + (N, 2))
        for d, v in self._diagonals:
            n0, n1 = max(0, -d), min(N, N - d)
            out[:, n0:n1] += v[n0:n1, None] * z[:, n0 + d:n1 + d]
        return out

    def solve(self, inner_rhs: np.ndarray, node_rhs: np.ndarray):
        """The solution of the whole system for the interior right-hand sides
        ``(G, E, bq)`` and the nodes' ``(E + 1, N)`` (the pinned rows ignored: 0 there):
        ``(interior values (G, E, bq), node values (E + 1, N))``."""
        E, N, G, b, lo, nn = self.E, self.N, self.G, self.b, self._lo, self._nn
        inner_rhs = np.asarray(inner_rhs, float)
        y = inner_rhs[:, :, None, :].copy()
        z = np.empty((E, 1, G * b, 2))
        self._interior(slice(None), y, z)
        out = self._apply_h(z[:, 0])  # (E, N, 2): each element's two ends
        full = np.array(node_rhs, float)
        full[:E] -= out[:, :, 0]
        full[1:] -= out[:, :, 1]
        r = np.zeros((nn + 2, N))  # two rows of zeros: no node k + 1, k + 2 at the end
        r[:nn] = full[lo:E]
        r[0, self._pins] = 0.0
        for k in range(nn):  # L
            m = 2 * N if k < nn - 1 else N
            seg = r[k:k + 2].reshape(-1)[:m]
            seg[:] = seg[self._perm[k]]
            r[k] = dtrsv(self._lu[k].T, r[k], lower=1, diag=1, overwrite_x=1)
            if k < nn - 1:
                r[k + 1] -= self._l21[k].T @ r[k]
        for k in range(nn - 1, -1, -1):  # U
            if k < nn - 1:
                r[k] -= self._u12[k].reshape(N, 2 * N) @ r[k + 1:k + 3].reshape(-1)
            r[k] = dtrsv(self._lu[k].T, r[k], lower=0, diag=0, overwrite_x=1)
        nodes = np.zeros((E + 1, N))
        nodes[lo:E] = r[:nn]
        ends = np.stack([nodes[:E], nodes[1:]], axis=-1).reshape(E, 2 * N)  # (n, side)
        y = (inner_rhs - np.matmul(ends[None], self._cin))[:, :, None, :]
        self._interior(slice(None), y, z)
        return y[:, :, 0, :], nodes
