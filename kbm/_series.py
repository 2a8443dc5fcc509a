"""Lazy power series in the small parameter whose coefficients are Fourier series in psi.

``F(x, xdot)`` is evaluated along ``x = sum_n eps**n X_n`` and
``xdot = sum_n eps**n V_n`` once, as a tree of lazy nodes: coefficient ``n``
of every node is computed on first request and kept, so each product of
Fourier series is formed exactly once however high the order.  The leaves
``X`` and ``V`` are filled by the KBM recursion, order by order.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

__all__ = ["Node", "Leaf", "Const", "Sum", "Product", "Scaled", "TrigOf"]


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
