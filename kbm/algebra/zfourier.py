"""Truncated Fourier series of real functions as polynomials in ``z = exp(i tau)``.

A real ``2 pi``-periodic trigonometric polynomial of degree ``K``,
``f(tau) = sum_{k=0}^{K} C_k cos(k tau) + S_k sin(k tau)``, is kept in exponential
form ``f = sum_{k=-K}^{K} c_k z**k`` with ``c_{+-k} = (C_k -+ i S_k)/2``, as the pair
of real polynomials ``P_re(z) = sum Re(c_k) z**(k+K)`` and ``P_im(z) = sum Im(c_k)
z**(k+K)`` with the offset ``K``.  Then a product of two series is three products
of polynomials (Karatsuba's form of ``(a + i b)(c + i d)``), ``d/dtau`` is
``c_k -> i k c_k`` and no trigonometric identity is ever used.  This is the
arithmetic of the direct limit-cycle series (:mod:`kbm.slowflow.cycle_series`).

The polynomials come from one of several *kinds* (:func:`arithmetic`):

- ``"exact"``: python-flint's ``fmpq_poly`` (exact rationals, FFT-based products
  in C), or, without python-flint, the pure-Python :class:`ListPoly` over
  ``gmpy2.mpq`` (schoolbook products: the same numbers, slower);
- ``"float"``: :class:`NumpyPoly`, double precision with ``numpy.convolve``;
- ``"mp"``: python-flint's ``arb_poly`` (ball arithmetic at the requested
  precision, so every coefficient carries a rigorous error bound), or, without
  python-flint, :class:`ListPoly` over ``mpmath.mpf``.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Any, Callable

import numpy as np

try:  # python-flint: exact and ball-arithmetic polynomials in C
    import flint as _flint
except ImportError:  # pragma: no cover - exercised by forcing the fallback in the tests
    _flint = None

__all__ = ["ZSeries", "Arithmetic", "arithmetic", "ListPoly", "NumpyPoly", "HAVE_FLINT"]

#: whether python-flint is importable (the fast path of the exact and mp arithmetics)
HAVE_FLINT = _flint is not None


# ----------------------------------------------------------------------------- polynomials
class ListPoly:
    """A dense polynomial over any field-like scalar type (pure Python, schoolbook product).

    The fallback polynomial of :func:`arithmetic` when python-flint is missing;
    implements the few operations :class:`ZSeries` needs, with the same names as
    python-flint's polynomials.
    """

    __slots__ = ("c",)

    def __init__(self, coeffs=()):
        c = list(coeffs)
        while c and not c[-1]:
            c.pop()
        self.c = c

    def __add__(self, other: "ListPoly") -> "ListPoly":
        a, b = self.c, other.c
        if len(a) < len(b):
            a, b = b, a
        out = list(a)
        for i, v in enumerate(b):
            out[i] = out[i] + v
        return ListPoly(out)

    def __neg__(self) -> "ListPoly":
        return ListPoly([-v for v in self.c])

    def __sub__(self, other: "ListPoly") -> "ListPoly":
        return self + (-other)

    def __mul__(self, other) -> "ListPoly":
        if not isinstance(other, ListPoly):
            return ListPoly([v * other for v in self.c])
        a, b = self.c, other.c
        if not a or not b:
            return ListPoly()
        out = [a[0] * 0] * (len(a) + len(b) - 1)
        for i, u in enumerate(a):
            if u:
                for j, v in enumerate(b):
                    out[i + j] += u * v
        return ListPoly(out)

    def left_shift(self, n: int) -> "ListPoly":
        """Multiply by ``z**n``."""
        return ListPoly([self.c[0] * 0] * n + self.c) if self.c else ListPoly()

    def derivative(self) -> "ListPoly":
        return ListPoly([v * i for i, v in enumerate(self.c)][1:])

    def coeffs(self) -> list:
        return list(self.c)


class NumpyPoly:
    """A dense polynomial with ``float64`` coefficients (products by ``numpy.convolve``)."""

    __slots__ = ("c",)

    def __init__(self, coeffs=()):
        self.c = np.asarray(coeffs, dtype=float)

    def __add__(self, other: "NumpyPoly") -> "NumpyPoly":
        a, b = self.c, other.c
        if len(a) < len(b):
            a, b = b, a
        out = a.copy()
        out[:len(b)] += b
        return NumpyPoly(out)

    def __neg__(self) -> "NumpyPoly":
        return NumpyPoly(-self.c)

    def __sub__(self, other: "NumpyPoly") -> "NumpyPoly":
        return self + (-other)

    def __mul__(self, other) -> "NumpyPoly":
        if isinstance(other, NumpyPoly):
            if not len(self.c) or not len(other.c):
                return NumpyPoly()
            return NumpyPoly(np.convolve(self.c, other.c))
        return NumpyPoly(self.c * float(other))

    def left_shift(self, n: int) -> "NumpyPoly":
        return NumpyPoly(np.concatenate([np.zeros(n), self.c])) if len(self.c) else NumpyPoly()

    def derivative(self) -> "NumpyPoly":
        return NumpyPoly(self.c[1:] * np.arange(1, len(self.c)))

    def coeffs(self) -> list:
        return list(self.c)


# ----------------------------------------------------------------------------- arithmetics
@dataclass(frozen=True)
class Arithmetic:
    """A kind of numbers and polynomials for :class:`ZSeries`.

    Attributes
    ----------
    name
        ``"exact"``, ``"float"`` or ``"mp"``.
    backend
        What does the work: ``"flint"``, ``"python"`` or ``"numpy"``.
    poly
        The polynomial type (called with a list of coefficients).
    num
        Converts a :class:`fractions.Fraction` to the scalar type.
    prec
        Working precision in bits (``None`` for exact arithmetic).
    """

    name: str
    backend: str
    poly: Callable[[list], Any]
    num: Callable[[Fraction], Any]
    prec: int | None = None

    @property
    def zero(self):
        return self.num(Fraction(0))

    def is_exact(self) -> bool:
        return self.name == "exact"


def arithmetic(kind: str = "exact", *, prec: int | None = None,
               use_flint: bool | None = None) -> Arithmetic:
    """The :class:`Arithmetic` of the given kind.

    Parameters
    ----------
    kind
        ``"exact"`` (rationals), ``"float"`` (double precision) or ``"mp"``
        (``prec`` bits, ball arithmetic with python-flint, else mpmath).
    prec
        Bits of working precision for ``"mp"``.
    use_flint
        Force (``True``) or forbid (``False``) python-flint; default: use it when
        it is installed.  Forbidding it selects the pure-Python fallback.

    Notes
    -----
    The ``"mp"`` kind sets the global working precision of python-flint
    (``flint.ctx.prec``) or of mpmath (``mpmath.mp.prec``); the caller restores it
    (see :func:`kbm.slowflow.cycle_series.lindstedt_series`).
    """
    flint_ok = HAVE_FLINT if use_flint is None else (use_flint and HAVE_FLINT)
    if kind == "float":
        return Arithmetic("float", "numpy", NumpyPoly, lambda q: float(q))
    if kind == "exact":
        if flint_ok:
            fmpq = _flint.fmpq
            return Arithmetic("exact", "flint", _flint.fmpq_poly,
                              lambda q: fmpq(q.numerator, q.denominator))
        from .laurent import Q
        return Arithmetic("exact", "python", ListPoly, lambda q: Q(q.numerator, q.denominator))
    if kind == "mp":
        if prec is None:
            raise ValueError("the mp arithmetic needs prec (bits)")
        if flint_ok:
            arb = _flint.arb
            return Arithmetic("mp", "flint", _flint.arb_poly,
                              lambda q: arb(q.numerator) / q.denominator, prec)
        import mpmath
        return Arithmetic("mp", "python", ListPoly,
                          lambda q: mpmath.mpf(q.numerator) / q.denominator, prec)
    raise ValueError(f"unknown arithmetic {kind!r}")


# ----------------------------------------------------------------------------- the series
class ZSeries:
    """``f(tau) = sum_{k=-K}^{K} (re_k + i im_k) exp(i k tau)`` for a real function ``f``.

    ``re``, ``im`` are polynomials in ``z`` of one :class:`Arithmetic` holding the
    coefficient of ``z**k`` at the power ``k + K``.  Immutable by convention.
    """

    __slots__ = ("re", "im", "K", "ar")

    def __init__(self, re, im, K: int, ar: Arithmetic):
        self.re, self.im, self.K, self.ar = re, im, K, ar

    # -- construction ---------------------------------------------------------------
    @classmethod
    def zero(cls, ar: Arithmetic) -> "ZSeries":
        return cls(ar.poly([]), ar.poly([]), 0, ar)

    @classmethod
    def trig(cls, ar: Arithmetic, C, S, k: int) -> "ZSeries":
        """``C cos(k tau) + S sin(k tau)`` (scalars of ``ar``; ``k >= 0``)."""
        z = ar.zero
        if k == 0:
            return cls(ar.poly([C]), ar.poly([]), 0, ar)
        re = [z] * (2 * k + 1)
        im = [z] * (2 * k + 1)
        half_c, half_s = C / 2, S / 2
        re[0], im[0] = half_c, half_s          # z**-k: (C + i S)/2
        re[2 * k], im[2 * k] = half_c, -half_s  # z**+k: (C - i S)/2
        return cls(ar.poly(re), ar.poly(im), k, ar)

    @classmethod
    def constant(cls, ar: Arithmetic, c) -> "ZSeries":
        return cls(ar.poly([c]), ar.poly([]), 0, ar)

    # -- ring operations --------------------------------------------------------------
    def _aligned(self, other: "ZSeries"):
        d = self.K - other.K
        if d == 0:
            return self.re, self.im, other.re, other.im, self.K
        if d > 0:
            return self.re, self.im, other.re.left_shift(d), other.im.left_shift(d), self.K
        return self.re.left_shift(-d), self.im.left_shift(-d), other.re, other.im, other.K

    def __add__(self, other: "ZSeries") -> "ZSeries":
        a, b, c, d, K = self._aligned(other)
        return ZSeries(a + c, b + d, K, self.ar)

    def __sub__(self, other: "ZSeries") -> "ZSeries":
        a, b, c, d, K = self._aligned(other)
        return ZSeries(a - c, b - d, K, self.ar)

    def __neg__(self) -> "ZSeries":
        return ZSeries(-self.re, -self.im, self.K, self.ar)

    def __mul__(self, other: "ZSeries") -> "ZSeries":
        # (a + i b)(c + i d) = (ac - bd) + i((a + b)(c + d) - ac - bd)
        ac = self.re * other.re
        bd = self.im * other.im
        t = (self.re + self.im) * (other.re + other.im)
        return ZSeries(ac - bd, t - ac - bd, self.K + other.K, self.ar)

    def square(self) -> "ZSeries":
        """``f**2`` with two polynomial products: ``(a + i b)**2 = a**2 - b**2 + 2 i a b``."""
        ab = self.re * self.im
        return ZSeries(self.re * self.re - self.im * self.im, ab + ab, 2 * self.K, self.ar)

    def scale(self, c) -> "ZSeries":
        """``c f`` for a real scalar ``c``."""
        return ZSeries(self.re * c, self.im * c, self.K, self.ar)

    # -- calculus and harmonic balance --------------------------------------------------
    def _k_times(self, p):
        """The polynomial with coefficient ``k c_k`` where ``p`` holds ``c_k`` at ``k + K``."""
        return p.derivative().left_shift(1) - p * self.K

    def dtau(self) -> "ZSeries":
        """``df/dtau``: ``c_k -> i k c_k``."""
        return ZSeries(-self._k_times(self.im), self._k_times(self.re), self.K, self.ar)

    def _coeff_lists(self) -> tuple[list, list]:
        n = 2 * self.K + 1
        z = self.ar.zero
        re = list(self.re.coeffs())[:n]
        im = list(self.im.coeffs())[:n]
        return re + [z] * (n - len(re)), im + [z] * (n - len(im))

    def harmonic(self, k: int) -> tuple[Any, Any]:
        """``(C_k, S_k)``: the coefficients of ``cos(k tau)`` and ``sin(k tau)`` (``k >= 1``)."""
        if k > self.K:
            return self.ar.zero, self.ar.zero
        re, im = self._coeff_lists()
        j = self.K + k
        return re[j] * 2, -(im[j] * 2)

    def solve_periodic(self, w0sq) -> "ZSeries":
        """``u`` with ``w0sq (u'' + u) = f`` minus its first harmonic, and no first harmonic.

        Harmonic ``k != +-1`` of ``u`` is ``c_k / (w0sq (1 - k**2))``.
        """
        re, im = self._coeff_lists()
        K = self.K
        z = self.ar.zero
        for j in range(2 * K + 1):
            k = j - K
            if k in (1, -1):
                re[j] = im[j] = z
                continue
            d = w0sq * (1 - k * k)
            re[j] = re[j] / d
            im[j] = im[j] / d
        return ZSeries(self.ar.poly(re), self.ar.poly(im), K, self.ar)

    def trig_coefficients(self) -> dict[int, tuple[Any, Any]]:
        """``{k: (C_k, S_k)}`` for ``k = 0..K`` (``S_0 = 0``): the real form."""
        re, im = self._coeff_lists()
        K = self.K
        out = {0: (re[K], self.ar.zero)}
        for k in range(1, K + 1):
            out[k] = (re[K + k] * 2, -(im[K + k] * 2))
        return out
