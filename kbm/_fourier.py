"""Finite real Fourier series in the phase ``psi`` with exact Laurent coefficients.

``f(psi) = sum_m c_m cos(m psi) + s_m sin(m psi)``, ``m >= 0``, each ``c_m``, ``s_m``
a :class:`~kbm._laurent.Laurent` polynomial in ``a``, the parameters and
``omega0``.  This is the representation of the polynomial KBM recursion:
products use the product-to-sum formulas, ``d/dpsi`` acts on the harmonic
index, ``d/da`` on the coefficients.  No integration over ``psi`` is ever done.
"""

from __future__ import annotations

import sympy as sp

from ._laurent import Laurent, LaurentRing, _Q

__all__ = ["PolyFourier"]

_HALF = _Q(1, 2)


class PolyFourier:
    """A finite Fourier series; ``cos`` and ``sin`` map harmonic ``m`` to a coefficient."""

    __slots__ = ("ring", "cos", "sin")

    def __init__(self, ring: LaurentRing, cos: dict | None = None, sin: dict | None = None):
        self.ring = ring
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
        cos = dict(self.cos)
        for m, c in other.cos.items():
            cos[m] = cos[m] + c if m in cos else c
        sin = dict(self.sin)
        for m, c in other.sin.items():
            sin[m] = sin[m] + c if m in sin else c
        return PolyFourier(self.ring, cos, sin)

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
        cos: dict[int, Laurent] = {}
        sin: dict[int, Laurent] = {}

        def put(d, m, v):
            if m in d:
                d[m] = d[m] + v
            else:
                d[m] = v

        # cos m cos n = (cos(m-n) + cos(m+n))/2 ; sin m sin n = (cos(m-n) - cos(m+n))/2
        # sin m cos n = (sin(m+n) + sin(m-n))/2
        for m, c1 in self.cos.items():
            for n, c2 in other.cos.items():
                v = (c1 * c2).scale(_HALF)
                put(cos, abs(m - n), v)
                put(cos, m + n, v)
            for n, s2 in other.sin.items():
                v = (c1 * s2).scale(_HALF)
                put(sin, m + n, v)
                d = n - m
                if d > 0:
                    put(sin, d, v)
                elif d < 0:
                    put(sin, -d, -v)
        for m, s1 in self.sin.items():
            for n, c2 in other.cos.items():
                v = (s1 * c2).scale(_HALF)
                put(sin, m + n, v)
                d = m - n
                if d > 0:
                    put(sin, d, v)
                elif d < 0:
                    put(sin, -d, -v)
            for n, s2 in other.sin.items():
                v = (s1 * s2).scale(_HALF)
                put(cos, abs(m - n), v)
                put(cos, m + n, -v)
        return PolyFourier(self.ring, cos, sin)

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
        cos = {m: c.scale(_Q(1, 1 - m * m)) * omega0_sq_inv for m, c in self.cos.items()
               if m != 1}
        sin = {m: c.scale(_Q(1, 1 - m * m)) * omega0_sq_inv for m, c in self.sin.items()
               if m != 1}
        return PolyFourier(self.ring, cos, sin)

    def as_expr(self, psi: sp.Symbol) -> sp.Expr:
        """The sympy expression, harmonics in increasing order."""
        parts = []
        for m in sorted(self.cos):
            parts.append(self.cos[m].as_expr() * sp.cos(m * psi))
        for m in sorted(self.sin):
            parts.append(self.sin[m].as_expr() * sp.sin(m * psi))
        return sp.Add(*parts)
