"""Symbolic averaged rates evaluated at numbers (:mod:`numerics.spectrum.phase_diffusion`).

:func:`numbers` turns parameter values into 30-digit sympy floats, :func:`finite` cuts the
infinite Bessel series of a transcendental force (Jacobi-Anger) after 80 terms, :func:`fn`
makes a numpy function of ``(a, psi)`` and :func:`at` one value at ``a``.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import sympy as sp

from kbm.errors import ParameterError
from kbm.symbols import a, psi

__all__ = ["numbers", "finite", "fn", "at"]


def numbers(params: Mapping[str, object]) -> dict:
    """``{Symbol(name): 30-digit Float}`` of parameter values (a bad value: ParameterError)."""
    out = {}
    for k, v in params.items():
        try:
            out[sp.Symbol(k)] = sp.Float(sp.N(sp.sympify(v), 30), 30)
        except (TypeError, ValueError, sp.SympifyError):
            raise ParameterError(f"{k} = {v!r} is not a number") from None
    return out


def finite(expr: sp.Expr, terms: int = 80, expand: bool = True) -> sp.Expr:
    """Infinite sums (Jacobi-Anger's Bessel series) cut after ``terms`` terms: ``J_m(k a)``
    falls faster than any power once ``m > e k a/2``.  ``expand``: written out term by term
    (order 1's short series, as before); otherwise left as finite sums that numpy adds up
    (order 2's summands are products of series, whose symbolic expansion ran for minutes:
    ``kbm spectrum sedf --order 2``)."""
    def cut(f, *limits):
        part = sp.Sum(f, *((n, lo, sp.Min(hi, lo + terms)) for n, lo, hi in limits))
        return part.doit() if expand else part

    return expr.replace(lambda e: isinstance(e, sp.Sum), lambda e: cut(e.function, *e.limits))


def fn(expr: sp.Expr, subs: Mapping, expand: bool = True):
    """``expr`` with ``subs`` as a numpy function of ``(a, psi)`` (series by :func:`finite`);
    a free symbol left over is a missing value (ParameterError)."""
    e = finite(sp.sympify(expr).subs(subs), expand=expand)
    free = e.free_symbols - {a, psi}
    if free:
        raise ParameterError(f"give values for {', '.join(sorted(s.name for s in free))}")
    return sp.lambdify((a, psi), e, modules=["numpy", "scipy"])


def at(expr: sp.Expr, subs: Mapping, a_val: float) -> float:
    """``expr`` at ``a = a_val``; an infinite (Bessel) series summed in numpy after 80 terms
    (sympy's ``evalf`` of the ``Sum`` took minutes for the SEDF's second order: ``float`` of
    the noise-induced shift alone ran over 100 s of CPU)."""
    e = sp.sympify(expr).subs(subs)
    if not e.has(sp.Sum):
        return float(e.subs(a, a_val))
    e = finite(e.subs(a, sp.Float(a_val, 30)), expand=False)
    return float(np.real(sp.lambdify((), e, modules=["numpy", "scipy"])()))
