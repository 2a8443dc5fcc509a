"""The roots of an averaged amplitude equation ``A(a) = 0``, without sympy or scipy.

- :func:`brentq`: Brent's method as :func:`scipy.optimize.brentq` runs it, bit for bit;
- :func:`amplitude_roots`: the roots ``0 < a* <= a_max`` of ``A(a)/a`` (sign changes on a
  grid, each refined by :func:`brentq` to ``1e-14``), the one search behind
  :meth:`kbm.slowflow.averaged.AveragedRates.cycles` and the first-order guess of
  :mod:`numerics.cycles.guess` (which runs it on cached rates, issue 39).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from ..errors import ParameterError

__all__ = ["brentq", "amplitude_roots"]


def brentq(f: Callable[[float], float], xa: float, xb: float, xtol: float = 2e-12,
           rtol: float = 8.881784197001252e-16, maxiter: int = 100) -> float:
    """A root of ``f`` in ``[xa, xb]`` by Brent's method (R. P. Brent, *Algorithms for
    Minimization without Derivatives*, Prentice-Hall 1973, ch. 4), in the form of
    :func:`scipy.optimize.brentq`: inverse quadratic interpolation or the secant where
    the step is short enough, else bisection, stopped when half the bracket is below
    ``(xtol + rtol |x|)/2``.  The same steps in the same floating-point operations, so the
    same root to the last bit (a test compares them); here so that the averaged cycles need
    no :mod:`scipy.optimize` (its import is 0.2-0.3 s, issue 39).

    Raises
    ------
    ValueError
        If ``f(xa)`` and ``f(xb)`` have the same sign.
    RuntimeError
        If the root is not bracketed to the tolerance within ``maxiter`` steps.
    """
    xpre, xcur = float(xa), float(xb)
    xblk = fblk = spre = scur = 0.0
    fpre, fcur = float(f(xpre)), float(f(xcur))
    if fpre == 0:
        return xpre
    if fcur == 0:
        return xcur
    if fpre * fcur > 0:
        raise ValueError("f(a) and f(b) must have different signs")
    for _ in range(maxiter):
        if fpre != 0 and fcur != 0 and math.copysign(1.0, fpre) != math.copysign(1.0, fcur):
            xblk, fblk = xpre, fpre
            spre = scur = xcur - xpre
        if abs(fblk) < abs(fcur):
            xpre, xcur, xblk = xcur, xblk, xcur
            fpre, fcur, fblk = fcur, fblk, fcur
        delta = (xtol + rtol * abs(xcur)) / 2
        sbis = (xblk - xcur) / 2
        if fcur == 0 or abs(sbis) < delta:
            return xcur
        if abs(spre) > delta and abs(fcur) < abs(fpre):
            if xpre == xblk:  # interpolate (secant)
                stry = -fcur * (xcur - xpre) / (fcur - fpre)
            else:  # extrapolate (inverse quadratic)
                dpre = (fpre - fcur) / (xpre - xcur)
                dblk = (fblk - fcur) / (xblk - xcur)
                stry = -fcur * (fblk * dblk - fpre * dpre) / (dblk * dpre * (fblk - fpre))
            if 2 * abs(stry) < min(abs(spre), 3 * abs(sbis) - delta):  # a good short step
                spre, scur = scur, stry
            else:
                spre = scur = sbis
        else:
            spre = scur = sbis
        xpre, fpre = xcur, fcur
        xcur += scur if abs(scur) > delta else (delta if sbis > 0 else -delta)
        fcur = float(f(xcur))
    raise RuntimeError(f"Brent's method did not converge in {maxiter} steps")


def amplitude_roots(rate: Callable, m: float, pars, *, a_max: float = 20.0,
                    n_grid: int = 4000) -> list[float]:
    """The roots ``0 < a* <= a_max`` of ``rate(a, m, *pars) / a`` in increasing order: the
    grid points where it is zero and a :func:`brentq` root (``xtol = 1e-15``,
    ``rtol = 1e-14``) in each grid interval where it changes sign.

    Raises
    ------
    ParameterError
        If the amplitude equation is not finite somewhere on the grid.
    """
    grid = np.linspace(a_max / n_grid, a_max, n_grid)
    g = rate(grid, m, *pars) / grid
    if not np.all(np.isfinite(g)):
        raise ParameterError(f"the averaged amplitude equation is not finite at "
                             f"a = {grid[~np.isfinite(g)][0]:.6g}")
    sg = np.sign(g)
    roots = list(grid[sg == 0])
    for i in np.nonzero(sg[:-1] * sg[1:] < 0)[0]:
        roots.append(brentq(lambda s: float(rate(s, m, *pars)) / s, grid[i], grid[i + 1],
                            xtol=1e-15, rtol=1e-14))
    return sorted(roots)
