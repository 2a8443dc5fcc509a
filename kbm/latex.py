"""LaTeX in the paper's notation, in one place.

:class:`KBMLatexPrinter` prints ``besselj(m, k a)`` as ``J_{m}(k a)``, the
parameters with their Greek names (``lam`` as ``\\lambda``, ``xdot`` as
``\\dot{x}``), and orders every sum deterministically (sympy's ``lex`` order,
which does not depend on ``PYTHONHASHSEED``).  :func:`equation_lines` breaks a
long right-hand side into ``align`` lines at top-level ``+``/``-`` signs (and
inside long Bessel sums), so no equation runs off the page.
"""

from __future__ import annotations

import sympy as sp
from sympy.printing.latex import LatexPrinter

__all__ = ["KBMLatexPrinter", "latex", "equation_lines", "SYMBOL_NAMES"]

#: LaTeX names of the package's symbols
SYMBOL_NAMES = {
    sp.Symbol("xdot"): r"\dot{x}",
    sp.Symbol("lam"): r"\lambda",
    sp.Symbol("psi"): r"\psi",
    sp.Symbol("mu"): r"\mu",
    sp.Symbol("eps"): r"\varepsilon",
}


class KBMLatexPrinter(LatexPrinter):
    """sympy's LaTeX printer with the package's notation."""

    def __init__(self, settings=None):
        settings = dict(settings or {})
        settings.setdefault("symbol_names", SYMBOL_NAMES)
        settings.setdefault("order", "lex")
        settings.setdefault("long_frac_ratio", 2)
        super().__init__(settings)

    def _print_besselj(self, expr, exp=None):
        order, arg = expr.args
        tex = r"J_{%s}\!\left(%s\right)" % (self._print(order), self._print(arg))
        if exp is not None:
            tex = r"J_{%s}^{%s}\!\left(%s\right)" % (self._print(order), exp, self._print(arg))
        return tex

    def _print_Piecewise(self, expr):
        # only used for the sums that leave out |h| = 1: print the value with the condition
        (val, cond), *rest = expr.args
        return r"%s\,\Big|_{%s}" % (self._print(val), self._print(cond))


def latex(expr: sp.Expr, **settings) -> str:
    """LaTeX of ``expr`` in the package's notation (deterministic)."""
    return KBMLatexPrinter(settings).doprint(expr)


def _terms(expr: sp.Expr) -> list[sp.Expr]:
    printer = KBMLatexPrinter()
    if isinstance(expr, sp.Add):
        return list(printer._as_ordered_terms(expr, order="lex"))
    return [expr]


def _signed(tex: str, first: bool) -> str:
    if first:
        return tex
    return tex if tex.startswith("-") else "+ " + tex


def equation_lines(lhs: str, expr: sp.Expr, width: int = 90) -> str:
    """``lhs &= ...`` for an ``align`` environment, broken into lines of ~``width`` chars.

    Top-level terms are packed greedily; a single term longer than ``width`` that
    is an infinite sum is printed as ``\\sum (`` body terms ``)`` over several lines.
    """
    pieces: list[str] = []
    for term in _terms(sp.sympify(expr)):
        coeff, body = sp.Integer(1), term
        if isinstance(term, sp.Mul):
            sums = [f for f in term.args if isinstance(f, sp.Sum)]
            if len(sums) == 1:
                body = sums[0]
                coeff = term / body
        tex = latex(term)
        if isinstance(body, sp.Sum) and len(tex) > width and isinstance(body.function, sp.Add):
            lims = "".join(r"\sum_{%s=%s}^{%s}" % (latex(v), latex(lo), latex(hi))
                           for v, lo, hi in reversed(body.limits))
            head = ("" if coeff == 1 else ("-" if coeff == -1 else latex(coeff) + r"\,")) + lims
            inner = [latex(t) for t in _terms(body.function)]
            pieces.append(head + r"\Big[" + inner[0])
            for t in inner[1:-1]:
                pieces.append(_signed(t, False))
            pieces.append(_signed(inner[-1], False) + r"\Big]" if len(inner) > 1 else r"\Big]")
            continue
        pieces.append(tex)
    lines: list[str] = []
    cur = ""
    for i, p in enumerate(pieces):
        p = _signed(p, i == 0) if not p.startswith(("+", "-")) or i == 0 else p
        if cur and len(cur) + len(p) > width:
            lines.append(cur)
            cur = p
        else:
            cur = (cur + " " + p).strip()
    lines.append(cur)
    out = f"{lhs} &= {lines[0]}"
    for ln in lines[1:]:
        out += " \\\\\n  &\\quad " + ln
    return out
