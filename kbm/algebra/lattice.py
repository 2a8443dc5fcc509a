"""Integer lattice lines of the Jacobi-Anger families: where a harmonic ``h(n_1, n_2)`` is fixed.

A family of harmonics in :mod:`~kbm.algebra.bessel_fourier` is a sum over
integer indices ``n_i >= l_i`` whose harmonic ``h`` is an integer linear form
in them.  Harmonic balance asks for the coefficient of one harmonic ``m``: the
sum of the family's coefficient over the admissible points with ``h = m``.  For
one index that is at most one point; for two it is a line of the lattice,
found exactly with the extended Euclidean algorithm.
"""

from __future__ import annotations

import sympy as sp

from ..errors import OrderError

__all__ = ["linear_form", "egcd", "line", "line_points_exist", "line_sum"]


def linear_form(h: sp.Expr, idx: tuple[sp.Symbol, ...]) -> tuple[list[int], int]:
    """Integer coefficients of the linear form ``h`` in the indices, and its constant."""
    h = sp.expand(h)
    coeffs = [int(h.coeff(s)) for s in idx]
    const = h.subs({s: 0 for s in idx})
    return coeffs, int(const)


def egcd(p: int, q: int) -> tuple[int, int, int]:
    """``(g, x, y)`` with ``p x + q y = g = gcd(p, q) >= 0``."""
    x0, y0, x1, y1 = 1, 0, 0, 1
    while q:
        r = p // q
        p, q = q, p - r * q
        x0, x1 = x1, x0 - r * x1
        y0, y1 = y1, y0 - r * y1
    if p < 0:
        p, x0, y0 = -p, -x0, -y0
    return p, x0, y0


def _ceil_div(p: int, q: int) -> int:
    """``ceil(p / q)`` in integers."""
    return -((-p) // q)


def line(h: sp.Expr, idx, target: int):
    """Admissible points of a two-index family where ``h == target``.

    Returns ``None`` if there are none, ``"all"`` if ``h`` is constant and equal
    to ``target``, else ``(x0, y0, d1, d2, lo, hi)``: the points are
    ``(n1, n2) = (x0 + d1 s, y0 + d2 s)`` for integer ``s`` in ``[lo, hi]``
    (``None`` for an unbounded end).  Found with the extended Euclidean algorithm.
    """
    syms = tuple(s for s, _ in idx)
    (p1, p2), q = linear_form(h, syms)
    (s1, l1), (s2, l2) = idx
    rhs = target - q
    g, u, w = egcd(p1, p2)
    if g == 0:
        return "all" if rhs == 0 else None
    if rhs % g:
        return None
    k = rhs // g
    # general solution n1 = u k + (p2/g) s, n2 = w k - (p1/g) s
    x0, y0, d1, d2 = u * k, w * k, p2 // g, -p1 // g
    lo, hi = None, None
    for base, step, low in ((x0, d1, l1), (y0, d2, l2)):
        if step > 0:  # base + step s >= low
            b = _ceil_div(low - base, step)
            lo = b if lo is None else max(lo, b)
        elif step < 0:
            b = (base - low) // (-step)
            hi = b if hi is None else min(hi, b)
        elif base < low:
            return None
    if lo is not None and hi is not None and hi < lo:
        return None
    return x0, y0, d1, d2, lo, hi


def line_points_exist(h, idx, target) -> bool:
    """Whether a two-index family has an admissible point where ``h == target``."""
    return line(h, idx, target) is not None


def line_sum(c: sp.Expr, h: sp.Expr, idx, target: int, index: sp.Symbol) -> sp.Expr:
    """Sum of ``c`` over the admissible index points where ``h == target``.

    A sum left along an unbounded line runs over ``index`` (a fresh summation index).
    """
    if not idx:
        return c if h == target else sp.Integer(0)
    syms = tuple(s for s, _ in idx)
    coeffs, q = linear_form(h, syms)
    rhs = target - q
    if len(idx) == 1:
        (s, lo), p = idx[0], coeffs[0]
        if p == 0:
            return sp.Sum(c, (s, lo, sp.oo)) if rhs == 0 else sp.Integer(0)
        if rhs % p:
            return sp.Integer(0)
        n = rhs // p
        return c.subs(s, n) if n >= lo else sp.Integer(0)
    if len(idx) != 2:
        raise OrderError("harmonic balance over three or more nested Bessel sums is not "
                         "implemented: a term of F multiplies several sines or cosines of x "
                         "that do not combine into one; use order 1, or write F with one "
                         "sine or cosine of x per term")
    points = line(h, idx, target)
    if points is None:
        return sp.Integer(0)
    (s1, l1), (s2, l2) = idx
    if points == "all":
        return sp.Sum(c, (s1, l1, sp.oo), (s2, l2, sp.oo))
    x0, y0, d1, d2, lo, hi = points
    s = sp.Symbol("_s", integer=True)
    body = c.xreplace({s1: x0 + d1 * s, s2: y0 + d2 * s})
    if lo is not None and hi is not None:
        return sp.Add(*[body.subs(s, j) for j in range(lo, hi + 1)])
    if hi is not None:  # s <= hi: substitute s -> -s
        body, lo = body.xreplace({s: -s}), -hi
    body = body.xreplace({s: index})
    return sp.Sum(sp.expand(body), (index, lo, sp.oo))
