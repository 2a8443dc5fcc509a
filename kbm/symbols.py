"""The symbols shared by every module: the state, the KBM variables and the parameters.

All are plain :class:`sympy.Symbol` objects without assumptions, so that an
expression printed with :func:`str` and read back with :func:`parse` gives the
same symbols again.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping

import sympy as sp

from .errors import ModelError

__all__ = ["x", "xdot", "t", "a", "psi", "mu", "symbol", "parse", "PARSE_LOCALS"]

#: displacement of the oscillator
x = sp.Symbol("x")
#: velocity of the oscillator
xdot = sp.Symbol("xdot")
#: time
t = sp.Symbol("t")
#: first-harmonic amplitude of the KBM expansion
a = sp.Symbol("a")
#: total phase of the KBM expansion
psi = sp.Symbol("psi")
#: the small parameter (the paper's mu; epsilon in the textbooks)
mu = sp.Symbol("mu")

# Names that sympy.sympify would turn into functions or constants.  They are
# read as plain symbols here (beta, zeta, gamma, lambda are common parameter names).
_SHADOWED = ("beta", "gamma", "zeta", "lambda", "lam", "E", "I", "N", "O", "Q", "S", "k",
             "Delta", "delta", "Omega", "omega", "kappa", "alpha", "eta", "nu", "sigma", "v")


def symbol(name: str) -> sp.Symbol:
    """Return the plain symbol called ``name`` (the one every module uses)."""
    return sp.Symbol(name)


#: ``locals`` for :func:`sympy.sympify` that read the parameter names as symbols
PARSE_LOCALS: Mapping[str, sp.Basic] = {
    **{name: sp.Symbol(name) for name in _SHADOWED},
    "x": x, "xdot": xdot, "t": t, "a": a, "psi": psi, "mu": mu,
    "besselj": sp.besselj, "Sum": sp.Sum, "oo": sp.oo, "pi": sp.pi,
}


def parse(text: str | sp.Basic, extra: Iterable[str] = ()) -> sp.Expr:
    """Read an expression written with the package's symbol names.

    ``beta``, ``gamma``, ``zeta`` and ``lambda`` are read as symbols, not as
    sympy's special functions, so this is the way to read back the strings in
    the command line's JSON output.

    Parameters
    ----------
    text
        The expression, e.g. ``"(1 - x**2)*xdot"``.
    extra
        Further names to read as plain symbols.

    Raises
    ------
    kbm.errors.ModelError
        If the text is not a valid expression.

    Examples
    --------
    >>> parse("a/2*(1 - beta*a**2/4)")
    a*(-a**2*beta/4 + 1)/2
    """
    if isinstance(text, sp.Basic):
        return text
    loc = dict(PARSE_LOCALS)
    loc.update({name: sp.Symbol(name) for name in extra})
    try:
        expr = sp.sympify(text, locals=loc)
    except (sp.SympifyError, SyntaxError, TypeError, ValueError) as exc:
        raise ModelError(f"cannot read the expression {text!r}: {exc}") from None
    if not isinstance(expr, sp.Expr):
        raise ModelError(f"{text!r} is not an algebraic expression (it reads as {expr!r})")
    return expr
