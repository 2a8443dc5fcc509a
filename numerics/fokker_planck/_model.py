"""The model's pieces that every Kramers solve needs (:mod:`.kramers`, :mod:`._orthonormal`,
:mod:`._stationary_orthonormal`): the damping as a polynomial in the velocity, the
half-width of the position range, the number of Chebyshev intervals that resolve
``exp(-G/scale)``, and the bottoms of the wells next to the escape's saddles
(:func:`next_wells`)."""

from __future__ import annotations

import math

import numpy as np
import sympy as sp

from kbm.model.conservative import ConservativeSplit
from kbm.errors import ModelError, ParameterError
from kbm.symbols import x as X, xdot as V

__all__ = ["velocity_terms", "lobatto_coefficients", "grid_check", "next_wells"]


def velocity_terms(split: ConservativeSplit) -> list:
    """``[(k, a_k)]`` with ``mu h(x, v) = sum_k a_k(x) v^k`` (numpy functions of ``x``).

    Raises
    ------
    kbm.errors.ModelError
        When ``h`` is not a polynomial in the velocity.
    """
    h = sp.expand(split.mu * split.h)
    try:
        poly = sp.Poly(h, V)
    except sp.PolynomialError:
        raise ModelError(f"the damping mu h = {h} is not a polynomial in x': the Hermite "
                         "expansion of the Kramers equation needs one") from None
    out = []
    for (k,), coef in zip(poly.monoms(), poly.coeffs()):
        if coef.free_symbols - {X}:
            raise ParameterError(f"the damping needs values for {coef.free_symbols - {X}}")
        f = sp.lambdify(X, coef, "numpy")
        out.append((int(k), lambda z, f=f: np.broadcast_to(np.asarray(f(z), float),
                                                           np.shape(z)).copy()))
    return out


def _half_width(G, scale: float, span: float = 45.0) -> float:
    grid = np.linspace(-50, 50, 20001)
    Gmin = float(np.min(G(grid)))
    L = 1.0
    while min(float(G(np.array(L))), float(G(np.array(-L)))) - Gmin < span * scale:
        L *= 1.1
        if L > 1e4:
            raise ModelError("the potential does not confine the noisy motion (G grows too "
                             "slowly): no stationary density")
    return L


def lobatto_coefficients(f: np.ndarray) -> np.ndarray:
    """The Chebyshev coefficients of the polynomial interpolating ``f`` at the points
    ``cos(pi j/n)``, ``j = 0 .. n``: the discrete cosine transform of type I (Trefethen,
    *Spectral Methods in MATLAB*, 2000, ch. 8; ``O(n^2)`` where the least-squares fit of
    ``numpy.polynomial.chebyshev.chebfit`` on the same square system is ``O(n^3)``)."""
    f = np.asarray(f, float)
    n = f.size - 1
    w = np.full(n + 1, 2.0 / n)
    w[[0, -1]] /= 2
    j = np.arange(n + 1)
    c = np.cos(np.pi * np.outer(j, j) / n) @ (w * f)
    c[[0, -1]] /= 2
    return c


def _chebyshev_size(G, s2: float, L: float, target: float = 1e-9) -> int:
    """Chebyshev intervals that resolve ``exp(-(G - G_min)/sigma^2)`` on ``[-L, L]``."""
    n = 64
    while n < 600:
        t = np.cos(np.pi * np.arange(n + 1) / n)
        Gx = G(L * t)
        f = np.exp(-(Gx - Gx.min()) / s2)
        c = lobatto_coefficients(f)
        if float(np.max(np.abs(c[-8:]))) <= target * float(np.max(np.abs(c))):
            return int(math.ceil(1.15 * n))
        n = int(1.2 * n)
    return 600


def grid_check(ladder, rates, nc: int, grow: float, fits, solve, table: list, tol: float,
               max_cheb: int) -> tuple:
    """The escape ladders' check of the position grid (linear and nonlinear damping): the
    rate on ``grow`` times the intervals at the top rung of the Hermite ladder where it fits
    (at the rung below, the CDC at mu = 0.02 stated 3e-15 of a grid change of 9.3e-13: the
    high orders need the finer grid most), appended to ``table``.

    Returns ``(chebyshev_error, done, finer, k, prev)``: ``done`` when the change is within
    ``tol`` of the rate or the grid cannot grow; else the ladder runs again on ``finer``."""
    k = len(rates) - 1
    prev = max(k - 1, 0)
    finer = 2 * int(round(grow * nc / 2))
    check = max([i for i in range(k + 1) if fits(ladder[i], finer)], default=0)
    r_fine = solve(ladder[check], finer)
    table.append((ladder[check], finer, r_fine))
    err = abs(r_fine - rates[check])
    done = err <= tol * abs(rates[-1]) or finer > max_cheb or not fits(ladder[prev], finer)
    return err, done, finer, k, prev


def next_wells(g, saddles) -> tuple:
    """``(x_wl, x_wr)``: the bottoms of the wells beyond the saddles ``x_l < 0 < x_r``, the
    first zeros of the force ``g = G'`` outward of each saddle where ``G`` turns upward
    (Brent's method to 1e-15).

    Raises
    ------
    kbm.errors.ModelError
        When ``G`` falls without a minimum within 50 saddle distances (no next well).
    """
    from scipy.optimize import brentq

    out = []
    for xs in saddles:
        side = math.copysign(1.0, xs)
        grid = xs + side * 1e-3 * abs(xs) * np.arange(1, 50001)
        slope = side * np.asarray(g(grid), float)  # dG/d|x|: < 0 past the saddle
        up = np.flatnonzero(slope > 0)
        if up.size == 0 or up[0] == 0:
            raise ModelError(f"no well beyond the saddle at x = {xs:.6g} (G falls without a "
                             "minimum): the escape rate needs the next well's bottom")
        i = int(up[0])
        out.append(float(brentq(lambda z: float(g(np.array(z))), grid[i - 1], grid[i],
                                xtol=1e-15, rtol=1e-15)))
    return tuple(out)
