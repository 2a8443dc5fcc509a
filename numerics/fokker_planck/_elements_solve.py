"""One stationary Kramers solve on spectral elements (:func:`element_stationary`; the
discretisation in :mod:`._elements`, its factorisation in :mod:`._elements_lu`), the
solution's class (:class:`ElementKramersSolution`: ``<x^2>``, ``<v^2>``, ``<a^2>`` and the
mass below an energy as :class:`._stationary_solve.OrthonormalKramersSolution`), and
:func:`element_kramers`, the same solve from a model's name with the velocity scale, the
range and the centres of the points that the present ladder chooses
(:mod:`._stationary_orthonormal`, steps 1 to 3)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ._blocks import on_one_blas_thread, one_blas_thread
from ._elements import ElementOperator, element_edges, element_nodes, gll
from ._hermite_functions import hermite_integrals
from ._stationary_solve import OrthonormalKramersSolution

__all__ = ["ElementKramersSolution", "element_stationary", "element_kramers", "element_sizes"]


@dataclass(frozen=True, eq=False, repr=False)
class ElementKramersSolution(OrthonormalKramersSolution):
    """:class:`._stationary_solve.OrthonormalKramersSolution` on the nodes of spectral
    elements (:attr:`x` descending from ``L``, :attr:`weights` the assembled GLL weights):
    the moments and :meth:`mass_below` as there, the values between the nodes by each
    element's Lagrange polynomial.  ``P(E)`` by :meth:`energy_density`
    (:mod:`._energy_quadrature`) on each element's piece of a stretch (:meth:`pieces`),
    the even orders' values by :meth:`even_order_values`."""

    degree: int = 0
    edges: tuple = ()

    def __repr__(self) -> str:
        return (f"ElementKramersSolution(<x^2> = {self.x2:.10g}, <v^2> = {self.v2:.10g}; "
                f"{self.coef.shape[0]} Hermite x {len(self.edges) - 1} elements of degree "
                f"{self.degree})")

    #: the first Gauss-Legendre rule of ``P(E)`` on each element's piece of a stretch
    #: (:func:`._energy_quadrature.energy_density`; the integrand there is a polynomial of
    #: the degree times a smooth function of ``x``)
    quadrature_nodes = 16

    def _lagrange(self, xs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(lag, idx)``: the Lagrange weights ``(len(xs), p + 1)`` of each position on its
        element's GLL nodes (barycentric form) and those nodes' indices in ascending
        order."""
        p, edges = self.degree, np.asarray(self.edges)
        r, _, _ = gll(p)
        bary = 1.0 / np.prod(np.where(np.eye(p + 1, dtype=bool), 1.0,
                                      r[:, None] - r[None, :]), axis=1)
        e = np.clip(np.searchsorted(edges, xs, side="right") - 1, 0, edges.size - 2)
        a, b = edges[e], edges[e + 1]
        t = (2 * xs - a - b) / (b - a)
        d = t[:, None] - r[None, :]
        hit = d == 0
        d[hit] = 1.0
        lag = bary / d
        lag = np.where(hit.any(axis=1)[:, None], hit.astype(float), lag)
        lag /= lag.sum(axis=1, keepdims=True)
        return lag, e[:, None] * p + np.arange(p + 1)[None, :]

    def values(self, xs) -> np.ndarray:
        """``c_n`` at the positions ``xs`` (rows ``n``), by the Lagrange polynomial of the
        element holding each (barycentric form on its GLL nodes)."""
        xs = np.atleast_1d(np.asarray(xs, float))
        lag, idx = self._lagrange(xs)
        asc = self.coef[:, ::-1]  # ascending nodes
        return np.einsum("nkj,kj->nk", asc[:, idx], lag)

    def even_order_values(self, xs) -> np.ndarray:
        """``c_n`` of the even orders (columns) at the positions ``xs`` (rows), as
        :meth:`values` (one sparse product: what
        :func:`._energy_quadrature.even_order_values` is for one Chebyshev grid)."""
        import scipy.sparse as sps

        xs = np.atleast_1d(np.asarray(xs, float))
        lag, idx = self._lagrange(xs)
        if "even" not in self._cache:
            self._cache["even"] = np.ascontiguousarray(self.coef[::2, ::-1].T)
        V = self._cache["even"]
        S = sps.csr_matrix((lag.ravel(), idx.ravel(), np.arange(0, lag.size + 1, lag.shape[1])),
                           shape=(xs.size, V.shape[0]))
        return S @ V

    def pieces(self, E: float) -> list:
        """The stretches of :meth:`._solution.KramersSolution.stretches` cut at the ends of
        the elements, the ranges of ``P(E)``'s rules (:mod:`._energy_quadrature`): the
        values are piecewise polynomials, and one Gauss-Legendre rule across an element's
        end converges only algebraically (as :meth:`_stretch` cuts them for
        :meth:`mass_below`)."""
        edges = np.asarray(self.edges)
        out = []
        for a, b in self.stretches(E):
            cuts = [a, *edges[(edges > a) & (edges < b)].tolist(), b]
            out.extend(zip(cuts[:-1], cuts[1:]))
        return out

    def _series(self):
        return None

    def _stretch(self, coefs, E: float, a: float, b: float, n: int) -> float:
        """The mass of ``H < E`` over ``a < x < b``, element by element (the values are
        piecewise polynomials: one Gauss-Legendre rule across an element's end converges
        only algebraically), ``max(8, n/4)`` nodes in ``x = (u + w)/2 + (w - u)/2
        sin(pi s/2)`` on each piece ``(u, w)`` (the square-root ends at ``a``, ``b``
        become smooth)."""
        edges = np.asarray(self.edges)
        cuts = np.concatenate([[a], edges[(edges > a) & (edges < b)], [b]])
        t, w = np.polynomial.legendre.leggauss(max(8, n // 4))
        u, v = cuts[:-1, None], cuts[1:, None]
        xs = (0.5 * (u + v) + 0.5 * (v - u) * np.sin(0.5 * np.pi * t)).ravel()
        jac = (0.25 * np.pi * (v - u) * np.cos(0.5 * np.pi * t) * w).ravel()
        U = np.sqrt(np.maximum(2 * (E - self.G(xs)), 0.0)) / self.sigma
        c = self.values(xs)
        return float(np.sum(jac * np.sum(c * self._band(c.shape[0], U), axis=0)))


@on_one_blas_thread
def element_stationary(split, D: float, s: float, half: float, nh: int, elements: int,
                       degree: int, G, omega0: float, *, alpha: float = 0.95, centres=(),
                       widths=(), weight=0.0, iterations: int = 8, rtol: float = 1e-14,
                       chunk: int = 2, fold: bool | None = None) -> ElementKramersSolution:
    """One stationary solve in ``nh`` orthonormal Hermite functions of ``v/s`` times
    ``elements`` spectral elements of degree ``degree`` on ``[-half, half]``
    (:mod:`._elements`; the ends of the elements by :func:`._elements.element_edges` with
    ``alpha``, ``centres``, ``widths``, ``weight`` as :func:`._bases.cheb_centred`), every
    ``c_n(+-half) = 0``: inverse iteration ``A c_new = W c`` from the Maxwellian
    ``exp(-G/s^2)`` in ``h_0``, each solve by :class:`._elements_lu.CondensedLU` with one
    step of iterative refinement, until the normalised coefficients change by less than
    ``rtol`` (at most ``iterations`` solves).  The residual is ``|lambda_0|``.
    ``fold`` (default: whenever :func:`._parity.reflection_symmetric` holds on the nodes)
    solves on the elements of ``x >= 0`` only, the odd orders 0 at ``x = 0``, the
    equations there those of the element on the right (:mod:`._parity`: the density is
    even under ``(x, v) -> (-x, -v)``; half the work)."""
    from ._orthonormal import orthonormal_terms
    from ._parity import reflection_symmetric

    E, p = element_sizes((elements, degree), nh)
    edges = element_edges(E, half, alpha, centres, widths, weight)
    x, W = element_nodes(edges, p)
    if fold is None:
        fold = reflection_symmetric(split, x[::-1])
    if fold:  # x >= 0: the odd orders vanish at x = 0 (._parity), the node 0 is x = 0
        edges = edges[E // 2:]
        xs, Ws = element_nodes(edges, p)
        pins, ends = np.arange(1, nh, 2), [-1]
    else:
        xs, Ws, pins, ends = x, W, None, [0, -1]
    terms = orthonormal_terms(split, D, s, xs, None, nh)
    Gx = np.asarray(G(xs), float)
    mass, _ = hermite_integrals(nh)
    with one_blas_thread():
        op = ElementOperator(terms, edges, p, xs)
        lu = op.factor(chunk, pins)

        def pin(c):
            c[:, ends] = 0.0
            if fold:
                c[1::2, 0] = 0.0
            return c

        c = np.zeros((nh, xs.size))
        c[0] = np.exp(-(Gx - Gx.min()) / s**2)
        c = pin(c)
        c /= float(Ws @ (mass @ c))
        lam = last = math.nan
        for _ in range(iterations):
            new = refined_solve(op, lu, pin, c * Ws)
            norm = float(Ws @ (mass @ new))
            new /= norm
            lam = 1.0 / norm
            last = float(np.max(np.abs(new - c))) / float(np.max(np.abs(new)))
            c = new
            if last <= rtol:
                break
    if fold:  # c_n(-x) = (-1)^n c_n(x), the half weights doubled but at x = 0
        sign = np.where(np.arange(nh) % 2 == 0, 1.0, -1.0)[:, None]
        c = np.concatenate([sign * c[:, :0:-1], c], axis=1)
        edges = np.concatenate([-edges[:0:-1], edges])
        c /= 2.0  # the half's mass was normalised to 1
    return ElementKramersSolution(
        x[::-1].copy(), W[::-1].copy(), c[:, ::-1].copy(), s, G, float(omega0), abs(lam),
        alpha=float(alpha), centres=tuple(map(float, centres)),
        widths=tuple(map(float, widths)), iteration_change=last,
        weight=float(weight) if np.ndim(weight) == 0 else tuple(map(float, weight)),
        degree=p, edges=tuple(map(float, edges)))


def refined_solve(op, lu, pin, r: np.ndarray) -> np.ndarray:
    """``A^-1 r`` by the factors ``lu`` of ``op`` (:class:`._elements.ElementOperator`,
    :class:`._elements_lu.CondensedLU`) with one step of iterative refinement, the residual
    pinned by ``pin`` (the boundary and fold conditions): the solve of the stationary
    inverse iteration here and of the escape's shift-invert (:mod:`._escape_elements`)."""
    x = op.join(*lu.solve(*op.split(r)))
    return x + op.join(*lu.solve(*op.split(pin(r - op.matvec(x)))))


def element_sizes(elements, n_hermite) -> tuple[int, int]:
    """``(E, p)`` from ``elements = (E, p)``, checked with ``n_hermite``.

    Raises
    ------
    kbm.errors.ParameterError
        Unless ``E`` is even and at least 2 (``x = 0`` an interface node), ``p`` odd and
        at least 3 (:mod:`._elements`: an even degree makes each element's interior
        derivative singular) and ``n_hermite`` at least 2."""
    from kbm.errors import ParameterError

    try:
        E, p = (int(v) for v in elements)
    except (TypeError, ValueError):
        raise ParameterError(f"elements = {elements!r}: give (number of elements, "
                             "degree), e.g. (100, 13)") from None
    if E < 2 or E % 2:
        raise ParameterError(f"elements: {E} elements; give an even number >= 2 (x = 0 "
                             "is then an interface node)")
    if p < 3 or p % 2 == 0:
        raise ParameterError(f"elements: degree {p}; give an odd degree >= 3 (an even one "
                             "makes each element's interior derivative singular)")
    if n_hermite is None or int(n_hermite) < 2:
        raise ParameterError(f"n_hermite = {n_hermite}: the element solve needs the number "
                             "of Hermite functions (>= 2), e.g. n_hermite=258")
    return E, p


def element_kramers(model, params: dict | None, D: float, *, n_hermite: int, elements: int,
                    degree: int, sigma: float | None = None, L: float | None = None,
                    well: bool = True, omega0: float | None = None,
                    **kw) -> ElementKramersSolution:
    """:func:`element_stationary` of a model at rest with the range ``L``
    (:func:`._model._half_width`), the velocity scale and the centres of the points of
    :func:`._stationary_points.stationary_points` (from the pilot solve of
    :func:`._stationary_orthonormal.stationary_orthonormal`, 32 functions; with ``well``
    the deepest well's centre too, as the ladder's last rungs), unless ``sigma`` and ``L``
    are given; ``model`` a name with its ``params``, or a split model
    (:func:`kbm.model.conservative.split_conservative`) with ``params`` ``None``;
    ``omega0`` by default the model's (else ``g'(0)^(1/2)``); ``kw`` go to
    :func:`element_stationary`."""
    import sympy as sp

    from kbm.model.conservative import split_conservative
    from ._model import _chebyshev_size, _half_width
    from ._stationary_orthonormal import FIRST_HERMITE, MIN_INTERVALS
    from ._stationary_points import ALPHA, stationary_points
    from ._stationary_solve import orthonormal_stationary

    split = model if params is None else split_conservative(
        model, {k: v for k, v in dict(params).items() if k != "D"})
    mu = float(split.mu)
    G = split.numpy_functions()[2]
    if omega0 is None:
        w0 = sp.sympify(split.model.omega0).subs({sp.Symbol(k): v
                                                  for k, v in split.params.items()})
        omega0 = float(w0) if w0.is_number else math.sqrt(float(split.numpy_functions()[1](
            np.array(0.0))))
    half = _half_width(G, D / mu) if L is None else float(L)
    v2 = math.nan  # the pilot's <v^2> sets the scale only when none is given
    if sigma is None:
        nc = max(MIN_INTERVALS, 2 * math.ceil(_chebyshev_size(G, D / mu, half) / 4))
        v2 = orthonormal_stationary(split, D, math.sqrt(D / mu), half, FIRST_HERMITE, nc, G,
                                    omega0, alpha=ALPHA).v2
    s, points = stationary_points(split, D, G, half, v2, sigma, well=well)
    return element_stationary(split, D, s, half, n_hermite, elements, degree, G, omega0,
                              **points, **kw)
