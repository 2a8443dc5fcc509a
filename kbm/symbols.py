"""The symbols shared by every module: the state, the KBM variables and the parameters.

All are plain :class:`sympy.Symbol` objects without assumptions, so that an
expression printed with :func:`str` and read back with :func:`parse` gives the
same symbols again.
"""

from __future__ import annotations

import ast
import math
import re
from collections.abc import Iterable, Mapping

import sympy as sp
from sympy.parsing.sympy_parser import (convert_xor, parse_expr,
                                        standard_transformations)

from .errors import InputSizeError, ModelError, NonFiniteError

__all__ = ["x", "xdot", "t", "a", "psi", "mu", "symbol", "parse", "check_finite", "PARSE_LOCALS",
           "FUNCTIONS", "MAX_EXPONENT", "MAX_DIGITS", "MAX_LENGTH"]

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
    # read as what they are, so that check_finite refuses them (never as parameter names)
    "zoo": sp.zoo, "nan": sp.nan, "inf": sp.oo,
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

#: largest integer exponent :func:`parse` reads: ``x**1000`` is read, ``x**1001`` and
#: ``(x + 1)**100000`` are refused before sympy expands or evaluates anything
MAX_EXPONENT = 1000

#: most decimal digits of an integer literal, or of a power of number literals
#: (``9**1000`` has 955 digits and is read; ``10**10**10`` is refused while reading)
MAX_DIGITS = 2000

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
    _check_size(tree)
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


def _digits(node: ast.AST) -> float | None:
    """An upper bound on log10 of the absolute value of a constant subexpression, or
    ``None`` if the node is not built from number literals alone.

    Only the size is bounded (sums, products and powers of literals), so that no large
    integer is ever formed: a power whose exponent or result would pass
    :data:`MAX_EXPONENT` / :data:`MAX_DIGITS` raises :class:`ModelError` here.
    """
    if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)):
        v = abs(node.value)
        if v <= 1:
            return 0.0
        if isinstance(v, int) and v.bit_length() > 1000:
            return v.bit_length() * math.log10(2)
        return math.log10(v)
    if isinstance(node, ast.UnaryOp):
        return _digits(node.operand)
    if isinstance(node, ast.BinOp):
        left, right = _digits(node.left), _digits(node.right)
        if left is None or right is None:
            return None
        if isinstance(node.op, (ast.Pow, ast.BitXor)):
            return _power_digits(node, left, right)
        if isinstance(node.op, ast.Mult):
            return left + right
        return max(left, right) + 1
    return None


def _power_digits(node: ast.BinOp, base: float, exponent: float) -> float:
    if exponent > math.log10(MAX_EXPONENT) + 1e-12:
        raise InputSizeError(f"the exponent {_short(node.right)} is too large: powers with exponents "
                         f"above {MAX_EXPONENT} are not read (a bound on the work of reading "
                         "input); write a smaller power")
    digits = base * 10 ** exponent
    if digits > MAX_DIGITS:
        raise InputSizeError(f"the number {_short(node)} has about {digits:.3g} digits; numbers "
                         f"with more than {MAX_DIGITS} digits are not read (a bound on the "
                         "work of reading input)")
    return digits


def _short(node: ast.AST) -> str:
    text = ast.unparse(node)
    return text if len(text) <= 40 else text[:37] + "..."


def _check_size(tree: ast.AST) -> None:
    """Refuse integer literals and powers whose size passes :data:`MAX_DIGITS` or
    :data:`MAX_EXPONENT` before anything is evaluated or expanded."""
    for node in ast.walk(tree):
        if isinstance(node, ast.Constant) and isinstance(node.value, float) \
                and not math.isfinite(node.value):
            raise InputSizeError("a number literal is beyond 1.8e308 and overflows to infinity; "
                             "write a finite number")
        if isinstance(node, ast.Constant) and isinstance(node.value, int) \
                and not isinstance(node.value, bool) and node.value.bit_length() > 3.33 * MAX_DIGITS:
            raise InputSizeError(f"an integer literal with about "
                             f"{node.value.bit_length() * math.log10(2):.0f} digits is not read "
                             f"(at most {MAX_DIGITS} digits)")
        if isinstance(node, ast.BinOp) and isinstance(node.op, (ast.Pow, ast.BitXor)):
            exponent = _digits(node.right)
            if exponent is None:
                continue  # a symbolic exponent: sympy keeps it unevaluated
            base = _digits(node.left)
            if base is None:  # x**N: N bounded by MAX_EXPONENT
                _power_digits(node, 0.0, exponent)
            else:
                _power_digits(node, base, exponent)


def _nonfinite(expr: sp.Basic) -> sp.Basic | None:
    """The first non-finite constant (``oo``, ``zoo``, ``nan``) in ``expr``, outside the
    limits of a ``Sum`` (where ``oo`` is an index bound), or ``None``."""
    if expr in (sp.oo, -sp.oo, sp.zoo, sp.nan) or expr is sp.S.NaN:
        return expr
    if isinstance(expr, sp.Sum):
        return _nonfinite(expr.function)
    for arg in expr.args:
        found = _nonfinite(arg)
        if found is not None:
            return found
    return None


def check_finite(expr: sp.Basic, what: str) -> None:
    """Raise :class:`ModelError` if ``expr`` holds ``oo``, ``zoo`` or ``nan`` (a division by
    zero reads as ``zoo``), naming ``what`` it is."""
    bad = _nonfinite(expr)
    if bad is not None:
        raise NonFiniteError(f"{what} contains the non-finite constant {bad} (infinity, complex "
                         "infinity from a division by zero, or nan); write a finite expression")


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
    check_finite(expr, f"the expression {text!r}")
    return expr
