"""Finite real Fourier series in two angles ``(psi, theta)`` with exact Laurent coefficients.

``f(psi, theta) = sum c_{m,k} cos(m psi + k theta) + s_{m,k} sin(m psi + k theta)`` over
*canonical* index pairs (``m > 0``, or ``m = 0`` and ``k >= 0``); each coefficient is a
:class:`~kbm.algebra.laurent.Laurent` polynomial in the amplitude ``a``, the parameters
and the detuning.  This is the representation of the forced KBM recursion
(:mod:`kbm.forced.engine`): ``psi`` is the oscillator's phase, ``theta = nu t`` the
forcing angle.  Products use the product-to-sum formulas, ``d/dpsi`` and ``d/dtheta``
act on the indices, ``d/da`` on the coefficients; no integral is ever done.

The series satisfies the ring protocol the lazy eps-series of
:mod:`kbm.algebra.lazy_series` need (``+``, ``-``, ``*``, ``scale``, ``scale_q``,
``is_zero``).
"""

from __future__ import annotations

import sympy as sp

from ..algebra.laurent import Laurent, LaurentRing, Q, accumulate, term_product

__all__ = ["TwoAngle", "canonical"]

_HALF = Q(1, 2)


def canonical(m: int, k: int) -> tuple[int, int, int]:
    """``(m', k', sign)`` with ``(m', k')`` canonical and ``m psi + k theta = sign (m' psi +
    k' theta)``."""
    if m > 0 or (m == 0 and k >= 0):
        return m, k, 1
    return -m, -k, -1


class TwoAngle:
    """A finite Fourier series in ``(psi, theta)``; ``cos``/``sin`` map ``(m, k)`` to a
    :class:`Laurent` coefficient."""

    __slots__ = ("ring", "cos", "sin")

    def __init__(self, ring: LaurentRing, cos: dict | None = None, sin: dict | None = None):
        self.ring = ring
        self.cos = {mk: c for mk, c in (cos or {}).items() if c}
        self.sin = {mk: c for mk, c in (sin or {}).items() if c and mk != (0, 0)}

    # -- construction ---------------------------------------------------------------
    @classmethod
    def harmonic(cls, ring: LaurentRing, m: int, k: int, c: Laurent,
                 kind: str = "cos") -> "TwoAngle":
        """``c cos(m psi + k theta)`` (or ``sin``), any sign of ``(m, k)``."""
        m, k, sign = canonical(m, k)
        if kind == "cos":
            return cls(ring, {(m, k): c})
        return cls(ring, sin={(m, k): c if sign > 0 else -c})

    def is_zero(self) -> bool:
        return not self.cos and not self.sin

    def harmonics(self) -> set[tuple[int, int]]:
        """The index pairs with a nonzero coefficient."""
        return set(self.cos) | set(self.sin)

    # -- arithmetic -----------------------------------------------------------------
    def __add__(self, other: "TwoAngle") -> "TwoAngle":
        if other.is_zero():
            return self
        if self.is_zero():
            return other
        cos = dict(self.cos)
        for mk, c in other.cos.items():
            cos[mk] = cos[mk] + c if mk in cos else c
        sin = dict(self.sin)
        for mk, c in other.sin.items():
            sin[mk] = sin[mk] + c if mk in sin else c
        return TwoAngle(self.ring, cos, sin)

    def __neg__(self) -> "TwoAngle":
        return TwoAngle(self.ring, {mk: -c for mk, c in self.cos.items()},
                        {mk: -c for mk, c in self.sin.items()})

    def __sub__(self, other: "TwoAngle") -> "TwoAngle":
        return self + (-other)

    def scale(self, c) -> "TwoAngle":
        """Multiply by a :class:`Laurent` coefficient or (as the lazy series do for constant
        factors of ``F``) by another :class:`TwoAngle` series."""
        if isinstance(c, TwoAngle):
            return self * c
        return TwoAngle(self.ring, {mk: v * c for mk, v in self.cos.items()},
                        {mk: v * c for mk, v in self.sin.items()})

    def scale_q(self, q) -> "TwoAngle":
        """Multiply by a rational number."""
        return TwoAngle(self.ring, {mk: v.scale(q) for mk, v in self.cos.items()},
                        {mk: v.scale(q) for mk, v in self.sin.items()})

    def __mul__(self, other: "TwoAngle") -> "TwoAngle":
        # cos A cos B = (cos(A-B) + cos(A+B))/2      sin A sin B = (cos(A-B) - cos(A+B))/2
        # sin A cos B = (sin(A+B) + sin(A-B))/2      cos A sin B = (sin(A+B) - sin(A-B))/2
        bias = self.ring.bias_all
        cos: dict = {}
        sin: dict = {}

        def product(t1: dict, t2: dict) -> dict:
            return term_product(t1, t2, bias)

        for (m1, k1), c1 in self.cos.items():
            t1 = c1.terms
            for (m2, k2), c2 in other.cos.items():
                pr = product(t1, c2.terms)
                a_, b_, _ = canonical(m1 - m2, k1 - k2)
                accumulate(cos, (a_, b_), pr, 1)
                accumulate(cos, canonical(m1 + m2, k1 + k2)[:2], pr, 1)
            for (m2, k2), s2 in other.sin.items():  # cos A sin B
                pr = product(t1, s2.terms)
                a_, b_, sg = canonical(m1 + m2, k1 + k2)
                accumulate(sin, (a_, b_), pr, sg)
                a_, b_, sg = canonical(m1 - m2, k1 - k2)
                accumulate(sin, (a_, b_), pr, -sg)
        for (m1, k1), s1 in self.sin.items():
            t1 = s1.terms
            for (m2, k2), c2 in other.cos.items():  # sin A cos B
                pr = product(t1, c2.terms)
                a_, b_, sg = canonical(m1 + m2, k1 + k2)
                accumulate(sin, (a_, b_), pr, sg)
                a_, b_, sg = canonical(m1 - m2, k1 - k2)
                accumulate(sin, (a_, b_), pr, sg)
            for (m2, k2), s2 in other.sin.items():
                pr = product(t1, s2.terms)
                accumulate(cos, canonical(m1 - m2, k1 - k2)[:2], pr, 1)
                accumulate(cos, canonical(m1 + m2, k1 + k2)[:2], pr, -1)
        ring = self.ring

        def finish(d: dict) -> dict:
            return {mk: Laurent(ring, {mono: v * _HALF for mono, v in t.items() if v})
                    for mk, t in d.items()}

        return TwoAngle(ring, finish(cos), finish(sin))

    # -- calculus -------------------------------------------------------------------
    def d_angle(self, which: int) -> "TwoAngle":
        """``d/dpsi`` (``which = 0``) or ``d/dtheta`` (``which = 1``)."""
        cos = {mk: c.scale(mk[which]) for mk, c in self.sin.items() if mk[which]}
        sin = {mk: c.scale(-mk[which]) for mk, c in self.cos.items() if mk[which]}
        return TwoAngle(self.ring, cos, sin)

    def da(self) -> "TwoAngle":
        """``d/da`` (``a`` is generator 0 of the ring)."""
        return TwoAngle(self.ring, {mk: c.diff(0) for mk, c in self.cos.items()},
                        {mk: c.diff(0) for mk, c in self.sin.items()})

    def split(self, keep) -> tuple["TwoAngle", "TwoAngle"]:
        """``(part with keep(m, k) true, the rest)``."""
        yes = TwoAngle(self.ring, {mk: c for mk, c in self.cos.items() if keep(*mk)},
                       {mk: c for mk, c in self.sin.items() if keep(*mk)})
        no = TwoAngle(self.ring, {mk: c for mk, c in self.cos.items() if not keep(*mk)},
                      {mk: c for mk, c in self.sin.items() if not keep(*mk)})
        return yes, no

    def map_coefficients(self, fn) -> "TwoAngle":
        """``fn((m, k), c)`` applied to every coefficient (the same harmonic kept)."""
        return TwoAngle(self.ring, {mk: fn(mk, c) for mk, c in self.cos.items()},
                        {mk: fn(mk, c) for mk, c in self.sin.items()})

    # -- display --------------------------------------------------------------------
    def as_expr(self, psi: sp.Symbol, theta: sp.Symbol) -> sp.Expr:
        """The sympy expression, harmonics in a fixed order (deterministic, no factoring)."""
        parts = []
        for mk in sorted(self.cos):
            parts.append(self.cos[mk].as_primitive_expr() * sp.cos(mk[0] * psi + mk[1] * theta))
        for mk in sorted(self.sin):
            parts.append(self.sin[mk].as_primitive_expr() * sp.sin(mk[0] * psi + mk[1] * theta))
        return sp.Add(*parts)
