"""The solves of the escape ladder for linear damping (:func:`.escape.kramers_escape`): one
factorisation per position grid and sink, extended up the Hermite ladder, and each rate's
inverse iteration started from the last mode found (on another grid: interpolated).

The elimination of :class:`._fraction.EscapeFraction` runs upward, so the rung of ``N``
Hermite functions reuses the factors of every smaller rung: the ladder costs the
factorisation of its largest truncation and a few solves per rung, where the ladder from the
top down factorised every rung anew.  One factorisation is kept at a time (the memory).
"""

from __future__ import annotations

import numpy as np

from ._blocks import one_blas_thread
from ._fraction import EscapeFraction
from ._ladder import hermite_chebyshev_ladder
from ._parity import parity_maps, symmetric

__all__ = ["FractionRungs", "chebyshev_interpolation", "pair_escape"]

#: the storage of a factorisation, in units of its need: the next grid of the ladder (1.2
#: times the intervals, about 1.44 times the numbers per order) then fits into it when its
#: Hermite capacity is no larger (the top rung's at mu = 0.02: 2896 x 158^2 into 4096 x
#: 132^2), so the three factorisations of the escape (ladder, grid, sink) share one set of
#: pages (Linux maps pages when first written: the slack is address space only)
SLACK = 1.5


def chebyshev_interpolation(n_from: int, n_to: int) -> np.ndarray:
    """The matrix (``n_to + 1`` by ``n_from + 1``) of polynomial interpolation from the
    Chebyshev-Gauss-Lobatto points ``cos(pi j/n_from)`` to ``cos(pi i/n_to)`` (the
    barycentric formula, Berrut and Trefethen, SIAM Rev. 46 (2004) 501, eq. 5.2; weights
    ``(-1)^j``, halved at the ends).  A map ``x(t)`` shared by both grids
    (:func:`._bases.cheb_centred`) leaves it unchanged."""
    t0 = np.cos(np.pi * np.arange(n_from + 1) / n_from)
    t1 = np.cos(np.pi * np.arange(n_to + 1) / n_to)
    w = (-1.0) ** np.arange(n_from + 1)
    w[[0, -1]] *= 0.5
    diff = t1[:, None] - t0[None, :]
    hit = np.abs(diff) < 1e-15
    with np.errstate(divide="ignore", invalid="ignore"):
        P = w / diff
        P /= P.sum(axis=1, keepdims=True)
    rows = hit.any(axis=1)
    P[rows] = hit[rows].astype(float)
    return P


class FractionRungs:
    """The escape rate of linear damping at ``(n Hermite functions, nc intervals, sink)``,
    the factorisations shared along the ladder.

    Parameters
    ----------
    split : kbm.model.conservative.ConservativeSplit
    sigma, gamma : float
        The Hermite scale ``sqrt(kT)`` and the friction.
    wells : (float, float)
        The sink's centres.
    half : float
        The half-width of the range.
    sink : callable
        ``sink(xs, sharp)``: the sink at the points (``sharp`` 1 or 2).
    points : callable
        ``points(nc)``: ``(x, D)``, the ``nc + 1`` points (decreasing, symmetric for an
        even potential) and their differentiation matrix, one map of the Chebyshev points
        for every ``nc`` (:func:`._bases.cheb_centred`), so a mode moves from one grid to
        another by polynomial interpolation in the Chebyshev variable.
    """

    def __init__(self, split, sigma: float, gamma: float, wells, sink, points):
        self.g = split.numpy_functions()[0]
        self.sigma, self.gamma, self.wells = sigma, gamma, wells
        self.sink, self.points = sink, points
        self._key, self._frac = None, None
        self._modes = {}  # nc -> (fold, mode): the last slowest mode on each grid

    def _factor(self, n: int, nc: int, sharp: int, capacity: int) -> EscapeFraction:
        if self._key == (nc, sharp):
            if n > self._frac.n:
                self._frac.extend(n)
            return self._frac
        xs, Dx = self.points(nc)
        g = np.asarray(self.g(xs), float)
        fold = symmetric(g, self.wells)
        cap = max(n, capacity, 2)
        mm = parity_maps(nc + 1, fold)[0][0].size
        # the last factors' pages hold the new ones when large enough, else they are freed
        # before the next factorisation (the memory) and the new storage has room for a
        # grid 1.2 times as fine (pages untouched cost nothing)
        buffer = None if self._frac is None else self._frac.storage()
        if buffer is not None and buffer.size < cap * mm * mm:
            buffer = None
        self._key, self._frac = None, None
        if buffer is None:
            buffer = np.zeros(int(SLACK * cap * mm * mm))
        self._frac = EscapeFraction(Dx, g, self.sink(xs, sharp), self.sigma, self.gamma, n,
                                    fold, capacity=cap, buffer=buffer)
        del buffer
        self._key = (nc, sharp)
        return self._frac

    def _start(self, nc: int, frac: EscapeFraction):
        """The last mode on ``nc``, else the last on another grid interpolated to it."""
        if nc in self._modes:
            return self._modes[nc][1]
        if not self._modes:
            return None
        nc0, (fold, mode) = next(reversed(self._modes.items()))
        if fold != frac.fold:
            return None
        P = chebyshev_interpolation(nc0, nc)
        maps0 = parity_maps(nc0 + 1, fold)
        out = []
        for k, c in enumerate(mode):
            p = k % 2 if fold else 0
            F = maps0[p][1]
            full = c if F is None else F @ c
            out.append((P @ full)[frac.maps[p][0]])
        return out

    def rate(self, n: int, nc: int, sharp: int = 1, capacity: int = 0) -> float:
        """The slowest decay rate with ``n`` Hermite functions on ``nc`` intervals (the
        sharper sink for ``sharp = 2``); ``capacity``: the largest ``n`` to come on this
        grid (room held for it)."""
        with one_blas_thread():
            frac = self._factor(n, nc, sharp, capacity)
            rate = frac.slowest(n=n, start=self._start(nc, frac))
        if frac.mode is not None:
            self._modes.pop(nc, None)
            self._modes[nc] = (frac.fold, frac.mode)
        return rate


def pair_escape(split, sigma: float, gamma: float, wells, sink, points, ladder, *, start: int,
                n_cheb: int, tol: float, max_hermite: int, max_cheb: int,
                max_cost: float) -> dict:
    """The Hermite and Chebyshev ladders of :func:`.escape.kramers_escape` in Risken's pair
    (``basis="pair"``): the truncation grows by ``sqrt 2`` from ``start`` (``ladder(start,
    stop)``, :func:`._problem.hermite_ladder`) until two successive rates agree to ``tol``,
    then the rate at the top rung on 1.2 times the intervals (:func:`._model.grid_check`;
    when it moves by more than ``tol`` the ladder runs again there) and one rung below with
    ``sink(xs, 2)`` (the loop of :func:`._ladder.hermite_chebyshev_ladder`).  One :class:`FractionRungs` factorisation per grid and sink, extended
    up the ladder; the factors keep ``n m^2`` numbers at most ``3 max_cost`` (``m`` the
    points, about ``n_cheb/2`` folded).

    Returns
    -------
    dict
        The fields of :class:`.escape.KramersEscape` but ``saddles`` and ``wells``.
    """
    nc = int(n_cheb)
    memo = {}
    folds = abs(wells[0] + wells[1]) <= 1e-12 * wells[1]  # about: EscapeFraction decides

    def cost(n, nc):  # in the budget's units: a third of the numbers kept
        m = nc // 2 + 1 if folds else nc + 1
        return n * m * m / 3

    def fits(n, nc):
        m = nc // 2 + 1 if folds else nc + 1
        return n * m * m <= 3 * max_cost

    rungs = FractionRungs(split, sigma, gamma, wells, sink, points)

    def solve(n, nc, sharp=1):
        if (n, nc, sharp) not in memo:
            top = max([r for r in ladder(n, int(max_hermite)) if fits(r, nc)], default=n)
            memo[n, nc, sharp] = rungs.rate(n, nc, sharp, capacity=top)
        return memo[n, nc, sharp]

    out = hermite_chebyshev_ladder(solve, ladder, fits, start=start, n_cheb=nc, tol=tol,
                                   max_hermite=max_hermite, max_cheb=max_cheb, cost=cost,
                                   budget=max_cost)
    del out["check_error"]
    return out
