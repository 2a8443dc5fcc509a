"""The symbols shared by every module: the state, the KBM variables and the parameters.

All are plain :class:`sympy.Symbol` objects without assumptions, so that an
expression printed with :func:`str` and read back with :func:`parse` gives the
same symbols again.
"""

from __future__ import annotations

import ast
import re
from collections.abc import Iterable, Mapping

import sympy as sp
from sympy.parsing.sympy_parser import (convert_xor, parse_expr,
                                        standard_transformations)

from .errors import ModelError

__all__ = ["x", "xdot", "t", "a", "psi", "mu", "symbol", "parse", "PARSE_LOCALS", "FUNCTIONS"]

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


#: functions an expression may call (sympy's, by name); nothing else can be called
FUNCTIONS: Mapping[str, object] = {
    name: getattr(sp, name) for name in (
        "sin", "cos", "tan", "cot", "sec", "csc", "asin", "acos", "atan", "atan2",
        "sinh", "cosh", "tanh", "asinh", "acosh", "atanh", "exp", "log", "sqrt", "Abs",
        "sign", "floor", "ceiling", "Min", "Max", "erf", "erfc", "gamma", "besselj",
        "bessely", "besseli", "besselk", "Heaviside", "DiracDelta", "Piecewise", "Sum",
        "Rational", "Integer", "Float")}

#: longest expression :func:`parse` reads (a bound on the work of reading user input)
MAX_LENGTH = 20_000

_ALLOWED_NODES = (ast.Expression, ast.BinOp, ast.UnaryOp, ast.Name, ast.Load, ast.Constant,
                  ast.Call, ast.Tuple, ast.Add, ast.Sub, ast.Mult, ast.Div, ast.Pow, ast.Mod,
                  ast.USub, ast.UAdd, ast.BitXor, ast.keyword, ast.Compare, ast.Lt, ast.LtE,
                  ast.Gt, ast.GtE)


def _check_syntax(text: str) -> None:
    """Refuse anything but arithmetic on names, numbers and calls of :data:`FUNCTIONS`.

    The expression is parsed by Python's own parser (``ast``, which runs nothing);
    attribute access, subscripts, strings, lambdas, comprehensions, dunder names and
    calls of anything but a whitelisted function name are errors.
    """
    if len(text) > MAX_LENGTH:
        raise ModelError(f"the expression is {len(text)} characters long; at most "
                         f"{MAX_LENGTH} are read")
    try:
        tree = ast.parse(text.strip(), mode="eval")
    except SyntaxError as exc:
        raise ModelError(f"cannot read the expression {text!r}: {exc.msg}") from None
    nodes = list(ast.walk(tree))
    for node in nodes:  # the kind of syntax first: attributes, subscripts, lambdas, ...
        if not isinstance(node, _ALLOWED_NODES):
            raise ModelError(f"cannot read the expression {text!r}: "
                             f"{type(node).__name__} is not allowed (only arithmetic, numbers, "
                             "names and calls of mathematical functions)")
    for node in nodes:
        if isinstance(node, ast.Name) and (node.id.startswith("_") or "__" in node.id):
            raise ModelError(f"cannot read the expression {text!r}: the name {node.id!r} is "
                             "not allowed")
        if isinstance(node, ast.Constant) and not isinstance(node.value, (int, float)):
            raise ModelError(f"cannot read the expression {text!r}: only numbers are allowed "
                             f"as constants, not {node.value!r}")
        if isinstance(node, ast.Call) and not (isinstance(node.func, ast.Name)
                                               and node.func.id in FUNCTIONS):
            what = node.func.id if isinstance(node.func, ast.Name) else ast.unparse(node.func)
            raise ModelError(f"cannot read the expression {text!r}: {what!r} is not a known "
                             f"function (known: {', '.join(sorted(FUNCTIONS))})")


def parse(text: str | sp.Basic, extra: Iterable[str] = ()) -> sp.Expr:
    """Read an expression written with the package's symbol names, safely.

    ``beta``, ``gamma``, ``zeta`` and ``lambda`` are read as symbols, not as
    sympy's special functions, so this is the way to read back the strings in
    the command line's JSON output.  The text is checked with Python's parser
    first (:func:`_check_syntax`): only arithmetic, numbers, names and calls of
    the mathematical functions in :data:`FUNCTIONS` are read, so reading an
    untrusted string runs no code.  ``^`` is read as a power.

    Parameters
    ----------
    text
        The expression, e.g. ``"(1 - x**2)*xdot"``.
    extra
        Further names to read as plain symbols.

    Raises
    ------
    kbm.errors.ModelError
        If the text is not a valid expression or uses anything else.

    Examples
    --------
    >>> parse("a/2*(1 - beta*a**2/4)")
    a*(-a**2*beta/4 + 1)/2
    >>> parse("x.__class__")
    Traceback (most recent call last):
    ...
    kbm.errors.ModelError: cannot read the expression 'x.__class__': Attribute is not allowed ...
    """
    if isinstance(text, sp.Basic):
        return text
    if not isinstance(text, str):
        raise ModelError(f"an expression must be a string or a sympy expression, got "
                         f"{type(text).__name__}")
    # 'lambda' is a common parameter name and a Python keyword: read it as a symbol
    src = re.sub(r"\blambda\b", "lambda_", text)
    _check_syntax(src)
    loc: dict[str, object] = dict(PARSE_LOCALS)
    loc["lambda_"] = sp.Symbol("lambda")
    loc.update({name: sp.Symbol(name) for name in extra})
    glob: dict[str, object] = {"__builtins__": {}, "Symbol": sp.Symbol, "Integer": sp.Integer,
                               "Float": sp.Float, "Rational": sp.Rational, **FUNCTIONS}
    try:
        expr = parse_expr(src, local_dict=loc, global_dict=glob,
                          transformations=(*standard_transformations, convert_xor))
    except (sp.SympifyError, SyntaxError, TypeError, ValueError, NameError,
            AttributeError, ZeroDivisionError) as exc:
        raise ModelError(f"cannot read the expression {text!r}: {exc}") from None
    if not isinstance(expr, sp.Expr):
        raise ModelError(f"{text!r} is not an algebraic expression (it reads as {expr!r})")
    return expr
