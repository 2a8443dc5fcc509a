"""Bounds on the work of reading input and of the symbolic expansion (issue 21, item 3).

The size estimate of :func:`kbm.expansion.cost.expansion_cost` is read from the expression's
tree without expanding it; it must bound the true degree and number of monomials, which
the reference computes by expanding with :class:`sympy.Poly`.
"""

from __future__ import annotations

import pytest
import sympy as sp
from hypothesis import given, settings, strategies as st

from kbm.expansion.cost import COST_BUDGET, expansion_cost
from kbm.errors import InputSizeError, NonFiniteError
from kbm.symbols import MAX_DIGITS, MAX_EXPONENT, parse, x, xdot

atoms = st.sampled_from([x, xdot, sp.Integer(1), sp.Integer(2), sp.Rational(-1, 3)])


@st.composite
def polynomials(draw, depth=3):
    if depth == 0:
        return draw(atoms)
    kind = draw(st.sampled_from(["atom", "add", "mul", "pow"]))
    if kind == "atom":
        return draw(atoms)
    if kind == "pow":
        return sp.Pow(draw(polynomials(depth - 1)), draw(st.integers(1, 4)))
    args = [draw(polynomials(depth - 1)) for _ in range(draw(st.integers(2, 3)))]
    return (sp.Add if kind == "add" else sp.Mul)(*args)


@settings(max_examples=60, deadline=None)
@given(polynomials(), st.integers(1, 5))
def test_the_cost_estimate_bounds_the_true_degree_and_monomials(expr, order):
    """Upper bounds, checked against the expanded polynomial (sympy.Poly)."""
    cost = expansion_cost(expr, order)
    assert cost is not None
    poly = sp.Poly(sp.expand(expr), x, xdot)
    if poly.is_zero:
        return
    _, d, m = cost
    assert d >= poly.total_degree()
    assert m >= len(poly.monoms())
    assert cost[0] == order * (order * (d - 1) + 2) ** 2 * m


def test_non_polynomial_F_has_no_estimate():
    assert expansion_cost(sp.sin(x) * xdot, 2) is None


def test_van_der_pol_to_order_30_is_within_budget():
    """The engine's order limit (30, van der Pol) stays well inside the budget."""
    assert expansion_cost((1 - x**2) * xdot, 30)[0] < COST_BUDGET / 5


@pytest.mark.parametrize("text", [f"x**{MAX_EXPONENT}", f"10**{MAX_DIGITS // 2}*x",
                                  "9**9*x**3", "2**-3*x"])
def test_sizes_inside_the_bounds_are_read_exactly(text):
    """Reference: Python's own integer arithmetic on the same literals."""
    assert parse(text) == sp.sympify(text)


@pytest.mark.parametrize("text", [f"x**{MAX_EXPONENT + 1}", "10**10**10", "2**(2**64)",
                                  f"10**{MAX_DIGITS + 1}", "7**(3**7)", "(x+1)**(10**4)"])
def test_sizes_past_the_bounds_are_refused_with_the_bound(text):
    with pytest.raises(InputSizeError, match=str(MAX_EXPONENT) + "|" + str(MAX_DIGITS)):
        parse(text)


@pytest.mark.parametrize("text", ["zoo*x", "oo*xdot", "-oo", "nan", "x/0", "1e999*x", "inf"])
def test_non_finite_constants_are_refused(text):
    with pytest.raises((NonFiniteError, InputSizeError)):
        parse(text)


def test_an_infinite_index_bound_of_a_sum_is_read():
    """``oo`` as the upper limit of a Bessel sum (the engine's JSON output) stays readable."""
    expr = parse("Sum(besselj(n, a)/n, (n, 1, oo))")
    assert isinstance(expr, sp.Sum)
