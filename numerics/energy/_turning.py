"""Turning points: the solutions ``x`` of ``G(x) = E`` on a stretch where ``G`` is monotone.

:func:`solve` is vectorised over energies; :func:`solve1` is the same safeguarded
Newton iteration for one energy in Python floats (the position scheme calls it
thousands of times, where the array overhead dominated).  Both start from the
inverse of a table of ``G`` (257 samples, kept in ``cache`` per stretch) with
its cell as the bracket.
"""

from __future__ import annotations

import bisect
import math

import numpy as np

_EPS = float(np.finfo(float).eps)


def _table(cache: dict, G, lo: float, hi: float, increasing: bool):
    key = (lo, hi, increasing)
    if key not in cache:
        if len(cache) > 64:
            cache.clear()
        xt = np.linspace(lo, hi, 257)
        Gt = G(xt)
        if not increasing:
            xt, Gt = xt[::-1], Gt[::-1]
        Gt = np.maximum.accumulate(Gt)
        cache[key] = (xt, Gt, xt.tolist(), Gt.tolist())
    return cache[key]


def solve(fun: tuple, cache: dict, E, a: float, b: float, increasing: bool) -> np.ndarray:
    """``x`` in ``(a, b)`` with ``G(x) = E`` for each energy (``fun = (g, g', G, h)``)."""
    g, _, G, _ = fun
    E = np.asarray(E, float)
    lo = np.full(E.shape, a, float)
    hi = np.full(E.shape, b, float)
    if not np.isfinite(b if increasing else a):
        far = hi if increasing else lo
        start = max(1.0, abs(a if increasing else b)) * (1 if increasing else -1)
        far[...] = start
        for _ in range(200):
            short = G(far) < E
            if not np.any(short):
                break
            far[short] *= 2.0
    sgn = 1.0 if increasing else -1.0
    xt, Gt, _, _ = _table(cache, G, float(np.min(lo)), float(np.max(hi)), increasing)
    i = np.clip(np.searchsorted(Gt, E), 1, len(xt) - 1)
    cell = np.sort(np.stack([xt[i - 1], xt[i]]), axis=0)
    lo, hi = np.maximum(lo, cell[0]), np.minimum(hi, cell[1])
    xk = np.clip(np.interp(E, Gt, xt), lo, hi)
    for _ in range(100):
        r = G(xk) - E
        left = sgn * r > 0           # the root lies left of xk
        hi = np.where(left, xk, hi)
        lo = np.where(left, lo, xk)
        with np.errstate(divide="ignore", invalid="ignore"):
            step = xk - r / g(xk)
        ok = (step >= lo) & (step <= hi)
        new = np.where(ok, step, 0.5 * (lo + hi))
        done = np.abs(new - xk) <= 32 * _EPS * np.maximum(1.0, np.abs(xk))
        xk = new
        # per energy: Newton converged, the bracket is down to one ulp (a rounded
        # Newton step may then leave it forever), or G(x) - E is at the rounding level
        # of E (near a saddle, where g is small, Newton then wanders among a few ulps)
        if np.all((done & ok) | (lo == hi) | (np.nextafter(lo, hi) == hi)
                  | (np.abs(r) <= 4 * _EPS * np.maximum(1.0, np.abs(E)))):
            break
    return xk


def solve1(scalar: tuple, fun: tuple, cache: dict, E: float, a: float, b: float,
           increasing: bool) -> float:
    """:func:`solve` for one energy ``E`` with ``scalar = (g, G)`` on floats."""
    g, G = scalar
    E = float(E)
    lo, hi = float(a), float(b)
    if not math.isfinite(b if increasing else a):
        far = max(1.0, abs(a if increasing else b)) * (1 if increasing else -1)
        for _ in range(200):
            if G(far) >= E:
                break
            far *= 2.0
        lo, hi = (lo, far) if increasing else (far, hi)
    sgn = 1.0 if increasing else -1.0
    _, _, xt, Gt = _table(cache, fun[2], lo, hi, increasing)
    i = min(max(bisect.bisect_left(Gt, E), 1), len(xt) - 1)
    c0, c1 = sorted((xt[i - 1], xt[i]))
    lo, hi = max(lo, c0), min(hi, c1)
    dG = Gt[i] - Gt[i - 1]
    xk = xt[i - 1] + (xt[i] - xt[i - 1]) * ((E - Gt[i - 1]) / dG if dG > 0 else 0.5)
    xk = min(max(xk, lo), hi)
    tiny = 4 * _EPS * max(1.0, abs(E))
    for _ in range(100):
        r = G(xk) - E
        if abs(r) <= tiny:
            return xk
        if sgn * r > 0:
            hi = xk
        else:
            lo = xk
        d = g(xk)
        step = xk - r / d if d != 0 else math.nan
        ok = lo <= step <= hi
        new = step if ok else 0.5 * (lo + hi)
        if (ok and abs(new - xk) <= 32 * _EPS * max(1.0, abs(xk))) or hi <= math.nextafter(lo, hi):
            return new
        xk = new
    return xk
