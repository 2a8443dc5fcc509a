"""Sparse Laurent polynomials with exact rational coefficients.

The coefficients of the Fourier series in the polynomial KBM recursion are
Laurent polynomials in the amplitude ``a``, the parameters and ``omega0``:
the recursion divides only by ``2 omega0 a``, ``omega0**2`` and integers, so the
ring ``Q[g1, 1/g1, ..., gk, 1/gk]`` is closed under every operation it needs and
all arithmetic stays exact.

A monomial is packed into one Python integer (16 bits per generator, biased),
so that multiplying monomials is one integer addition.
"""

from __future__ import annotations

from collections.abc import Sequence
from math import gcd as _gcd

import sympy as sp
from sympy.core.add import _addsort

# Q: the exact rational number type of the coefficients (gmpy2.mpq, else fractions.Fraction).
try:  # gmpy2 makes rational arithmetic several times faster
    from gmpy2 import mpq as Q
except ImportError:  # pragma: no cover - gmpy2 is a declared dependency
    from fractions import Fraction as Q

try:  # python-flint: dense polynomial products in C, for rings of one generator
    from flint import fmpq as _fmpq, fmpq_poly as _fmpq_poly, fmpz_poly as _fmpz_poly
except ImportError:  # pragma: no cover - python-flint is a declared dependency
    _fmpq = _fmpq_poly = _fmpz_poly = None

__all__ = ["LaurentRing", "Laurent", "Q", "HAVE_DENSE", "to_dense"]

#: whether one-generator Laurent polynomials can be multiplied densely (python-flint)
HAVE_DENSE = _fmpq_poly is not None

_BITS = 16
_BIAS = 1 << (_BITS - 1)
_MASK = (1 << _BITS) - 1


class LaurentRing:
    """The ring of Laurent polynomials in the given generators over Q."""

    __slots__ = ("gens", "ngens", "bias_all", "zero_mono", "_unit", "dense")

    def __init__(self, gens: Sequence[sp.Symbol]):
        self.gens = tuple(gens)
        self.ngens = len(self.gens)
        #: whether the elements compute on their dense form (one generator, python-flint)
        self.dense = HAVE_DENSE and self.ngens == 1
        self.bias_all = sum(_BIAS << (_BITS * i) for i in range(self.ngens))
        self.zero_mono = self.bias_all
        self._unit = [1 << (_BITS * i) for i in range(self.ngens)]

    def exponent(self, mono: int, i: int) -> int:
        return ((mono >> (_BITS * i)) & _MASK) - _BIAS

    def monomial(self, exps: Sequence[int]) -> int:
        m = self.bias_all
        for i, e in enumerate(exps):
            if not -_BIAS < e < _BIAS - 1:
                raise OverflowError("exponent out of range of the packed representation")
            m += e << (_BITS * i)
        return m

    def const(self, c) -> "Laurent":
        c = Q(c)
        return Laurent(self, {self.zero_mono: c} if c else {})

    def gen(self, i: int, power: int = 1) -> "Laurent":
        return Laurent(self, {self.zero_mono + power * self._unit[i]: Q(1)})

    def from_expr(self, expr: sp.Expr) -> "Laurent":
        """Convert a sympy polynomial (rational coefficients) in the generators."""
        expr = sp.together(sp.sympify(expr))
        num, den = sp.fraction(expr)
        num = sp.expand(num)
        if num == 0:
            return Laurent(self, {})
        if not self.gens:
            return self.const(sp.Rational(expr))
        dpoly = sp.Poly(den, *self.gens)
        if len(dpoly.terms()) != 1:
            raise TypeError(f"{den} is not a monomial: not a Laurent polynomial")
        (dexps, dc), = dpoly.terms()
        out: dict[int, object] = {}
        for exps, c in sp.Poly(num, *self.gens).terms():
            c = c / dc
            if not c.is_Rational:
                raise TypeError(f"coefficient {c} is not rational")
            out[self.monomial([e - d for e, d in zip(exps, dexps)])] = Q(int(c.p), int(c.q))
        return Laurent(self, out)


class Laurent:
    """An element of a :class:`LaurentRing` (immutable by convention).

    ``terms`` maps packed monomials to rational coefficients.  In a ring of one
    generator (with python-flint) the arithmetic runs instead on the dense form
    ``(low, p)``, the element being ``gens[0]**(low - bias) * p(gens[0])`` with ``p``
    an ``fmpq_poly``; each form is made from the other on first use and kept.
    """

    __slots__ = ("ring", "_terms", "_dense")

    def __init__(self, ring: LaurentRing, terms: dict | None = None, dense: tuple | None = None):
        self.ring = ring
        self._terms = {} if terms is None and dense is None else terms
        self._dense = dense

    @classmethod
    def from_dense(cls, ring: LaurentRing, low: int, poly) -> "Laurent":
        """The element ``gens[0]**(low - bias) * poly(gens[0])`` (one generator)."""
        return cls(ring, None, (low, poly))

    @property
    def terms(self) -> dict:
        """``{packed monomial: rational coefficient}`` (no zero coefficients)."""
        if self._terms is None:
            low, poly = self._dense
            den = int(poly.denom())
            self._terms = {low + k: Q(int(n), den)
                           for k, n in enumerate(poly.numer().coeffs()) if n}
        return self._terms

    def dense(self) -> tuple:
        """The dense form ``(low, fmpq_poly)`` (rings of one generator only)."""
        if self._dense is None:
            terms = self._terms
            if terms:
                low = min(terms)
                self._dense = (low, to_dense(terms, low))
            else:
                self._dense = (self.ring.bias_all, _fmpq_poly())
        return self._dense

    def __bool__(self) -> bool:
        if self._terms is not None:
            return bool(self._terms)
        return bool(self._dense[1])

    def __add__(self, other: "Laurent") -> "Laurent":
        if not other:
            return self
        if not self:
            return other
        if self.ring.dense:
            (l1, p1), (l2, p2) = self.dense(), other.dense()
            if l1 > l2:
                p1, l1 = p1.left_shift(l1 - l2), l2
            elif l2 > l1:
                p2 = p2.left_shift(l2 - l1)
            return Laurent.from_dense(self.ring, l1, p1 + p2)
        out = dict(self.terms)
        for m, c in other.terms.items():
            v = out.get(m)
            if v is None:
                out[m] = c
            else:
                v = v + c
                if v:
                    out[m] = v
                else:
                    del out[m]
        return Laurent(self.ring, out)

    def __neg__(self) -> "Laurent":
        if self.ring.dense:
            low, poly = self.dense()
            return Laurent.from_dense(self.ring, low, -poly)
        return Laurent(self.ring, {m: -c for m, c in self.terms.items()})

    def __sub__(self, other: "Laurent") -> "Laurent":
        return self + (-other)

    def __mul__(self, other: "Laurent") -> "Laurent":
        if not self or not other:
            return Laurent(self.ring, {})
        if self.ring.dense:
            (l1, p1), (l2, p2) = self.dense(), other.dense()
            return Laurent.from_dense(self.ring, l1 + l2 - self.ring.bias_all, p1 * p2)
        out = term_product(self.terms, other.terms, self.ring.bias_all)
        return Laurent(self.ring, {m: c for m, c in out.items() if c})

    def scale(self, c) -> "Laurent":
        c = Q(c)
        if not c:
            return Laurent(self.ring, {})
        if self.ring.dense:
            low, poly = self.dense()
            return Laurent.from_dense(self.ring, low,
                                      poly * _fmpq(int(c.numerator), int(c.denominator)))
        return Laurent(self.ring, {m: v * c for m, v in self.terms.items()})

    def shift(self, i: int, power: int) -> "Laurent":
        """Multiply by ``gens[i]**power`` (power may be negative)."""
        d = power * self.ring._unit[i]
        if self.ring.dense:
            low, poly = self.dense()
            return Laurent.from_dense(self.ring, low + d, poly)
        return Laurent(self.ring, {m + d: c for m, c in self.terms.items()})

    def diff(self, i: int) -> "Laurent":
        """Partial derivative with respect to ``gens[i]``."""
        ring = self.ring
        if ring.dense:
            # d/dg (g**e p(g)) = g**(e - 1) (e p(g) + g p'(g))
            low, poly = self.dense()
            e = low - ring.bias_all
            return Laurent.from_dense(ring, low - 1, poly * e + poly.derivative().left_shift(1))
        unit = ring._unit[i]
        out = {}
        for m, c in self.terms.items():
            e = ring.exponent(m, i)
            if e:
                out[m - unit] = c * e
        return Laurent(ring, out)

    def as_primitive_expr(self) -> sp.Expr:
        """``content * monomial * primitive polynomial``: readable and cheap (no factoring).

        The rational content and the common monomial (lowest power of each
        generator) are pulled out; the sign is chosen so that the leading term of
        the remaining polynomial is positive.
        """
        if not self.terms:
            return sp.Integer(0)
        ring = self.ring
        lows = [min(ring.exponent(m, i) for m in self.terms) for i in range(ring.ngens)]
        nums = [int(c.numerator) for c in self.terms.values()]
        dens = [int(c.denominator) for c in self.terms.values()]
        g = 0
        for v in nums:
            g = _gcd(g, abs(v))
        lcm = 1
        for d in dens:
            lcm = lcm * d // _gcd(lcm, d)
        lead = self.terms[max(self.terms)]
        content = sp.Rational(g if lead > 0 else -g, lcm)
        shifted = self
        for i, e in enumerate(lows):
            if e:
                shifted = shifted.shift(i, -e)
        inner = shifted.scale(Q(lcm, 1) / Q(int(content.p), 1)).as_expr() \
            if content.p else sp.Integer(0)
        mono = sp.Mul(*[g_**e for g_, e in zip(ring.gens, lows) if e])
        return sp.Mul(content, mono, inner)

    def as_expr(self) -> sp.Expr:
        """The sympy expression (terms in a fixed order, so printing is deterministic)."""
        ring = self.ring
        if ring.ngens == 1:
            g = ring.gens[0]
            return _sum_of_monomials([_monomial_term(self.terms[m], g, ring.exponent(m, 0))
                                      for m in sorted(self.terms)])
        parts = []
        for m in sorted(self.terms):
            c = self.terms[m]
            term = sp.Rational(int(c.numerator), int(c.denominator))
            for i, g in enumerate(ring.gens):
                e = ring.exponent(m, i)
                if e:
                    term *= g**e
            parts.append(term)
        return sp.Add(*parts)


def term_product(t1: dict, t2: dict, bias: int) -> dict:
    """The product of two raw term dicts (monomial code -> coefficient) of a ring with
    ``bias_all`` = ``bias``; zero coefficients are kept (the caller filters)."""
    out: dict = {}
    get = out.get
    for m1, c1 in t1.items():
        base = m1 - bias
        for m2, c2 in t2.items():
            m = base + m2
            v = get(m)
            out[m] = c1 * c2 if v is None else v + c1 * c2
    return out


def merged(a: dict, b: dict) -> dict:
    """``a + b`` of two coefficient dicts by key (``a``'s keys first, then ``b``'s new ones)."""
    out = dict(a)
    for k, c in b.items():
        out[k] = out[k] + c if k in out else c
    return out


def accumulate(d: dict, key, terms: dict, sign: int) -> None:
    """``d[key] += sign * terms`` on raw term dicts, in place (``sign`` is +1 or -1)."""
    tgt = d.get(key)
    if tgt is None:
        d[key] = dict(terms) if sign > 0 else {m: -c for m, c in terms.items()}
        return
    get = tgt.get
    if sign > 0:
        for m, c in terms.items():
            w = get(m)
            tgt[m] = c if w is None else w + c
    else:
        for m, c in terms.items():
            w = get(m)
            tgt[m] = -c if w is None else w - c


def _monomial_term(c, g: sp.Symbol, e: int) -> sp.Expr:
    """``c * g**e`` as sympy builds it, without the general product's simplification
    (the arguments are already canonical: a rational number and a power)."""
    coeff = sp.Rational(int(c.numerator), int(c.denominator))
    if not e:
        return coeff
    power = g if e == 1 else sp.Pow(g, e)
    if coeff is sp.S.One:
        return power
    return sp.Mul._from_args((coeff, power))


def _sum_of_monomials(terms: list) -> sp.Expr:
    """``sp.Add(*terms)`` for nonzero terms ``c * g**e`` with distinct exponents: nothing
    combines, so the canonical sum is made directly (the number first, the rest in
    sympy's canonical order), without asking each new coefficient whether it is zero."""
    if len(terms) < 2:
        return terms[0] if terms else sp.Integer(0)
    numbers = [t for t in terms if t.is_Number]
    rest = [t for t in terms if not t.is_Number]
    _addsort(rest)
    return sp.Add._from_args(numbers + rest, is_commutative=True)


# ----------------------------------------------------------------------------- dense form
def to_dense(terms: dict, low: int):
    """The ``fmpq_poly`` ``p`` with ``terms = a**(low - bias) * p(a)`` (one generator;
    ``low`` a packed monomial not above any of ``terms``)."""
    den = 1
    for v in terms.values():
        d = int(v.denominator)
        den = den * d // _gcd(den, d)
    nums = [0] * (max(terms) - low + 1)
    for k, v in terms.items():
        nums[k - low] = int(v.numerator) * (den // int(v.denominator))
    return _fmpq_poly(nums, den)
