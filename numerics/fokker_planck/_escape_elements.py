"""The escape rate's rungs on spectral elements (:class:`ElementRungs`): the ``slowest`` of
:func:`._orthonormal.nonlinear_escape` at low friction, where the saddle layer's points
make the Chebyshev blocks of :class:`._folded.FoldedRungs` dear.

The discretisation is the stationary route's (:mod:`._elements`: orthonormal Hermite
functions of the velocity times continuous-Galerkin spectral elements in ``x`` with the
Gauss-Lobatto-Legendre rule, factorised by static condensation, :mod:`._elements_lu`) with
the escape's sink as one more function of ``x`` and the parity fold of
:mod:`._parity` (``x >= 0``, the odd orders 0 at ``x = 0``); the rate is the smallest
``|lambda|`` of ``A c = lambda W c`` (``W`` the GLL mass) by shift-invert Arnoldi at 0.

Why.  The Chebyshev blocks of the folded escape are dense in the ``m`` points, so a rung
costs ``N m^3`` operations and keeps ``2 N m^2`` numbers; ``m`` follows the layer's width
``l`` in ``x`` (``2.2 L/l`` intervals) and ``N`` the layer's width in ``v``, both like
``mu^(-1/2)``.  An element couples only its neighbours: ``E (28/3 N^3 + ...)`` operations
and about :data:`WORDS` ``N^2`` numbers per folded element.  CDC Delta = 3, D = 0.2 mu,
mu = 0.002 (docs/noise-escape.rst): the ladder to 362 functions on 122 elements of degree
9 (the layer's 1094 intervals) took 21 s of CPU and 0.59 GB, 9.3e-8 from the converged
rate (512 x 240: 1e-10 from 724), where the Chebyshev ladder stopped at 128 functions by
the budget with a rate 5.8 times too large (the truncation's error: 128 functions on
elements give the same).
"""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sps

from ._blocks import one_blas_thread
from ._elements import ElementOperator, element_edges, element_nodes
from ._elements_solve import refined_solve
from ._orthonormal import orthonormal_terms

__all__ = ["ElementRungs", "DEGREE", "WORDS"]

#: the elements' degree (odd: :mod:`._elements`)
DEGREE = 9
#: numbers kept per ``N^2`` and folded element (the interface LU's ``4 N^2`` and the
#: elements' solves; 362 functions on 61 folded elements peaked at 0.62 GB with Python's
#: 0.15, about 58 bytes, as the stationary route's 60, :mod:`._elements_ladder`)
WORDS = 7.5


class ElementRungs:
    """The escape's slowest decay rate on spectral elements, called as
    :func:`._orthonormal.orthonormal_slowest` (the ``points`` argument unused): ``nc``
    intervals give ``E = nc/DEGREE`` elements (rounded up to even), their ends uniform in
    the map of :func:`._elements.element_edges` with the saddles' ``centres``, ``widths``
    and ``weights``.

    Parameters
    ----------
    half : float
        The half-width of the range (every order 0 at ``+-half``).
    centres, widths, weights : tuple of float
        Where the elements crowd (symmetric about 0).
    degree : int
        Odd.
    """

    def __init__(self, half: float, centres, widths, weights, degree: int = DEGREE):
        self.half, self.degree = float(half), int(degree)
        self.centres, self.widths, self.weights = tuple(centres), tuple(widths), tuple(weights)

    def elements(self, nc: int) -> int:
        """The elements on ``nc`` intervals: ``nc/degree`` rounded up to even."""
        return max(2, 2 * math.ceil(int(nc) / (2 * self.degree)))

    def numbers(self, nh: int, nc: int) -> float:
        """The numbers one rung keeps: :data:`WORDS` ``N^2`` per folded element."""
        return WORDS * nh * nh * self.elements(nc) / 2

    def __call__(self, split, D: float, s: float, points, nh: int, nc: int, sink) -> float:
        """The smallest decay rate in ``nh`` orthonormal Hermite functions of ``v/s`` on the
        elements of ``nc`` intervals with the sink ``sink(xs)``."""
        import scipy.sparse.linalg as spla

        E, p = self.elements(nc), self.degree
        edges = element_edges(E, self.half, 0.95, self.centres, self.widths, self.weights)
        edges = edges[E // 2:]
        xs, W = element_nodes(edges, p)
        terms = orthonormal_terms(split, D, s, xs, None, nh)
        terms.append((-sps.identity(nh, format="csr"), np.asarray(sink(xs), float)))
        with one_blas_thread():
            op = ElementOperator(terms, edges, p, xs)
            lu = op.factor(2, np.arange(1, nh, 2))

            def pin(c):  # x = half pinned; the odd orders at x = 0 (the fold)
                c[:, -1] = 0.0
                c[1::2, 0] = 0.0
                return c

            size = nh * xs.size
            inv = spla.LinearOperator(
                (size, size), dtype=float,
                matvec=lambda v: refined_solve(op, lu, pin,
                                               pin(v.reshape(nh, -1) * W)).reshape(-1))
            v0 = np.zeros((nh, xs.size))
            v0[0] = 1.0
            theta = spla.eigs(inv, k=1, ncv=6, which="LM", return_eigenvectors=False,
                              tol=1e-12, v0=pin(v0).reshape(-1))
        return float(-(1.0 / theta[0]).real)
