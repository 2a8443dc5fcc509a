"""The stationary density of the Kramers equation in Hermite-Chebyshev form
(:class:`KramersSolution`, what :func:`.kramers.stationary_kramers` returns): its moments,
the marginal of ``x`` and the mass below an energy, hence ``P(E)``."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ._bases import band_masses
from ._blocks import one_blas_thread

__all__ = ["KramersSolution", "moments_moved"]


@dataclass(frozen=True, eq=False)
class KramersSolution:
    """The stationary density of the Kramers equation in Hermite-Chebyshev form.

    Attributes
    ----------
    x, weights : numpy.ndarray
        Chebyshev points on ``[-L, L]`` and their Clenshaw-Curtis weights.
    coef : numpy.ndarray
        ``c_n(x_i)``, shape ``(N, len(x))``; ``P = sum c_n phi_n(v/sigma)/sigma`` in
        Risken's pair (``basis == "risken"``); in the orthonormal functions ``h_n`` for
        :class:`._stationary_solve.OrthonormalKramersSolution` (``basis ==
        "orthonormal"``, a nonlinear damping), whose marginal is ``sum m_n c_n``.
    sigma : float
        The velocity scale of the Hermite functions.
    G : callable
        The potential.
    omega0 : float
        The linear frequency of ``a^2 = x^2 + (x'/omega0)^2``.
    residual : float
        Largest coefficient of the last Hermite order and of the last Chebyshev modes,
        relative to the largest (the truncation's size).
    hermite_change : float
        The largest relative change of ``<x^2>`` and ``<v^2>`` when the number of Hermite
        functions was last doubled (the truncation's error as measured, what
        :func:`.kramers.stationary_kramers` stops on); ``nan`` when the number was given,
        ``0`` for linear damping (where ``sigma^2 = kT`` makes the Maxwellian one function).
        For a nonlinear damping (orthonormal Hermite functions,
        :mod:`._stationary_orthonormal`) the larger of that change and
        :attr:`chebyshev_change`.
    chebyshev_change : float
        The relative change of ``<x^2>`` and ``<v^2>`` when the Chebyshev intervals last
        grew (nonlinear damping; ``nan`` when not measured).
    refinements : tuple
        The pairs ``(coarse, fine)`` of solutions whose change of the moments is the stated
        error (the Hermite and the Chebyshev step of the ladders; empty when not kept): the
        same change of ``P(E)`` is its stated error
        (:func:`._energy_density.energy_density_change`).
    refine : callable or None
        The same solve on one grid step more (1.25 times the intervals, the same functions
        and points), called by :func:`._energy_density.energy_density_report` for ``P(E)``
        (whose grid error is larger than the moments'); ``None`` when not kept.
    """

    x: np.ndarray
    weights: np.ndarray
    coef: np.ndarray
    sigma: float
    G: object
    omega0: float
    residual: float
    hermite_change: float = math.nan
    chebyshev_change: float = math.nan
    refinements: tuple = field(default=(), repr=False, compare=False)
    refine: object = field(default=None, repr=False, compare=False)
    _cache: dict = field(default_factory=dict, repr=False, compare=False)

    def __repr__(self) -> str:
        return (f"KramersSolution(<x^2> = {self.x2:.10g}, <v^2> = {self.v2:.10g}; "
                f"{self.coef.shape[0]} Hermite x {self.x.size} Chebyshev)")

    @property
    def x2(self) -> float:
        """``<x^2>``."""
        return float(np.sum(self.weights * self.x**2 * self.coef[0]))

    basis = "risken"

    @property
    def v2(self) -> float:
        """``<v^2> = sigma^2 int (c_0 + sqrt(2) c_2) dx``."""
        return float(self.sigma**2 * np.sum(self.weights * (self.coef[0]
                                                            + math.sqrt(2) * self.coef[2])))

    @property
    def a2(self) -> float:
        """``<a^2> = <x^2> + <v^2>/omega0^2``."""
        return self.x2 + self.v2 / self.omega0**2

    def marginal(self) -> np.ndarray:
        """The density of ``x`` at the points :attr:`x`."""
        return self.coef[0].copy()

    def mass_below(self, E: float, nodes: int = 64) -> float:
        """The probability of ``H = v^2/2 + G(x) < E``.

        The inner integral over ``v`` is exact in the Hermite functions
        (:func:`numerics.fokker_planck._bases.band_masses`); the outer one runs over the
        stretches where ``G < E`` with the substitution that removes the square-root ends.
        """
        coefs = self._series()
        total = 0.0
        for a, b in self.stretches(E):
            n, last = nodes, None
            while True:  # Gauss-Legendre doubled until two rules agree
                val = self._stretch(coefs, E, a, b, n)
                if last is not None and (abs(val - last) <= 1e-13 or n >= 4096):
                    break
                last, n = val, 2 * n
            total += val
        return total

    def stretches(self, E: float) -> list:
        """The intervals ``(a, b)`` of ``[-L, L]`` where ``G < E`` (their ends by Brent's
        method from a 4097-point grid of ``G``, computed once), the ranges of the outer
        integrals of :meth:`mass_below` and of ``P(E)``."""
        L = float(self.x[0])
        if "grid" not in self._cache:
            grid = np.linspace(-L, L, 4097)
            self._cache["grid"] = (grid, np.asarray(self.G(grid), float))
        grid, Gg = self._cache["grid"]
        inside = Gg < E
        if not inside.any():
            return []
        edges = np.flatnonzero(np.diff(inside.astype(int)))
        starts = ([0] if inside[0] else []) + [i + 1 for i in edges if not inside[i]]
        ends = [i for i in edges if inside[i]] + ([grid.size - 1] if inside[-1] else [])
        return [(_root(self.G, E, grid[i0 - 1], grid[i0]) if i0 > 0 else -L,
                 _root(self.G, E, grid[i1], grid[i1 + 1]) if i1 < grid.size - 1 else L)
                for i0, i1 in zip(starts, ends)]

    def _series(self) -> np.ndarray:
        """Chebyshev coefficients of every ``c_n`` on ``[-L, L]`` (from the values at the
        Gauss-Lobatto points by the discrete cosine transform; computed once).  The product
        on one BLAS thread: OpenBLAS's ``dgemm`` splits the matrix among its threads, and
        the split changes the last bits (SEDF mu = 0.1, Delta = 3, D = 0.05: ``P(E)`` of
        ``kbm noise --json`` moved by up to 2.5e-14, its stated change by 1e-9 relative,
        between 1 and 2 threads), so the bytes would depend on the thread count."""
        if "series" not in self._cache:
            n = self.x.size - 1
            k = np.arange(n + 1)
            w = np.where((k == 0) | (k == n), 0.5, 1.0)
            T = np.cos(np.pi * np.outer(k, k) / n) * w[None, :]
            with one_blas_thread():
                c = (2.0 / n) * (T @ self.coef.T)
            c[0] /= 2
            c[n] /= 2
            self._cache["series"] = c
        return self._cache["series"]

    def _stretch(self, coefs, E: float, a: float, b: float, n: int) -> float:
        """The mass of ``H < E`` over ``a < x < b`` with ``n`` Gauss-Legendre nodes in
        ``x = (a + b)/2 + (b - a)/2 sin(pi s/2)`` (square-root ends become smooth)."""
        from numpy.polynomial import chebyshev as C

        t, w = np.polynomial.legendre.leggauss(n)
        xs = 0.5 * (a + b) + 0.5 * (b - a) * np.sin(0.5 * np.pi * t)
        jac = 0.25 * np.pi * (b - a) * np.cos(0.5 * np.pi * t)
        U = np.sqrt(np.maximum(2 * (E - self.G(xs)), 0.0)) / self.sigma
        c = C.chebval(self._t(xs), coefs)
        return float(np.sum(w * jac * np.sum(c * self._band(c.shape[0], U), axis=0)))

    def _t(self, xs: np.ndarray) -> np.ndarray:
        """The Chebyshev variable in ``[-1, 1]`` of the positions ``xs``."""
        return xs / float(self.x[0])

    def _band(self, n: int, U) -> np.ndarray:
        """``int_{-U}^{U}`` of each velocity function (rows) at each ``U``."""
        return band_masses(n, U)

    def energy_density(self, energies) -> np.ndarray:
        """The density ``P(E)`` of ``H = v^2/2 + G(x)`` at each of ``energies`` (the
        derivative of :meth:`mass_below`, :func:`._energy_density.energy_density`)."""
        from ._energy_density import energy_density

        return energy_density(self, energies)

    def energy_bins(self, edges) -> np.ndarray:
        """The density of ``E`` averaged over each bin of ``edges``."""
        edges = np.asarray(edges, float)
        M = np.array([self.mass_below(e) for e in edges])
        return np.diff(M) / np.diff(edges)


def _root(G, E, a, b):
    from scipy.optimize import brentq

    return brentq(lambda z: float(G(np.array(z))) - E, a, b, xtol=1e-15, rtol=1e-15)


def moments_moved(a, b) -> float:
    """The relative change of ``<x^2>`` and ``<v^2>`` from the solve ``a`` to ``b``, at least
    either inverse iteration's last change (an unconverged solve never ends a ladder: SEDF
    mu = 0.02, D = 0.01, 64 x 134 stopped at 8 iterations with a change of 9.3e-4); the
    measure of the stationary ladders (:mod:`._stationary_orthonormal`,
    :mod:`._elements_ladder`, :mod:`._linear_elements`)."""
    return max(abs(b.x2 - a.x2) / abs(b.x2), abs(b.v2 - a.v2) / abs(b.v2),
               a.iteration_change, b.iteration_change)
