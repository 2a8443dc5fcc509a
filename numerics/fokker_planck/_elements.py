"""The stationary Kramers equation in orthonormal Hermite functions of the velocity times
spectral ELEMENTS in the position (:func:`element_stationary`): a second discretisation
in ``x`` of the Galerkin-Hermite formulation of :mod:`._stationary_solve`, factorised by
static condensation (:mod:`._elements_lu`) instead of order by order.

The scheme.  ``[-L, L]`` is cut into ``E`` elements; on each, ``c_n(x)`` is the polynomial
of degree ``p`` through its Gauss-Lobatto-Legendre (GLL) nodes, continuous across the
elements (the shared end nodes): the continuous-Galerkin spectral element method with the
GLL quadrature (Karniadakis and Sherwin, *Spectral/hp Element Methods*, 2nd ed., ch. 4;
Deville, Fischer and Mund, *High-Order Methods for Incompressible Fluid Flow*, ch. 2).
Every equation of :func:`._orthonormal.orthonormal_terms` is projected on the same
piecewise polynomials with the GLL rule, so the mass matrix is diagonal (the GLL weights,
assembled), the derivative is ``Q = W D`` per element (``D`` the GLL differentiation
matrix) and the functions of ``x`` (force, friction) are diagonal.

Why Galerkin and not a multi-domain collocation.  The ``x``-equation of the Hermite
orders is a first-order symmetric hyperbolic system, ``-s X dc/dx`` with ``X`` the
symmetric multiplication by ``xi``.  With the GLL rule ``Q + Q^T = diag(-1, 0, .., 0, 1)``
exactly (summation by parts: the rule is exact for the degree ``2p - 1`` of
``phi_i phi_j'``), so after assembly the transport term is skew but for the two ends of
``[-L, L]``, as the continuous one is: the symmetric part of the discrete operator is that
of the velocity operator alone (bounded above by half the largest friction,
:mod:`._orthonormal`), so no spurious growing mode in ``x``, and the scheme needs no
interface conditions (continuity is built in) and no upwinding (which would couple all
Hermite orders at every interface through the characteristic decomposition of ``X``).
The error is spectral in ``p`` on each element (the density is analytic).

The degree is odd.  An element's interior block of ``Q`` is skew (summation by parts),
and a skew matrix of odd order is singular: with ``p`` even the ``p - 1`` interior points
make the transport part of each element's interior singular, and its elimination
(:mod:`._elements_lu`) fails (SEDF at rest, mu = 0.01, D = 0.005, 258 functions, degree
12: the largest ``||T^-1||`` of the order groups 5e11 and <x^2> 2.15133 on 100 elements
against 2.1574351; degree 11: at most 225, and 2.1574351).

Spurious eigenvalues.  With more Hermite functions than the elements resolve the
truncated operator has eigenvalues that are not the Kramers operator's (SEDF at rest,
mu = 0.1, D = 0.05, 256 functions on 56 elements of degree 11: ``+0.051`` and
``-0.0028 +- 0.0248 i`` beside ``lambda_0`` = 1e-16, where 182 functions give none
within 0.07); inverse iteration still finds ``lambda_0`` (<x^2> 2.328521859 either
way), but the functions and the elements are refined together.

Where the elements go.  Their ends are uniform in the coordinate of the map of
:func:`._bases.cheb_centred` (the Bayliss-Turkel ``psi`` on top of the Kosloff-Tal-Ezer
coordinate, the same centres, widths and weights that the present ladder chooses,
:func:`._stationary_points.stationary_points`), so the saddles, the separatrices' turning
points and the well get small elements.  The ends ``x = +-L`` are pinned to 0 (every
order), as the Chebyshev solve pins them.

The stationary density is the eigenvector of the truncated operator nearest 0, by inverse
iteration from the Maxwellian in ``exp(-G/s^2)`` as
:func:`._stationary_solve.orthonormal_stationary` (generalised: ``A c = lambda W c`` with
the diagonal mass ``W``; :mod:`._elements_solve`).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sps

from ._elements_lu import CondensedLU
from ._workspace import empty

__all__ = ["gll", "element_edges", "element_nodes", "ElementOperator"]


def gll(p: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(r, w, D)``: the ``p + 1`` Gauss-Lobatto-Legendre nodes on ``[-1, 1]`` (ascending),
    their weights ``2/(p (p + 1) P_p(r)^2)`` and the differentiation matrix
    ``D_ij = P_p(r_i)/(P_p(r_j) (r_i - r_j))``, ``D_00 = -p (p + 1)/4 = -D_pp``
    (Newton's iteration on ``(1 - r^2) P_p'(r)`` from the Chebyshev-Lobatto points)."""
    if p < 2:
        raise ValueError(f"degree {p}: at least 2")
    r = -np.cos(np.pi * np.arange(p + 1) / p)
    for _ in range(100):
        P = np.zeros((p + 1, p + 1))
        P[:, 0], P[:, 1] = 1.0, r
        for k in range(2, p + 1):
            P[:, k] = ((2 * k - 1) * r * P[:, k - 1] - (k - 1) * P[:, k - 2]) / k
        step = (r * P[:, p] - P[:, p - 1]) / ((p + 1) * P[:, p])
        r = r - step
        if np.max(np.abs(step)) < 1e-16:
            break
    Lp = P[:, p]
    w = 2.0 / (p * (p + 1) * Lp**2)
    dr = r[:, None] - r[None, :]
    np.fill_diagonal(dr, 1.0)
    D = Lp[:, None] / Lp[None, :] / dr
    np.fill_diagonal(D, 0.0)
    D[0, 0], D[p, p] = -p * (p + 1) / 4.0, p * (p + 1) / 4.0
    return r, w, D


def element_edges(E: int, L: float, alpha: float = 0.95, centres=(), widths=(),
                  weight=0.0) -> np.ndarray:
    """The ``E + 1`` ends of the elements on ``[-L, L]`` (ascending): uniform in the
    coordinate ``s`` of :func:`._bases.cheb_centred`'s map (``x`` solves
    ``phi(x) = s``; without centres ``x = L s``), symmetric about 0 when the centres are."""
    s = np.linspace(-1.0, 1.0, E + 1)
    c, w = np.asarray(centres, float), np.asarray(widths, float)
    q = np.broadcast_to(np.asarray(weight, float), c.shape)

    def psi(x):
        return x / L + (q * np.arctan((x[..., None] - c) / w)).sum(axis=-1)

    lo, hi = psi(np.array([-L, L]))
    target = lo + (s + 1) * (hi - lo) / 2
    a, b = np.full_like(s, -L), np.full_like(s, L)
    for _ in range(64):  # bisection to the last bit (deterministic)
        mid = 0.5 * (a + b)
        up = psi(mid) < target
        a, b = np.where(up, mid, a), np.where(up, b, mid)
    x = 0.5 * (a + b)
    if sorted(zip(c, w, q)) == sorted(zip(-c, w, q)):
        x = 0.5 * (x - x[::-1])
    x[0], x[-1] = -L, L
    return x


def element_nodes(edges: np.ndarray, p: int) -> tuple[np.ndarray, np.ndarray]:
    """``(x, W)``: the ``E p + 1`` global nodes (ascending; the ends of the elements shared)
    and their assembled GLL weights (the diagonal mass)."""
    r, w, _ = gll(p)
    a, b = edges[:-1, None], edges[1:, None]
    loc = 0.5 * (a + b) + 0.5 * (b - a) * r  # (E, p + 1)
    E = edges.size - 1
    x = np.empty(E * p + 1)
    x[:-1] = loc[:, :p].reshape(-1)
    x[-1] = edges[-1]
    W = np.zeros(E * p + 1)
    for k in range(p + 1):
        W[k:k + E * p:p] += 0.5 * (b[:, 0] - a[:, 0]) * w[k]
    return x, W


def _band(terms) -> int:
    """The largest distance of two Hermite orders coupled by any term (at least 1)."""
    out = 1
    for H, _ in terms:
        coo = sps.coo_matrix(H)
        keep = coo.data != 0
        if keep.any():
            out = max(out, int(np.max(np.abs(coo.row - coo.col)[keep])))
    return out


class ElementOperator:
    """The element matrices of ``sum_j kron(H_j, X_j)`` (``X_j`` the derivative ``Q`` or a
    function of ``x`` times the weights), its matrix-vector product on ``c`` of shape
    ``(N, E p + 1)`` and its :class:`._elements_lu.CondensedLU`.

    Parameters
    ----------
    terms : list of (scipy.sparse matrix, numpy.ndarray or None)
        :func:`._orthonormal.orthonormal_terms` at the nodes ``x`` with the derivative
        given as ``None`` (its one term with ``X = None``).
    edges : numpy.ndarray
        The ``E + 1`` ends of the elements, ascending (:func:`element_edges`).
    p : int
        The degree.
    x : numpy.ndarray
        The nodes of :func:`element_nodes`.
    """

    def __init__(self, terms, edges: np.ndarray, p: int, x: np.ndarray):
        _, w, Dr = gll(p)
        E, N = edges.size - 1, sps.csr_matrix(terms[0][0]).shape[0]
        self.E, self.p, self.N, self.x = E, p, N, x
        h = 0.5 * np.diff(edges)
        Q = w[:, None] * Dr  # W D on the reference element: the same on every element
        b = _band(terms)
        G = -(-N // b)
        q = p - 1
        self.b, self.G, self.q = b, G, q
        idx = np.arange(E)[:, None] * p + np.arange(p + 1)  # (E, p + 1) global nodes
        self._idx = idx
        deriv = [sps.csr_matrix(H) for H, X in terms if X is None]
        diag = [(sps.csr_matrix(H), np.asarray(X, float)) for H, X in terms if X is not None]
        if len(deriv) != 1:
            raise ValueError("one derivative term (X = None) expected")
        HD = deriv[0]
        self._HD, self._diag, self._Q = HD, diag, Q
        # the mass-weighted functions at each element's nodes: h_e w_k f_j(x)
        wx = h[:, None] * w[None, :]
        F = [(H, X[idx] * wx) for H, X in diag]
        # the global sparse derivative (assembled W D), for the matrix-vector product
        rows = (idx[:, :, None] + 0 * idx[:, None, :]).reshape(-1)
        cols = (idx[:, None, :] + 0 * idx[:, :, None]).reshape(-1)
        M = E * p + 1
        self._Qg = sps.csr_matrix((np.broadcast_to(Q, (E, p + 1, p + 1)).reshape(-1),
                                   (rows, cols)), shape=(M, M))
        self._Wf = [(H, np.bincount(idx.reshape(-1), (X[idx] * wx).reshape(-1), M))
                    for H, X in diag]

        def grouped(H):
            Hp = np.zeros((G * b, G * b))
            Hp[:N, :N] = sps.csr_matrix(H).toarray()
            H4 = Hp.reshape(G, b, G, b)
            g = np.arange(G - 1)
            return H4[np.arange(G), :, np.arange(G), :], H4[g, :, g + 1, :], H4[g + 1, :, g, :]

        QI = Q[1:p, 1:p]
        ar = np.arange(q)
        blocks = []
        for k in range(3):  # groups first: a group's blocks of all elements contiguous
            gd = grouped(HD)[k]
            gf = [(grouped(H)[k], f[:, 1:p]) for H, f in F]
            out = empty((gd.shape[0], E, b, q, b, q))  # rows (r, i), columns (s, j)
            view = out.transpose(0, 1, 2, 4, 3, 5)  # (group, element, r, s, i, j)
            base = np.einsum("grs,ij->grsij", gd, QI)
            for g in range(gd.shape[0]):  # a group at a time: no temporary of all
                view[g] = base[g]
                for Hg, fi in gf:
                    view[g][..., ar, ar] += np.einsum("rs,ei->ersi", Hg[g], fi)
                if k == 0:  # the padded orders beyond N: identity (decoupled)
                    for n in range(max(N, g * b), (g + 1) * b):
                        view[g][:, n % b, n % b, ar, ar] = 1.0
            blocks.append(out.reshape(gd.shape[0], E, b * q, b * q))
        self.inner = tuple(blocks)
        # interior rows to the two ends: H_D[n, n'] Q[i, end]
        HDp = np.zeros((G * b, N))
        HDp[:N] = HD.toarray()
        cols = np.stack([Q[1:p, 0], Q[1:p, p]])  # (2, q)
        cin = np.einsum("nm,si->nism", HDp, cols)  # (G b, q, 2, N)
        self.couple_in = cin.reshape(G, b, q, 2 * N).reshape(G, b * q, 2 * N)
        self._rows = np.stack([Q[0, 1:p], Q[p, 1:p]])  # the ends' rows to the interior
        self._F = F
        self._coo = []  # (rows, cols, values) of H_D and of each function's H
        for H in [HD] + [H for H, _ in F]:
            coo = sps.coo_matrix(H)
            coo.sum_duplicates()
            self._coo.append((coo.row, coo.col, coo.data))
        # H_D by its diagonals: entry n of diagonal d is H_D[n, n + d]
        offsets = np.unique(sps.coo_matrix(HD).col - sps.coo_matrix(HD).row)
        self._hd_diagonals = []
        for d in offsets:
            v = np.zeros(N)
            dv = HD.diagonal(int(d))
            if d >= 0:
                v[:dv.size] = dv
            else:
                v[-d:] = dv
            self._hd_diagonals.append((int(d), v))

    def ends(self, els: slice) -> list:
        """The end nodes' own blocks of the elements ``els``: ``[(a, c, rows, cols,
        vals)]``, the entries ``vals`` ``(E', nnz)`` at ``(rows, cols)`` of the block from
        the end ``c`` to the end ``a`` (``Q[k_a, k_c] H_D``, and on ``a = c`` the functions
        of ``x`` at that end times their ``H``)."""
        Q, p = self._Q, self.p
        E = len(range(self.E)[els])
        r, c, v = self._coo[0]
        out = []
        for a, ka in enumerate((0, p)):
            for t, kt in enumerate((0, p)):
                out.append((a, t, r, c, np.broadcast_to(Q[ka, kt] * v, (E, v.size))))
            for (hr, hc, hv), (_, f) in zip(self._coo[1:], self._F):
                out.append((a, a, hr, hc, f[els, ka, None] * hv[None]))
        return out

    def matvec(self, c: np.ndarray) -> np.ndarray:
        """The Galerkin operator (mass-weighted rows) on ``c`` ``(N, E p + 1)``."""
        out = (self._HD @ c) @ self._Qg.T
        for H, wf in self._Wf:
            out += (H @ c) * wf
        return out

    def split(self, c: np.ndarray):
        """``c`` ``(N, E p + 1)`` as (interior ``(G, E, bq)``, nodes ``(E + 1, N)``)."""
        E, p, G, b, q, N = self.E, self.p, self.G, self.b, self.q, self.N
        inner = np.zeros((G * b, E, q))
        inner[:N] = c[:, self._idx[:, 1:p]]
        inner = inner.reshape(G, b, E, q).transpose(0, 2, 1, 3)
        return np.ascontiguousarray(inner).reshape(G, E, b * q), np.ascontiguousarray(c[:, ::p].T)

    def join(self, inner: np.ndarray, nodes: np.ndarray) -> np.ndarray:
        """The inverse of :meth:`split`."""
        E, p, N = self.E, self.p, self.N
        c = np.empty((N, E * p + 1))
        c[:, ::p] = nodes.T
        q, b = self.q, self.b
        full = inner.reshape(self.G, E, b, q).transpose(0, 2, 1, 3).reshape(-1, E, q)
        c[:, self._idx[:, 1:p]] = full[:N]
        return c

    def factor(self, chunk: int = 2, first_pins=None) -> CondensedLU:
        """:class:`._elements_lu.CondensedLU` of the operator (``first_pins`` there), once:
        the interior blocks are factorised in place and dropped from :attr:`inner`."""
        if self.inner is None:
            raise RuntimeError("ElementOperator.factor: the blocks were factorised already")
        inner, self.inner = self.inner, None
        return CondensedLU(inner, self.couple_in, (self._rows, self._hd_diagonals),
                           self.ends, self.b, chunk, first_pins)
