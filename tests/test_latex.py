"""The LaTeX output says what the expressions say: parsed back independently and compared.

The emitted LaTeX is read back with sympy's LaTeX parser (an ANTLR grammar, an
independent route from our printer) and compared exactly with the engine's
expression for the polynomial results; Bessel results are checked numerically
by evaluating the printed ``J_{m}(k a)`` through the same parser.
"""

from __future__ import annotations

import pytest
import sympy as sp

from kbm import derive, latex, limit_cycle_series
from kbm.output.latex import equation_lines, visible_width

parse_latex = pytest.importorskip("sympy.parsing.latex").parse_latex
pytest.importorskip("antlr4")

a, psi = sp.symbols("a psi")


def _parse(tex: str) -> sp.Expr:
    # the printer's spacing commands are not in the parser's grammar
    for cmd in (r"\!", r"\,"):
        tex = tex.replace(cmd, " ")
    return parse_latex(tex)


@pytest.mark.parametrize("model, order", [("vdp", 4), ("duffing", 3), ("rayleigh", 3)])
def test_polynomial_latex_parses_back_exactly(model, order):
    """Every A_n, B_n, u_n of the polynomial models, printed and parsed back, is the same
    expression (exact rational arithmetic, so equality is exact)."""
    res = derive(model, order)
    for seq in (res.A, res.B, res.u):
        for e in seq[1:]:
            back = _parse(latex(e))
            back = back.subs({sp.Symbol("a"): a, sp.Symbol("psi"): psi})
            assert sp.simplify(sp.expand(back - e)) == 0, (latex(e), back, e)


def test_series_latex_parses_back():
    """The van der Pol frequency series printed as LaTeX reads back to the same rationals."""
    s = limit_cycle_series("vdp", 8)
    mu = sp.Symbol("mu")
    back = _parse(latex(s.omega_expr())).subs(sp.Symbol("mu"), mu)
    assert sp.expand(back - s.omega_expr()) == 0


def test_bessel_latex_evaluates_like_the_expression():
    """sedf B_1 = delta J_1(k a)/(Omega a): the printed J_{1}(k a) parsed back as a function
    call evaluates to the same number as sympy's besselj (numeric spot check)."""
    res = derive("sedf", 1)
    tex = latex(res.B[1]).replace(r"J_{1}\!\left(k a\right)", r"J(k a)")
    back = _parse(tex)
    vals = {sp.Symbol("a"): sp.Rational(7, 10), sp.Symbol("k"): 2 * sp.pi,
            sp.Symbol("delta"): sp.Rational(3, 2), sp.Symbol("Omega"): 1}
    back_v = back.replace(lambda e: isinstance(e, sp.core.function.AppliedUndef),
                          lambda e: sp.besselj(1, e.args[0])).subs(vals)
    assert abs(float(back_v) - float(res.B[1].subs(vals))) < 1e-14


def test_long_equations_are_broken():
    """No displayed line of the sedf u_2 is wider than the requested width (plus one
    unbreakable term), so equations do not run off the page."""
    res = derive("sedf", 2)
    text = equation_lines("u_2", res.u[2], 62)
    lines = text.split(r"\\")
    assert len(lines) > 5
    assert max(visible_width(ln) for ln in lines) < 2 * 62
