"""Scalar minimisation on an interval and a fixed quadrature, without scipy (issue 39).

- :func:`fminbound`: Brent's minimiser on ``[a, b]`` (golden section and parabolic steps;
  R. P. Brent, *Algorithms for Minimization without Derivatives*, Prentice-Hall 1973,
  ch. 5; Forsythe, Malcolm and Moler, *Computer Methods for Mathematical Computations*,
  1977, ``fmin``) in the form of ``scipy.optimize.minimize_scalar(method="bounded")``:
  the same steps in the same floating-point operations, so the same minimiser to the last
  bit (a test compares them);
- :func:`integral`: ``int_a^b f`` by composite Gauss--Legendre (panels of at most unit
  length, 20 nodes each), for smooth integrands (the energies ``G(x) = int_0^x g`` of
  :func:`numerics.cycles.homoclinic.saddles_passed`; a test compares it with
  ``scipy.integrate.quad``).

Here so that the homoclinic end of ``kbm branch`` needs neither :mod:`scipy.optimize`
nor :mod:`scipy.integrate` (their imports cost 0.2-0.5 s, more than the continuation).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

__all__ = ["fminbound", "integral"]


def _sign(v: float) -> float:
    """``numpy.sign`` of a float (``nan`` for ``nan``)."""
    return 1.0 if v > 0 else -1.0 if v < 0 else 0.0 if v == 0 else math.nan


def _largest(a: float, b: float) -> float:
    """``numpy.maximum`` of two floats (``nan`` if either is)."""
    return math.nan if a != a or b != b else (a if a >= b else b)


def fminbound(func: Callable[[float], float], a: float, b: float, xatol: float = 1e-5,
              maxiter: int = 500) -> float:
    """The minimiser of ``func`` on ``[a, b]`` by Brent's method, as scipy's bounded
    ``minimize_scalar`` (``options={"xatol": xatol, "maxiter": maxiter}``) returns it in
    ``res.x``.

    Raises
    ------
    ValueError
        If the bounds are not finite or ``a > b``.
    """
    x1, x2 = float(a), float(b)
    if not (math.isfinite(x1) and math.isfinite(x2)):
        raise ValueError("the bounds must be finite")
    if x1 > x2:
        raise ValueError("the lower bound exceeds the upper bound")
    sqrt_eps = math.sqrt(2.2e-16)
    golden_mean = 0.5 * (3.0 - math.sqrt(5.0))
    a, b = x1, x2
    fulc = a + golden_mean * (b - a)
    nfc, xf = fulc, fulc
    rat = e = 0.0
    x = xf
    fx = func(x)
    num = 1
    ffulc = fnfc = fx
    xm = 0.5 * (a + b)
    tol1 = sqrt_eps * abs(xf) + xatol / 3.0
    tol2 = 2.0 * tol1
    while abs(xf - xm) > (tol2 - 0.5 * (b - a)):
        golden = True
        if abs(e) > tol1:  # a parabola through the three best points
            golden = False
            r = (xf - nfc) * (fx - ffulc)
            q = (xf - fulc) * (fx - fnfc)
            p = (xf - fulc) * q - (xf - nfc) * r
            q = 2.0 * (q - r)
            if q > 0.0:
                p = -p
            q = abs(q)
            r = e
            e = rat
            if abs(p) < abs(0.5 * q * r) and p > q * (a - xf) and p < q * (b - xf):
                rat = (p + 0.0) / q
                x = xf + rat
                if (x - a) < tol2 or (b - x) < tol2:
                    rat = tol1 * (_sign(xm - xf) + ((xm - xf) == 0))
            else:
                golden = True
        if golden:  # a golden-section step
            e = a - xf if xf >= xm else b - xf
            rat = golden_mean * e
        x = xf + (_sign(rat) + (rat == 0)) * _largest(abs(rat), tol1)
        fu = func(x)
        num += 1
        if fu <= fx:
            if x >= xf:
                a = xf
            else:
                b = xf
            fulc, ffulc = nfc, fnfc
            nfc, fnfc = xf, fx
            xf, fx = x, fu
        else:
            if x < xf:
                a = x
            else:
                b = x
            if fu <= fnfc or nfc == xf:
                fulc, ffulc = nfc, fnfc
                nfc, fnfc = x, fu
            elif fu <= ffulc or fulc == xf or fulc == nfc:
                fulc, ffulc = x, fu
        xm = 0.5 * (a + b)
        tol1 = sqrt_eps * abs(xf) + xatol / 3.0
        tol2 = 2.0 * tol1
        if num >= maxiter:
            break
    return xf


#: the 20-point Gauss--Legendre rule on [-1, 1] (exact for polynomials of degree 39)
_NODES, _WEIGHTS = np.polynomial.legendre.leggauss(20)


def integral(f: Callable[[np.ndarray], np.ndarray], a: float, b: float) -> float:
    """``int_a^b f(s) ds`` by composite 20-point Gauss--Legendre on ``ceil(|b - a|)``
    equal panels; ``f`` takes an array of points.  For an integrand analytic in a
    neighbourhood of ``[a, b]`` the error falls like ``rho^-40`` per panel (rounding,
    ~1e-16 relative, for the smooth forces of the built-in models)."""
    a, b = float(a), float(b)
    if a == b:
        return 0.0
    n = max(1, math.ceil(abs(b - a)))
    edges = np.linspace(a, b, n + 1)
    half = 0.5 * np.diff(edges)
    mid = 0.5 * (edges[:-1] + edges[1:])
    s = (mid[:, None] + half[:, None] * _NODES[None, :]).ravel()
    vals = np.asarray(f(s), dtype=float).reshape(n, len(_NODES))
    return float(np.sum(half * (vals @ _WEIGHTS)))
