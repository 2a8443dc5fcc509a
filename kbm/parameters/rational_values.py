"""Exact parameter values along a line without sympy: rational expressions as nested lists
and their values in :class:`fractions.Fraction` arithmetic.

A derived scaled value such as ``delta = Delta/mu`` (paper eq. 3) is a rational function
with rational coefficients of the values given.  Along a parameter line
(:class:`kbm.parameters.bound.ParameterLine`) its exact value is needed thousands of times: here it
is computed from a tree of the expression (:func:`rational_tree`) with fractions, correctly
rounded to float as sympy's exact value is.  The same trees are kept in the line cards of
:mod:`numerics.flow.line_card`, whose lines give the same floats by the same code
(:func:`line_floats`) without importing sympy.  This module imports nothing heavy.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from fractions import Fraction
from typing import Any

from ..errors import ParameterError

__all__ = ["rational_tree", "tree_value", "line_floats", "line_rates"]


def rational_tree(expr: Any) -> list | None:
    """A sympy expression built of symbols and rationals by ``+``, ``*`` and integer powers
    as nested lists (``["s", name]``, ``["q", p, q]``, ``["+", ...]``, ``["*", ...]``,
    ``["^", base, n]``), or ``None`` for any other expression (not exact in fractions).
    Read from the expression's attributes: sympy is not imported here."""
    if expr.is_Symbol:
        return ["s", expr.name]
    if expr.is_Rational:
        return ["q", int(expr.p), int(expr.q)]
    if expr.is_Add or expr.is_Mul:
        args = [rational_tree(a) for a in expr.args]
        return None if any(a is None for a in args) else ["+" if expr.is_Add else "*", *args]
    if expr.is_Pow and expr.exp.is_Integer:
        base = rational_tree(expr.base)
        return None if base is None else ["^", base, int(expr.exp)]
    return None


def tree_value(tree: Sequence, env: Mapping[str, Fraction]) -> Fraction:
    """The exact value of :func:`rational_tree`'s form at ``env`` (fractions by name).

    Raises
    ------
    ZeroDivisionError
        Where a denominator vanishes (the value is undefined).
    """
    op = tree[0]
    if op == "s":
        return env[tree[1]]
    if op == "q":
        return Fraction(int(tree[1]), int(tree[2]))
    if op == "+":
        return sum((tree_value(a, env) for a in tree[1:]), Fraction(0))
    if op == "*":
        out = Fraction(1)
        for a in tree[1:]:
            out *= tree_value(a, env)
        return out
    if op == "^":
        return tree_value(tree[1], env) ** int(tree[2])
    raise ValueError(f"unknown node {op!r}")


def line_floats(vary: str, value: float, fractions: Mapping[str, Fraction], direct: bool,
                derived: Sequence[tuple[str, Sequence]],
                undefined: Callable[[str], object]) -> tuple[dict[str, float], dict]:
    """The float values that change along a line at ``vary = value``, and the exact ones.

    Parameters
    ----------
    vary, value
        The varied name and its value (a float, read exactly as its shortest repr).
    fractions
        The exact values the derived expressions need besides ``vary``.
    direct
        Whether ``vary`` is itself a value of the model (then it is in the result).
    derived
        ``(scaled, tree)`` in order: each derived value by its :func:`rational_tree`
        (a later one may use an earlier one).
    undefined
        Called with the scaled name whose value is undefined (a vanishing denominator),
        to raise the caller's error; the :class:`ZeroDivisionError` is raised if it
        returns.

    Returns
    -------
    ``(floats, env)``: the float values by name (``vary`` first where ``direct``, then
    the derived ones), and every exact value by name.

    Raises
    ------
    kbm.errors.ParameterError
        If ``value`` is not finite.
    """
    if not math.isfinite(value):
        raise ParameterError(f"parameter {vary} must be a finite real number, got {value!r}")
    env = dict(fractions)
    env[vary] = Fraction(repr(float(value)))
    out = {vary: float(env[vary])} if direct else {}
    for scaled, tree in derived:
        try:
            new = tree_value(tree, env)
        except ZeroDivisionError:
            undefined(scaled)
            raise
        env[scaled] = new
        out[scaled] = float(new)
    return out, env


def line_rates(vary: str, value: float, given: Mapping[str, float], direct: bool,
               rates: Sequence[tuple[str, Callable, Sequence[str]]]) -> dict[str, float]:
    """``d(value)/d(vary)`` at ``vary = value`` of the values that change along a line (1 for
    ``vary`` where ``direct``; ``f(*need)`` of each ``(scaled, f, need)``): line and card alike."""
    env = dict(given)
    env[vary] = float(value)
    out = {vary: 1.0} if direct else {}
    for scaled, f, need in rates:
        out[scaled] = float(f(*(env[n] for n in need)))
    return out
