"""Exact values of rational expressions without sympy (kbm/parameters/rational_values.py).

Reference: sympy's own exact rational arithmetic on the same expression (a second method);
the float of an exact rational is correctly rounded either way.
"""

from __future__ import annotations

import subprocess
import sys
from fractions import Fraction
from pathlib import Path

import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from kbm.errors import ParameterError
from kbm.parameters.rational_values import line_floats, rational_tree, tree_value

ROOT = Path(__file__).resolve().parents[1]
A, B = sp.symbols("A B")
rationals = st.fractions(min_value=-20, max_value=20, max_denominator=50)
leaves = st.one_of(st.sampled_from([A, B]), rationals.map(lambda q: sp.Rational(q.numerator,
                                                                                q.denominator)))
exprs = st.recursive(leaves, lambda sub: st.one_of(
    st.tuples(sub, sub).map(lambda t: t[0] + t[1]),
    st.tuples(sub, sub).map(lambda t: t[0] * t[1]),
    st.tuples(sub, st.integers(-3, 3)).map(lambda t: t[0] ** t[1])), max_leaves=6).filter(
        lambda e: not e.has(sp.zoo, sp.nan, sp.oo, -sp.oo))  # 0**-1 folded by sympy


@settings(max_examples=60, deadline=None)
@given(exprs, rationals, rationals)
def test_tree_value_is_sympys_exact_value(expr, a, b):
    """Sums, products and integer powers of symbols and rationals: the fraction value of
    the tree equals sympy's exact rational (undefined where sympy's is not finite)."""
    tree = rational_tree(expr)
    assert tree is not None
    env = {"A": a, "B": b}
    exact = expr.xreplace({A: sp.Rational(a.numerator, a.denominator),
                           B: sp.Rational(b.numerator, b.denominator)})
    if not exact.is_finite:
        with pytest.raises(ZeroDivisionError):
            tree_value(tree, env)
        return
    got = tree_value(tree, env)
    assert got == Fraction(int(exact.p), int(exact.q))


@pytest.mark.parametrize("expr", [sp.sqrt(A), sp.sin(A), A ** sp.Rational(1, 2) + B,
                                  A * sp.pi, A ** B, sp.Float(0.1) * A])
def test_expressions_not_exact_in_fractions_have_no_tree(expr):
    assert rational_tree(expr) is None


def test_line_floats_of_delta_equals_Delta_over_mu():
    """``delta = Delta/mu`` (paper eq. 3) at ``Delta = 1.5``, ``mu = 1/10``: exactly 15; a
    vanishing ``mu`` is passed to the caller's error, a non-finite value refused."""
    tree = rational_tree(sp.Symbol("Delta") / sp.Symbol("mu"))
    out, env = line_floats("Delta", 1.5, {"mu": Fraction(1, 10)}, False, [("delta", tree)],
                           lambda scaled: None)
    assert out == {"delta": 15.0} and env["delta"] == 15
    out, _ = line_floats("Delta", 1.5, {"mu": Fraction(1, 10)}, True, [("delta", tree)],
                         lambda scaled: None)
    assert list(out) == ["Delta", "delta"]

    def undefined(scaled):
        raise ParameterError(f"{scaled} undefined")

    with pytest.raises(ParameterError, match="delta undefined"):
        line_floats("mu", 0.0, {"Delta": Fraction(3, 2)}, True, [("delta", tree)], undefined)
    with pytest.raises(ParameterError, match="finite"):
        line_floats("Delta", float("nan"), {"mu": Fraction(1, 10)}, False, [("delta", tree)],
                    undefined)


def test_the_module_imports_no_sympy():
    """The line cards' warm path (numerics/flow/line_card.py) uses it without sympy."""
    code = "import sys, kbm.parameters.rational_values; print('sympy' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         cwd=ROOT, timeout=120)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "False"
