"""Finite real Fourier series in ``n`` angles with exact Laurent coefficients.

``f(psi) = sum_h c_h cos(h . psi) + s_h sin(h . psi)`` over *canonical* integer vectors
``h`` (the first nonzero entry positive, or ``h = 0``); each coefficient is a
:class:`~kbm.algebra.laurent.Laurent` polynomial in the amplitudes, the parameters and
the detunings.  It is the representation of the coupled KBM recursion
(:mod:`kbm.expansion.coupled`): ``psi = (psi_1, ..., psi_N)`` are the phases of the ``N``
oscillators (and the forcing angle ``theta`` last, when forced).  Products use the
product-to-sum formulas, ``d/dpsi_l`` acts on the indices and ``d/da_l`` on the
coefficients; no integral is ever done.  The forced recursion of one oscillator
(:mod:`kbm.expansion.forced`) is the case ``n = 2``, ``(psi, theta)``.

The series satisfies the ring protocol the lazy eps-series of
:mod:`kbm.algebra.lazy_series` need (``+``, ``-``, ``*``, ``scale``, ``scale_q``,
``is_zero``).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from functools import lru_cache

import sympy as sp

from .laurent import Laurent, LaurentRing, Q, accumulate, merged, term_product

__all__ = ["MultiAngle", "canonical", "forcing_harmonics"]

_HALF = Q(1, 2)


def canonical(h: tuple[int, ...]) -> tuple[tuple[int, ...], int]:
    """``(h', sign)`` with ``h'`` canonical and ``h . psi = sign (h' . psi)``."""
    for v in h:
        if v > 0:
            return h, 1
        if v < 0:
            return tuple(-w for w in h), -1
    return h, 1


@lru_cache(maxsize=1 << 16)
def _sum_difference(h1: tuple, h2: tuple) -> tuple[tuple, int, tuple, int]:
    """``(h+, s+, h-, s-)``: ``h1 + h2`` and ``h1 - h2`` canonical, with their signs.

    Pure-function memo (the same pairs of harmonics recur in every product): the key is two
    tuples of integers, the value tuples of integers computed from them alone."""
    plus, sp_ = canonical(tuple(p + q for p, q in zip(h1, h2)))
    minus, sm = canonical(tuple(p - q for p, q in zip(h1, h2)))
    return plus, sp_, minus, sm


class MultiAngle:
    """A finite Fourier series in ``n`` angles; ``cos``/``sin`` map index tuples to
    :class:`Laurent` coefficients."""

    __slots__ = ("ring", "n", "cos", "sin")

    def __init__(self, ring: LaurentRing, n: int, cos: dict | None = None,
                 sin: dict | None = None):
        self.ring, self.n = ring, n
        zero = (0,) * n
        self.cos = {h: c for h, c in (cos or {}).items() if c}
        self.sin = {h: c for h, c in (sin or {}).items() if c and h != zero}

    # -- construction ---------------------------------------------------------------
    @classmethod
    def harmonic(cls, ring: LaurentRing, h: Sequence[int], c: Laurent,
                 kind: str = "cos") -> "MultiAngle":
        """``c cos(h . psi)`` (or ``sin``), any sign of ``h``."""
        h, sign = canonical(tuple(h))
        if kind == "cos":
            return cls(ring, len(h), {h: c})
        return cls(ring, len(h), sin={h: c if sign > 0 else -c})

    def _new(self, cos: dict, sin: dict) -> "MultiAngle":
        return MultiAngle(self.ring, self.n, cos, sin)

    def is_zero(self) -> bool:
        return not self.cos and not self.sin

    def harmonics(self) -> set[tuple[int, ...]]:
        """The index vectors with a nonzero coefficient."""
        return set(self.cos) | set(self.sin)

    # -- arithmetic -----------------------------------------------------------------
    def __add__(self, other: "MultiAngle") -> "MultiAngle":
        if other.is_zero():
            return self
        if self.is_zero():
            return other
        return self._new(merged(self.cos, other.cos), merged(self.sin, other.sin))

    def __neg__(self) -> "MultiAngle":
        return self._new({h: -c for h, c in self.cos.items()},
                         {h: -c for h, c in self.sin.items()})

    def __sub__(self, other: "MultiAngle") -> "MultiAngle":
        return self + (-other)

    def scale(self, c) -> "MultiAngle":
        """Multiply by a :class:`Laurent` coefficient or by another series."""
        if isinstance(c, MultiAngle):
            return self * c
        return self._new({h: v * c for h, v in self.cos.items()},
                         {h: v * c for h, v in self.sin.items()})

    def scale_q(self, q) -> "MultiAngle":
        """Multiply by a rational number."""
        return self._new({h: v.scale(q) for h, v in self.cos.items()},
                         {h: v.scale(q) for h, v in self.sin.items()})

    def __mul__(self, other: "MultiAngle") -> "MultiAngle":
        # cos A cos B = (cos(A-B) + cos(A+B))/2      sin A sin B = (cos(A-B) - cos(A+B))/2
        # sin A cos B = (sin(A+B) + sin(A-B))/2      cos A sin B = (sin(A+B) - sin(A-B))/2
        bias = self.ring.bias_all
        cos: dict = {}
        sin: dict = {}
        for a, b, sign in ((self.cos, other.cos, 1), (self.sin, other.sin, -1)):
            for h1, c1 in a.items():  # cos A cos B, then sin A sin B
                t1 = c1.terms
                for h2, c2 in b.items():
                    pr = term_product(t1, c2.terms, bias)
                    plus, _, minus, _ = _sum_difference(h1, h2)
                    accumulate(cos, minus, pr, 1)
                    accumulate(cos, plus, pr, sign)
        for cs, sn in ((self.cos, other.sin), (other.cos, self.sin)):  # cos A sin B
            for h1, c1 in cs.items():
                t1 = c1.terms
                for h2, s2 in sn.items():
                    pr = term_product(t1, s2.terms, bias)
                    plus, sp_, minus, sm = _sum_difference(h1, h2)
                    accumulate(sin, plus, pr, sp_)
                    accumulate(sin, minus, pr, -sm)
        ring = self.ring

        def finish(d: dict) -> dict:
            return {h: Laurent(ring, {m: v * _HALF for m, v in t.items() if v})
                    for h, t in d.items()}

        return self._new(finish(cos), finish(sin))

    # -- calculus -------------------------------------------------------------------
    def d_angle(self, which: int) -> "MultiAngle":
        """``d/dpsi_which`` (angles counted from 0)."""
        cos = {h: c.scale(h[which]) for h, c in self.sin.items() if h[which]}
        sin = {h: c.scale(-h[which]) for h, c in self.cos.items() if h[which]}
        return self._new(cos, sin)

    def diff(self, gen: int) -> "MultiAngle":
        """``d/dg`` for the ring's generator ``gen`` (an amplitude)."""
        return self._new({h: c.diff(gen) for h, c in self.cos.items()},
                         {h: c.diff(gen) for h, c in self.sin.items()})

    def split(self, keep: Callable[[tuple], bool]) -> tuple["MultiAngle", "MultiAngle"]:
        """``(part with keep(h) true, the rest)``."""
        yes = self._new({h: c for h, c in self.cos.items() if keep(h)},
                        {h: c for h, c in self.sin.items() if keep(h)})
        no = self._new({h: c for h, c in self.cos.items() if not keep(h)},
                       {h: c for h, c in self.sin.items() if not keep(h)})
        return yes, no

    def map_coefficients(self, fn) -> "MultiAngle":
        """``fn(h, c)`` applied to every coefficient (the same harmonic kept)."""
        return self._new({h: fn(h, c) for h, c in self.cos.items()},
                         {h: fn(h, c) for h, c in self.sin.items()})

    # -- display --------------------------------------------------------------------
    def as_expr(self, angles: Sequence[sp.Expr]) -> sp.Expr:
        """The sympy expression in the given angle expressions, harmonics in a fixed order
        (deterministic, no factoring)."""
        parts = []
        for kind, table, fn in (("cos", self.cos, sp.cos), ("sin", self.sin, sp.sin)):
            for h in sorted(table):
                arg = sp.Add(*[v * g for v, g in zip(h, angles) if v])
                parts.append(table[h].as_primitive_expr() * (fn(arg) if any(h) else 1))
        return sp.Add(*parts)


def forcing_harmonics(expr: sp.Expr, theta: sp.Symbol):
    """``expr``, a polynomial in the parameters and in ``cos``/``sin`` of multiples of the
    forcing angle ``theta``, as harmonics of ``theta``: yields ``(k, kind, c)`` for the terms
    ``c cos(k theta)`` (``kind = "cos"``; ``k = 0`` the mean) and ``c sin(k theta)``, products
    reduced to sums first (``TR8``) and ``cos(k theta + c0)`` split by the addition formulas.
    The exact forced and coupled algebras build their constants from it.

    Raises
    ------
    kbm.errors.ModelError
        A term that is not a parameter coefficient times one ``cos``/``sin`` of
        ``k theta + c0`` with an integer ``k``.
    """
    from sympy.simplify.fu import TR8

    from ..errors import ModelError

    e = sp.expand(TR8(expr)) if expr.has(sp.sin, sp.cos) else sp.expand(expr)
    for term in sp.Add.make_args(e):
        trig = [f for f in sp.Mul.make_args(term) if f.has(theta)]
        if not trig:  # the mean (of a product of forcing terms too: a hard forcing's square)
            yield 0, "cos", term
            continue
        coeff = sp.Mul(*[f for f in sp.Mul.make_args(term) if not f.has(theta)])
        if len(trig) != 1 or not isinstance(trig[0], (sp.sin, sp.cos)):
            raise ModelError(f"the term {term} is not a polynomial in the state times "
                             "cos or sin of a multiple of theta")
        f = trig[0]
        arg = sp.expand(f.args[0])
        k = arg.coeff(theta)
        c = sp.expand(arg - k * theta)
        if not k.is_Integer or c.has(theta):
            raise ModelError(f"{f}: the forcing enters as cos(k theta + c), sin(k theta + "
                             "c) with an integer k (2 pi-periodic in theta)")
        kinds = [("cos", sp.cos(c)), ("sin", -sp.sin(c))] if isinstance(f, sp.cos) \
            else [("sin", sp.cos(c)), ("cos", sp.sin(c))]
        for kind, w in kinds:
            if w != 0:
                yield int(k), kind, coeff * w
