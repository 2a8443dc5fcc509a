"""The size of an exact one-degree-of-freedom expansion, estimated before any work.

A polynomial ``F`` of high degree makes the exact recursion slow (the harmonics and the
powers of ``a`` both grow by ``d - 1`` an order); :func:`check_cost` refuses such a request
with the estimate and the way out before anything is expanded.  Shared by
:mod:`kbm.expansion.one_dof` and the general engine's case ``N = 1``
(:mod:`kbm.expansion.coupled`).
"""

from __future__ import annotations

import math

import sympy as sp

from ..errors import CostError
from ..symbols import x, xdot

__all__ = ["COST_BUDGET", "expansion_cost", "check_cost"]

#: budget of :func:`expansion_cost` (a few seconds of symbolic work on two cores): measured,
#: with printing, (x+1)**40*xdot to order 2 is 5.5e5 (2 s), (x+1)**80*xdot 4.3e6 (13 s), vdp to
#: order 30 2.3e5 (1.3 s)
COST_BUDGET = 2_000_000


def _degree_and_terms(e: sp.Expr) -> tuple[int, int] | None:
    """Upper bounds on the total degree in ``x, xdot`` and on the number of monomials of
    ``e`` once expanded, read from its tree without expanding; ``None`` if ``e`` is not
    a polynomial in ``x, xdot``."""
    if not e.has(x, xdot):
        return 0, 1
    if e in (x, xdot):
        return 1, 1
    nvars = 2 if e.has(x) and e.has(xdot) else 1
    if e.is_Add or e.is_Mul:
        parts = [_degree_and_terms(arg) for arg in e.args]
        if any(p is None for p in parts):
            return None
        if e.is_Add:
            return max(p[0] for p in parts), sum(p[1] for p in parts)
        d, m = 0, 1
        for pd, pm in parts:
            d, m = d + pd, m * pm
        return d, m
    if e.is_Pow and e.exp.is_Integer and e.exp > 0:
        base = _degree_and_terms(e.base)
        if base is None:
            return None
        d, n = base[0] * int(e.exp), int(e.exp)
        # a product of n sums of m terms has at most C(m + n - 1, n) monomials, and a
        # polynomial of degree d in one (two) variables at most d + 1 ((d + 1)(d + 2)/2)
        dim = d + 1 if nvars == 1 else (d + 1) * (d + 2) // 2
        return d, min(math.comb(base[1] + n - 1, n), dim)
    return None


def expansion_cost(F: sp.Expr, order: int) -> tuple[int, int, int] | None:
    """The estimated size ``order * (order (d - 1) + 2)**2 * m`` of the exact expansion of a
    polynomial ``F`` of total degree ``d`` in ``x, xdot`` with ``m`` monomials, with ``d``
    and ``m``; ``None`` if ``F`` is not a polynomial in ``x, xdot``.

    ``u_n`` holds about ``(n (d - 1) + 2)**2 / 2`` terms ``a^p e^{i k psi}`` (harmonics and
    powers of ``a`` both grow by ``d - 1`` an order), each order multiplies them by the
    ``m`` monomials' series, and there are ``order`` orders.  ``d`` and ``m`` are read
    from the expression's tree (upper bounds: ``m <= (d + 1)(d + 2)/2``) before anything
    is expanded.
    """
    dm = _degree_and_terms(F)
    if dm is None:
        return None
    d, m = max(dm[0], 1), min(dm[1], (dm[0] + 1) * (dm[0] + 2) // 2)
    return order * (order * (d - 1) + 2) ** 2 * m, d, m


def check_cost(F: sp.Expr, order: int) -> None:
    """Raise :class:`~kbm.errors.CostError` with the estimate, the budget and the way out
    when :func:`expansion_cost` of ``F`` to ``order`` passes :data:`COST_BUDGET`; called
    before anything is expanded."""
    cost = expansion_cost(F, order)
    if cost is not None and cost[0] > COST_BUDGET:
        raise CostError(
            f"the exact expansion of F (total degree {cost[1]} in x, xdot, up to {cost[2]} "
            f"monomials) to order {order} is estimated at {cost[0]:.2g} terms, above the "
            f"budget {COST_BUDGET:.0e} (a few seconds); ask for a lower order, or evaluate at "
            f"numbers with the numeric backend (kbm.numeric_derive; on the command line "
            f"--numeric --a-range AMIN:AMAX)")
