"""Truncated power series with sympy coefficients, as lists ``[c_0, c_1, ..., c_{n-1}]``:
product, reciprocal and composition (the series reversion of
:func:`kbm.slowflow.tongues.mathieu_transition`; Knuth, *TAOCP* vol. 2, sec. 4.7)."""

from __future__ import annotations

import sympy as sp

__all__ = ["series_product", "series_reciprocal", "series_compose"]


def series_product(u: list, v: list, n: int) -> list:
    """``u v`` (truncated to ``n`` terms)."""
    out = [sp.Integer(0)] * n
    for i, x in enumerate(u[:n]):
        if x:
            for j, y in enumerate(v[:n - i]):
                out[i + j] += x * y
    return out


def series_reciprocal(u: list, n: int) -> list:
    """``1/u`` as a truncated power series (``u[0] != 0``)."""
    out = [1 / u[0]] + [sp.Integer(0)] * (n - 1)
    for k in range(1, n):
        out[k] = -sum(u[j] * out[k - j] for j in range(1, min(k, len(u) - 1) + 1)) / u[0]
    return out


def series_compose(u: list, v: list, n: int) -> list:
    """``u(v(x))`` for ``v[0] = 0`` (truncated)."""
    out = [sp.Integer(0)] * n
    power = [sp.Integer(1)] + [sp.Integer(0)] * (n - 1)
    for k in range(n):
        if k < len(u):
            out = [o + u[k] * p for o, p in zip(out, power)]
        power = series_product(power, v, n)
    return out
