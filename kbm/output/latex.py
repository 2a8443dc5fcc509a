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

__all__ = ["KBMLatexPrinter", "latex", "equation_lines", "series_lines", "visible_width",
           "SYMBOL_NAMES", "align_block"]

#: LaTeX names of the package's symbols
SYMBOL_NAMES = {
    sp.Symbol("xdot"): r"\dot{x}",
    sp.Symbol("lam"): r"\lambda",
    sp.Symbol("psi"): r"\psi",
    sp.Symbol("mu"): r"\mu",
    sp.Symbol("eps"): r"\varepsilon",
    sp.Symbol("Delta_over_mu"): r"(\Delta/\mu)",
}


class KBMLatexPrinter(LatexPrinter):
    """sympy's LaTeX printer with the package's notation."""

    def __init__(self, settings=None):
        settings = dict(settings or {})
        settings.setdefault("symbol_names", SYMBOL_NAMES)
        settings.setdefault("order", "lex")
        settings.setdefault("long_frac_ratio", 2)
        super().__init__(settings)

    def _argument(self, arg: sp.Expr) -> str:
        """``k a`` rather than sympy's ``a k``: the amplitude goes last, as in the paper."""
        amp = sp.Symbol("a")
        if isinstance(arg, sp.Mul) and amp in arg.args:
            rest = arg / amp
            return r"%s a" % self.parenthesize(rest, 50) if rest != 1 else "a"
        return self._print(arg)

    def _print_besselj(self, expr, exp=None):
        order, arg = expr.args
        sup = "" if exp is None else "^{%s}" % exp
        return r"J_{%s}%s\!\left(%s\right)" % (self._print(order), sup, self._argument(arg))

    def _phase(self, arg: sp.Expr) -> str:
        """``3 psi``, ``(2n+1) psi``: the harmonic number before the phase."""
        ph = sp.Symbol("psi")
        if arg.has(ph):
            h = sp.expand(arg / ph)
            if not h.has(ph):
                if h == 1:
                    return r"\psi"
                if h.is_Integer:
                    return r"%s\psi" % self._print(h)
                return r"\left(%s\right)\psi" % self._print(h)
        return self._print(arg)

    def _print_cos(self, expr, exp=None):
        sup = "" if exp is None else "^{%s}" % exp
        return r"\cos%s\!\left(%s\right)" % (sup, self._phase(expr.args[0]))

    def _print_sin(self, expr, exp=None):
        sup = "" if exp is None else "^{%s}" % exp
        return r"\sin%s\!\left(%s\right)" % (sup, self._phase(expr.args[0]))

    def _print_Piecewise(self, expr):
        # only used for the sums that leave out |h| = 1: print the value with the condition
        (val, cond), *rest = expr.args
        return r"%s\,\Big|_{%s}" % (self._print(val), self._print(cond))


def latex(expr: sp.Expr, **settings) -> str:
    """LaTeX of ``expr`` in the package's notation (deterministic)."""
    return KBMLatexPrinter(settings).doprint(expr)


def _terms(expr: sp.Expr, order: str = "lex") -> list[sp.Expr]:
    printer = KBMLatexPrinter()
    if isinstance(expr, sp.Add):
        return list(printer._as_ordered_terms(expr, order=order))
    return [expr]


def _brace(tex: str, i: int) -> int:
    """Index just after the brace group that opens at ``tex[i] == '{'``."""
    depth = 0
    for j in range(i, len(tex)):
        if tex[j] == "{":
            depth += 1
        elif tex[j] == "}":
            depth -= 1
            if depth == 0:
                return j + 1
    return len(tex)


def visible_width(tex: str) -> float:
    r"""A rough estimate of the printed width of ``tex`` in characters.

    ``\frac{x}{y}`` counts as the wider of ``x`` and ``y``, scripts count 0.7,
    spacing and ``\left``/``\right`` nothing, a command such as ``\beta`` one.
    """
    w = 0.0
    i = 0
    n = len(tex)
    while i < n:
        c = tex[i]
        if tex.startswith(r"\frac", i) and i + 5 < n and tex[i + 5] == "{":
            j = _brace(tex, i + 5)
            k = _brace(tex, j) if j < n and tex[j] == "{" else j
            w += max(visible_width(tex[i + 6:j - 1]), visible_width(tex[j + 1:k - 1])) + 0.5
            i = k
        elif c == "\\":
            j = i + 1
            while j < n and tex[j].isalpha():
                j += 1
            name = tex[i + 1:j]
            if name in ("left", "right", "Big", "big", "quad", "displaystyle") or j == i + 1:
                w += 1.0 if name == "quad" else 0.0
                i = j + (1 if j == i + 1 else 0)
                continue
            w += {"sum": 2.0, "cos": 3.0, "sin": 3.0}.get(name, 1.0)
            i = j
        elif c in "^_":
            if i + 1 < n and tex[i + 1] == "{":
                j = _brace(tex, i + 1)
                w += 0.7 * visible_width(tex[i + 2:j - 1])
                i = j
            else:
                w += 0.7
                i += 2
        elif c in "{} ":
            i += 1
        else:
            w += 1.0
            i += 1
    return w


def _split_product(term: sp.Expr):
    """``c * (t1 + t2 + ...) * rest`` -> (prefix factors, the Add, suffix factors) or None."""
    if not isinstance(term, sp.Mul):
        return None
    adds = [f for f in term.args if isinstance(f, sp.Add)]
    if len(adds) != 1:
        return None
    add = adds[0]
    others = [f for f in term.args if f is not add]
    trig = [f for f in others if isinstance(f, (sp.sin, sp.cos))]
    pre = [f for f in others if f not in trig]
    return sp.Mul(*pre), add, sp.Mul(*trig)


def _bracketed(head: str, add: sp.Expr, tail: str, width: int) -> list[str]:
    inner = _pieces(add, width)
    out = [head + r"\Big[" + inner[0]] + inner[1:]
    out[-1] += r"\Big]" + (r"\," + tail if tail else "")
    return out


def _pieces(expr: sp.Expr, width: int, order: str = "lex") -> list[str]:
    """Signed LaTeX pieces of ``expr``: its top-level terms, long ones split inside."""
    pieces: list[str] = []
    for term in _terms(sp.sympify(expr), order):
        tex = latex(term)
        if visible_width(tex) <= width:
            pieces.append(tex)
            continue
        coeff, body = sp.Integer(1), term
        if isinstance(term, sp.Mul):
            sums = [f for f in term.args if isinstance(f, sp.Sum)]
            if len(sums) == 1:
                body = sums[0]
                coeff = term / body
        if isinstance(body, sp.Sum):
            lims = "".join(r"\sum_{%s=%s}^{%s}" % (latex(v), latex(lo), latex(hi))
                           for v, lo, hi in reversed(body.limits))
            head = ("" if coeff == 1 else ("-" if coeff == -1 else latex(coeff) + r"\,")) + lims
            f = body.function
            split = _split_product(f)
            if isinstance(f, sp.Add):
                pieces.extend(_bracketed(head, f, "", width))
                continue
            if split is not None:
                pre, add, trig = split
                head2 = head + ("" if pre == 1 else latex(pre) + r"\,")
                pieces.extend(_bracketed(head2, add, "" if trig == 1 else latex(trig), width))
                continue
        split = _split_product(term)
        if split is not None:
            pre, add, trig = split
            head = "" if pre == 1 else ("-" if pre == -1 else latex(pre) + r"\,")
            pieces.extend(_bracketed(head, add, "" if trig == 1 else latex(trig), width))
            continue
        pieces.append(tex)
    return [p if i == 0 or p.startswith(("+", "-")) else "+ " + p for i, p in enumerate(pieces)]


def _pack(pieces: list[str], width: int) -> list[str]:
    lines: list[str] = []
    cur = ""
    for p in pieces:
        if cur and visible_width(cur) + visible_width(p) > width:
            lines.append(cur)
            cur = p
        else:
            cur = (cur + " " + p).strip()
    lines.append(cur)
    return lines


def _join(lhs: str, lines: list[str]) -> str:
    out = f"{lhs} &= {lines[0]}"
    for ln in lines[1:]:
        out += " \\\\\n  &\\quad " + ln
    return out


def equation_lines(lhs: str, expr: sp.Expr, width: int = 90, order: str = "lex") -> str:
    """``lhs &= ...`` for an ``align`` environment, broken into lines of ~``width`` chars.

    Top-level terms are packed greedily; a single term longer than ``width`` that
    is an infinite sum is printed as ``\\sum [`` body terms ``]`` over several lines.
    ``order="rev-lex"`` puts the terms of a power series in increasing powers.
    """
    return _join(lhs, _pack(_pieces(expr, width, order), width))


def series_lines(lhs: str, lead: sp.Expr, orders: list[tuple[int, sp.Expr]],
                 width: int = 90) -> str:
    """``lhs &= lead + mu [c_1] + mu^2 [c_2] + ...``, each bracket broken like :func:`equation_lines`."""
    pieces: list[str] = [] if lead == 0 else [latex(lead)]
    for n, c in orders:
        c = sp.sympify(c)
        if c == 0:
            continue
        mu_tex = r"\mu" if n == 1 else r"\mu^{%d}" % n
        inner = _pieces(c, width)
        sign = "" if not pieces else "+ "
        if len(inner) == 1:
            pieces.append(sign + mu_tex + r"\left(" + inner[0] + r"\right)")
            continue
        pieces.append(sign + mu_tex + r"\Big[" + inner[0])
        pieces.extend(inner[1:])
        pieces[-1] += r"\Big]"
    if not pieces:
        pieces = ["0"]
    return _join(lhs, _pack(pieces, width))


def align_block(rows) -> str:
    """The rows (``lhs &= rhs``) as one LaTeX ``align*`` environment."""
    return "\\begin{align*}\n" + " \\\\\n".join(rows) + "\n\\end{align*}"
