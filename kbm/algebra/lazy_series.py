"""Lazy power series in the small parameter whose coefficients are Fourier series in psi.

``F(x, xdot)`` is evaluated along ``x = sum_n eps**n X_n`` and
``xdot = sum_n eps**n V_n`` once, as a tree of lazy nodes: coefficient ``n``
of every node is computed on first request and kept, so each product of
Fourier series is formed exactly once however high the order.  The leaves
``X`` and ``V`` are filled by the KBM recursion, order by order; the tree is
made by :class:`Builder`.  The nodes hold any
:class:`~kbm.algebra.base.FourierSeries`.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import sympy as sp

from ..errors import UnsupportedTermError
from ..symbols import x, xdot
from .base import FourierAlgebra

__all__ = ["Node", "Leaf", "Const", "Sum", "Product", "Scaled", "TrigOf", "Tail", "Builder",
           "unsupported_message", "trig_argument_message"]


class Node:
    """A power series in eps; subclasses say how coefficient ``n`` is made."""

    def __init__(self, zero: Callable[[], Any]):
        self._zero = zero
        self._memo: list[Any] = []

    def coeff(self, n: int):
        while len(self._memo) <= n:
            self._memo.append(self._make(len(self._memo)))
        return self._memo[n]

    def _make(self, n: int):  # pragma: no cover - abstract
        raise NotImplementedError


class Leaf(Node):
    """A series whose coefficients are appended from outside (``x`` and ``xdot``)."""

    def __init__(self, zero, first):
        super().__init__(zero)
        self._memo = [first]

    def append(self, value) -> None:
        self._memo.append(value)

    def _make(self, n: int):
        raise RuntimeError(f"coefficient {n} of x or xdot requested before it was solved for")


class Const(Node):
    def __init__(self, zero, value):
        super().__init__(zero)
        self._value = value

    def _make(self, n: int):
        return self._value if n == 0 else self._zero()


class Sum(Node):
    def __init__(self, zero, terms: list[Node]):
        super().__init__(zero)
        self._terms = terms

    def _make(self, n: int):
        acc = self._zero()
        for term in self._terms:
            c = term.coeff(n)
            if not c.is_zero():
                acc = acc + c
        return acc


class Scaled(Node):
    """A series times a coefficient independent of psi and eps."""

    def __init__(self, zero, node: Node, scale: Callable[[Any], Any]):
        super().__init__(zero)
        self._node = node
        self._scale = scale

    def _make(self, n: int):
        c = self._node.coeff(n)
        return c if c.is_zero() else self._scale(c)


class Product(Node):
    """Cauchy product; ``low`` skips the leading coefficients known to vanish."""

    def __init__(self, zero, left: Node, right: Node, low_left: int = 0, low_right: int = 0):
        super().__init__(zero)
        self._l, self._r = left, right
        self._ll, self._lr = low_left, low_right

    def _make(self, n: int):
        acc = self._zero()
        if self._l is self._r:  # a square: use the symmetry of the Cauchy product
            lo = self._ll
            for j in range(lo, n - lo + 1):
                k = n - j
                if k < j:
                    break
                c = self._l.coeff(j)
                if c.is_zero():
                    continue
                d = self._l.coeff(k)
                if d.is_zero():
                    continue
                p = c * d
                acc = acc + (p if k == j else p.scale_q(2))
            return acc
        for j in range(self._ll, n - self._lr + 1):
            lc = self._l.coeff(j)
            if lc.is_zero():
                continue
            rc = self._r.coeff(n - j)
            if rc.is_zero():
                continue
            acc = acc + lc * rc
        return acc


class TrigOf(Node):
    """``f(c x)`` for ``f`` in (sin, cos), by Taylor expansion about ``c x_0``.

    ``f(c x) = sum_m c**m Delta**m / m! f^(m)(c x_0)`` with
    ``Delta = x - x_0 = O(eps)``; ``derivs[m % 4]`` are the Fourier series of
    ``f^(m)(c x_0)`` (Jacobi-Anger), ``powers(m)`` the lazy series ``Delta**m``
    and ``weight(m)`` the factor ``c**m / m!``.
    """

    def __init__(self, zero, derivs: list[Any], powers: Callable[[int], Node],
                 weight: Callable[[int], Any]):
        super().__init__(zero)
        self._derivs = derivs
        self._powers = powers
        self._weight = weight

    def _make(self, n: int):
        if n == 0:
            return self._derivs[0]
        acc = self._zero()
        for m in range(1, n + 1):
            dm = self._powers(m).coeff(n)
            if dm.is_zero():
                continue
            acc = acc + (dm * self._derivs[m % 4]).scale(self._weight(m))
        return acc


class Tail(Node):
    """A series without its ``eps**0`` coefficient: ``Delta = x - x_0`` for ``x`` a leaf."""

    def __init__(self, zero, series: Node):
        super().__init__(zero)
        self._series = series

    def _make(self, n: int):
        return self._zero() if n == 0 else self._series.coeff(n)


# ----------------------------------------------------------------------------- F along the series
def unsupported_message(term: sp.Expr) -> str:
    """The message for a term of F that is not a polynomial times sin/cos.

    A non-smooth term gets its smooth replacement; any other the numeric backend.
    """
    from ..model.smooth_terms import non_smooth_message, non_smooth_term

    bad = non_smooth_term(term)
    if bad is not None:
        return non_smooth_message(bad)
    return (f"the term {term} of F is not supported by the symbolic engine: F must be a "
            "polynomial in x and xdot, possibly times sin(k*x) or cos(k*x); for any smooth F "
            "use the numeric backend (numeric_derive, or --numeric --a-range AMIN:AMAX on "
            "the command line)")


def trig_argument_message(term: sp.Expr) -> str:
    """The message for sin or cos of something other than ``k*x + phase``."""
    return (f"the term {term} of F is not supported: sin and cos must have an argument "
            "linear in x (k*x + phase), without xdot")


class Builder:
    """Turns ``F(x, xdot)`` into a tree of lazy series nodes over one algebra.

    ``X`` and ``V`` are the leaves ``x = sum eps**n X_n`` and
    ``xdot = sum eps**n V_n``; sums, products, integer powers (by squaring,
    shared between equal bases), coefficients free of ``x`` and ``xdot`` and
    ``sin``/``cos`` of ``k x + phase`` (Taylor series about ``k x_0``, see
    :class:`TrigOf`) become nodes.
    """

    def __init__(self, alg: FourierAlgebra, X: Leaf, V: Leaf):
        self.alg, self.X, self.V = alg, X, V
        self.leaves = {x: X, xdot: V}
        self.zero = alg.zero
        self._pow: dict[tuple, Node] = {}
        self._delta: Node | None = None

    def power(self, key, base: Node, e: int, low: int = 0) -> Node:
        """``base**e`` (memoised under ``key``); ``low``: leading coefficients that vanish."""
        if e == 1:
            return base
        k = (key, e)
        if k not in self._pow:
            half = self.power(key, base, e // 2, low)
            node = Product(self.zero, half, half, low * (e // 2), low * (e // 2))
            if e % 2:
                node = Product(self.zero, node, base, low * (e - 1), low)
            self._pow[k] = node
        return self._pow[k]

    def delta(self) -> Node:
        """``Delta = x - x_0`` (one node, shared by every sin and cos of F)."""
        if self._delta is None:
            self._delta = Tail(self.zero, self.X)
        return self._delta

    def build(self, expr: sp.Expr) -> Node:
        """The node of the sympy expression ``expr`` in the leaves (``x`` and ``xdot``):
        the skeleton of every exact builder (:class:`kbm.algebra.coupled.MultiBuilder` too);
        the leaves' test (:meth:`varies`), a constant factor (:meth:`scaled`) and the terms
        that are no sum, product or power (:meth:`other`) are the builder's."""
        if expr in self.leaves:
            return self.leaves[expr]
        if not self.varies(expr):
            return Const(self.zero, self.alg.const(expr))
        if expr.is_Add:
            return Sum(self.zero, [self.build(t) for t in expr.args])
        if expr.is_Mul:
            const = [f for f in expr.args if not self.varies(f)]
            var = [f for f in expr.args if self.varies(f)]
            node = self.build(var[0])
            for f in var[1:]:
                node = Product(self.zero, node, self.build(f))
            return self.scaled(node, sp.Mul(*const)) if const else node
        if expr.is_Pow and expr.exp.is_Integer and expr.exp > 0:
            return self.power(expr.base, self.build(expr.base), int(expr.exp))
        return self.other(expr)

    def varies(self, expr: sp.Expr) -> bool:
        """Whether ``expr`` holds ``x`` or ``xdot``."""
        return expr.has(x, xdot)

    def scaled(self, node: Node, const: sp.Expr) -> Node:
        """``node`` times the factor ``const``, free of the leaves."""
        c = self.alg.coef(const)
        return Scaled(self.zero, node, lambda s, c=c: self.alg.scale(s, c))

    def other(self, expr: sp.Expr) -> Node:
        """``sin`` or ``cos`` of ``k x + phase`` (:meth:`trig`); anything else is refused."""
        if isinstance(expr, (sp.sin, sp.cos)):
            return self.trig(expr)
        raise UnsupportedTermError(unsupported_message(expr))

    def trig(self, expr: sp.Expr) -> Node:
        """``sin(c x + d)`` or ``cos(c x + d)``: split the phase, then a :class:`TrigOf`."""
        arg = sp.expand(expr.args[0])
        c = arg.coeff(x)
        rest = sp.expand(arg - c * x)
        if c == 0 or c.has(x, xdot) or rest.has(x, xdot):
            raise UnsupportedTermError(trig_argument_message(expr))
        if rest != 0:  # sin(c x + d) = sin(c x) cos d + cos(c x) sin d, etc.
            f = type(expr)
            if f is sp.sin:
                new = sp.sin(c * x) * sp.cos(rest) + sp.cos(c * x) * sp.sin(rest)
            else:
                new = sp.cos(c * x) * sp.cos(rest) - sp.sin(c * x) * sp.sin(rest)
            return self.build(sp.expand(new))
        kind = "sin" if isinstance(expr, sp.sin) else "cos"
        derivs = self.alg.trig(kind, c)
        delta = self.delta()

        def powers(m: int, delta=delta) -> Node:
            return self.power("__delta__", delta, m, low=1)

        def weight(m: int, c=c):
            return c**m / sp.factorial(m)

        return TrigOf(self.zero, derivs, powers, weight)
