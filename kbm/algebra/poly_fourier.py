"""Finite real Fourier series in the phase ``psi`` with exact Laurent coefficients.

``f(psi) = sum_m c_m cos(m psi) + s_m sin(m psi)``, ``m >= 0``, each ``c_m``, ``s_m``
a :class:`~kbm.algebra.laurent.Laurent` polynomial in ``a``, the parameters and
``omega0``.  This is the representation of the polynomial KBM recursion:
products use the product-to-sum formulas, ``d/dpsi`` acts on the harmonic
index, ``d/da`` on the coefficients.  No integration over ``psi`` is ever done.

:class:`PolyAlgebra` offers these series to the recursion through the
:class:`~kbm.algebra.base.FourierAlgebra` protocol.
"""

from __future__ import annotations

from math import gcd as _gcd
from typing import TYPE_CHECKING

import sympy as sp

from ..errors import UnsupportedTermError
from ..symbols import a, psi
from .laurent import (Laurent, LaurentRing, Q, _fmpq_poly, _fmpz_poly, accumulate, merged,
                      term_product)

if TYPE_CHECKING:  # the models sit above the algebra; only their type is named here
    from ..model.builtins import Oscillator

__all__ = ["PolyFourier", "PolyAlgebra", "ring_generators"]

_HALF = Q(1, 2)


class PolyFourier:
    """A finite Fourier series; ``cos`` and ``sin`` map harmonic ``m`` to a coefficient."""

    __slots__ = ("ring", "cos", "sin", "_dense_form")

    def __init__(self, ring: LaurentRing, cos: dict | None = None, sin: dict | None = None):
        self.ring = ring
        self._dense_form = None
        self.cos = {m: c for m, c in (cos or {}).items() if c}
        self.sin = {m: c for m, c in (sin or {}).items() if c and m != 0}

    # -- construction ---------------------------------------------------------------
    @classmethod
    def constant(cls, ring: LaurentRing, c: Laurent) -> "PolyFourier":
        return cls(ring, {0: c})

    def is_zero(self) -> bool:
        return not self.cos and not self.sin

    # -- arithmetic -----------------------------------------------------------------
    def __add__(self, other: "PolyFourier") -> "PolyFourier":
        return PolyFourier(self.ring, merged(self.cos, other.cos), merged(self.sin, other.sin))

    def __neg__(self) -> "PolyFourier":
        return PolyFourier(self.ring, {m: -c for m, c in self.cos.items()},
                           {m: -c for m, c in self.sin.items()})

    def __sub__(self, other: "PolyFourier") -> "PolyFourier":
        return self + (-other)

    def scale(self, c: Laurent) -> "PolyFourier":
        """Multiply by a coefficient independent of ``psi``."""
        return PolyFourier(self.ring, {m: v * c for m, v in self.cos.items()},
                           {m: v * c for m, v in self.sin.items()})

    def scale_q(self, q) -> "PolyFourier":
        """Multiply by a rational number."""
        return PolyFourier(self.ring, {m: v.scale(q) for m, v in self.cos.items()},
                           {m: v.scale(q) for m, v in self.sin.items()})

    def __mul__(self, other: "PolyFourier") -> "PolyFourier":
        if self.ring.dense:
            return self._mul_dense(other)
        return self._mul_sparse(other)

    def _dense(self) -> tuple[int, int, dict, dict]:
        """``(low, den, cos, sin)``: every coefficient as an integer ``fmpz_poly`` in ``a``
        times ``a**(low - bias) / den`` (one-generator rings; ``low`` the lowest packed
        monomial, ``den`` a common denominator).  Made once per series (a series is
        immutable) and kept."""
        if self._dense_form is None:
            forms = [(k, m, c.dense()) for k, d in ((0, self.cos), (1, self.sin))
                     for m, c in d.items()]
            low = min(l for _, _, (l, _) in forms)
            den = 1
            for _, _, (_, p) in forms:
                d = int(p.denom())
                den = den * d // _gcd(den, d)
            polys: tuple[dict, dict] = ({}, {})
            for k, m, (l, p) in forms:
                q = p.numer() * (den // int(p.denom()))
                polys[k][m] = q.left_shift(l - low) if l > low else q
            self._dense_form = (low, den, *polys)
        return self._dense_form

    def _mul_dense(self, other: "PolyFourier") -> "PolyFourier":
        """:meth:`__mul__` for one-generator rings: the same product-to-sum formulas on
        dense integer polynomials over a common denominator (exact, the same result as
        the sparse product)."""
        ring = self.ring
        if self.is_zero() or other.is_zero():
            return PolyFourier(ring)
        low1, den1, cos1, sin1 = self._dense()
        low2, den2, cos2, sin2 = other._dense()
        top = max((*cos1, *sin1)) + max((*cos2, *sin2)) + 1
        zero = _fmpz_poly()
        cos = [zero] * top  # accumulated by harmonic; halved at the end
        sin = [zero] * top
        for m, c1 in cos1.items():
            for n, c2 in cos2.items():
                pr = c1 * c2
                k = m - n if m > n else n - m
                cos[k] = cos[k] + pr
                cos[m + n] = cos[m + n] + pr
        for cs, sn in ((cos1, sin2), (cos2, sin1)):  # cos A sin B = (sin(A+B) - sin(A-B))/2
            for m, c in cs.items():
                for n, s in sn.items():
                    pr = c * s  # exact integer polynomials: the order of the sums is free
                    sin[m + n] = sin[m + n] + pr
                    if n > m:
                        sin[n - m] = sin[n - m] + pr
                    elif n < m:
                        sin[m - n] = sin[m - n] - pr
        for m, s1 in sin1.items():
            for n, s2 in sin2.items():
                pr = s1 * s2
                k = m - n if m > n else n - m
                cos[k] = cos[k] + pr
                cos[m + n] = cos[m + n] - pr
        low = low1 + low2 - ring.bias_all
        den = 2 * den1 * den2  # 2: the product-to-sum factor 1/2

        def finish(polys: list) -> dict:
            return {m: Laurent.from_dense(ring, low, _fmpq_poly(p, den))
                    for m, p in enumerate(polys) if p}

        return PolyFourier(ring, finish(cos), finish(sin))

    def _mul_sparse(self, other: "PolyFourier") -> "PolyFourier":
        # Product-to-sum formulas, accumulated in place on raw term dicts:
        # cos m cos n = (cos(m-n) + cos(m+n))/2 ; sin m sin n = (cos(m-n) - cos(m+n))/2
        # sin m cos n = (sin(m+n) + sin(m-n))/2
        ring = self.ring
        bias = ring.bias_all
        cos: dict[int, dict] = {}
        sin: dict[int, dict] = {}

        def product(t1: dict, t2: dict) -> dict:
            return term_product(t1, t2, bias)

        acc = accumulate

        for m, c1 in self.cos.items():
            t1 = c1.terms
            for n, c2 in other.cos.items():
                pr = product(t1, c2.terms)
                acc(cos, abs(m - n), pr, 1)
                acc(cos, m + n, pr, 1)
        for cs, sn in ((self.cos, other.sin), (other.cos, self.sin)):  # cos A sin B
            for m, c in cs.items():
                t1 = c.terms
                for n, s in sn.items():
                    pr = product(t1, s.terms)
                    acc(sin, m + n, pr, 1)
                    if n != m:
                        acc(sin, abs(n - m), pr, 1 if n > m else -1)
        for m, s1 in self.sin.items():
            t1 = s1.terms
            for n, s2 in other.sin.items():
                pr = product(t1, s2.terms)
                acc(cos, abs(m - n), pr, 1)
                acc(cos, m + n, pr, -1)
        half = _HALF

        def finish(d: dict) -> dict:
            return {m: Laurent(ring, {k: v * half for k, v in t.items() if v})
                    for m, t in d.items()}

        return PolyFourier(ring, finish(cos), finish(sin))

    # -- calculus -------------------------------------------------------------------
    def dpsi(self) -> "PolyFourier":
        """``d/dpsi``."""
        return PolyFourier(self.ring,
                           {m: c.scale(m) for m, c in self.sin.items()},
                           {m: c.scale(-m) for m, c in self.cos.items() if m})

    def da(self) -> "PolyFourier":
        """``d/da`` (``a`` is generator 0 of the ring)."""
        return PolyFourier(self.ring, {m: c.diff(0) for m, c in self.cos.items()},
                           {m: c.diff(0) for m, c in self.sin.items()})

    # -- harmonic balance -------------------------------------------------------------
    def harmonic(self, m: int) -> tuple[Laurent, Laurent]:
        """The coefficients ``(c_m, s_m)`` of ``cos(m psi)`` and ``sin(m psi)``."""
        zero = self.ring.const(0)
        return self.cos.get(m, zero), self.sin.get(m, zero)

    def solve_without_first(self, omega0_sq_inv: Laurent) -> "PolyFourier":
        """Solve ``omega0**2 (u'' + u) = self`` harmonic by harmonic, dropping ``m = 1``."""
        cos = {m: c.scale(Q(1, 1 - m * m)) * omega0_sq_inv for m, c in self.cos.items()
               if m != 1}
        sin = {m: c.scale(Q(1, 1 - m * m)) * omega0_sq_inv for m, c in self.sin.items()
               if m != 1}
        return PolyFourier(self.ring, cos, sin)

    def as_expr(self, psi: sp.Symbol) -> sp.Expr:
        """The sympy expression, harmonics in increasing order, each coefficient as
        content x monomial x primitive polynomial (deterministic, no factoring)."""
        parts = []
        for m in sorted(self.cos):
            parts.append(self.cos[m].as_primitive_expr() * sp.cos(m * psi))
        for m in sorted(self.sin):
            parts.append(self.sin[m].as_primitive_expr() * sp.sin(m * psi))
        return sp.Add(*parts)


# ----------------------------------------------------------------------------- the adapter
def ring_generators(model: Oscillator) -> list[sp.Symbol]:
    """``[a, *parameters]``: the generators of the Laurent ring of ``model`` (parameters
    sorted by name, ``omega0`` among them when it is a symbol)."""
    syms = set().union(*(f.free_symbols for f in model.rhs)) | model.omegas[0].free_symbols
    params = sorted(syms - set(model.state), key=lambda s: s.name)
    return [a, *params]


class PolyAlgebra:
    """Exact arithmetic for polynomial F: Laurent coefficients in (a, parameters).

    Implements :class:`~kbm.algebra.base.FourierAlgebra` with series
    :class:`PolyFourier` and coefficients :class:`~kbm.algebra.laurent.Laurent`.
    """

    exact = True

    def __init__(self, model: Oscillator):
        self.ring = LaurentRing(ring_generators(model))
        w0 = model.omegas[0]
        if w0.is_Symbol:
            i = self.ring.gens.index(w0)
            self.w0 = self.ring.gen(i)
            self.w0inv = self.ring.gen(i, -1)
        else:
            self.w0 = self.ring.const(Q(int(w0.p), int(w0.q)))
            self.w0inv = self.ring.const(Q(int(w0.q), int(w0.p)))
        self.a_inv = self.ring.gen(0, -1)

    def zero(self) -> PolyFourier:
        return PolyFourier(self.ring)

    def const(self, expr: sp.Expr) -> PolyFourier:
        return PolyFourier.constant(self.ring, self.ring.from_expr(expr))

    def coef(self, expr: sp.Expr) -> Laurent:
        return self.ring.from_expr(expr)

    def x0(self) -> PolyFourier:
        return PolyFourier(self.ring, {1: self.ring.gen(0)})

    def scale(self, f: PolyFourier, c: Laurent) -> PolyFourier:
        return f.scale(c)

    def dpsi(self, f: PolyFourier) -> PolyFourier:
        return f.dpsi()

    def da(self, f: PolyFourier) -> PolyFourier:
        return f.da()

    def secular(self, R: PolyFourier) -> tuple[Laurent, Laurent]:
        c1, s1 = R.harmonic(1)
        half = Q(-1, 2)
        A = (s1 * self.w0inv).scale(half)
        B = (c1 * self.w0inv * self.a_inv).scale(half)
        return A, B

    def solve(self, R: PolyFourier) -> PolyFourier:
        return R.solve_without_first(self.w0inv * self.w0inv)

    def coef_expr(self, c: Laurent) -> sp.Expr:
        return c.as_primitive_expr() if c else sp.Integer(0)

    def series_expr(self, f: PolyFourier) -> sp.Expr:
        return f.as_expr(psi)

    def trig(self, kind: str, c: sp.Expr) -> list[PolyFourier]:  # pragma: no cover
        # unreachable: derive() sends F with sin/cos to the Bessel algebra
        raise UnsupportedTermError("sin/cos in the polynomial algebra")
