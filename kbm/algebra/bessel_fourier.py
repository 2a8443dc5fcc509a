"""Fourier series with infinite families of harmonics: the Jacobi-Anger algebra.

For ``F`` containing ``sin(k x)`` or ``cos(k x)`` the KBM recursion meets
``sin(k a cos psi) = 2 sum_{n>=0} (-1)**n J_{2n+1}(k a) cos((2n+1) psi)`` and
``cos(k a cos psi) = J_0(k a) + 2 sum_{n>=1} (-1)**n J_{2n}(k a) cos(2n psi)``
(Jacobi-Anger; Abramowitz & Stegun 9.1.44-45).  A series here is a sum of
*terms*; a term is ``c(n_1..n_j) cos(h psi)`` or ``... sin(h psi)`` summed over
the integer indices ``n_i >= l_i`` (none for an ordinary harmonic), with the
harmonic ``h`` an integer linear form in the indices.  Products of terms add
indices, so order 2 meets double sums; the coefficient of one harmonic of a
double sum is a single sum along a lattice line, found exactly with the
extended Euclidean algorithm (:mod:`~kbm.algebra.lattice`).  Nothing is
truncated here: truncation happens only when a result is evaluated numerically
(:mod:`kbm.output.evaluate`).

:class:`SymAlgebra` offers these series to the recursion through the
:class:`~kbm.algebra.base.FourierAlgebra` protocol; :func:`tidy` and
:func:`tidy_sums` put its coefficients in display form.  (The series, its
display and its adapter change together, so they stay in one module of a little
over 350 lines; the lattice arithmetic is apart.)
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import sympy as sp

from ..errors import OrderError
from ..symbols import a, psi
from .lattice import line_points_exist, line_sum, linear_form

if TYPE_CHECKING:  # the models sit above the algebra; only their type is named here
    from ..model.builtins import Oscillator

__all__ = ["SymFourier", "SymAlgebra", "jacobi_anger", "tidy", "tidy_sums",
           "INDEX", "DISPLAY_INDEX", "COS", "SIN"]

#: internal summation indices, renamed to n, m, ... for display
INDEX = tuple(sp.Symbol(f"_n{i}", integer=True) for i in range(1, 9))
#: display names of the summation indices
DISPLAY_INDEX = (sp.Symbol("n"), sp.Symbol("m"), sp.Symbol("j"))

#: the two kinds of term: ``c cos(h psi)`` and ``c sin(h psi)``
COS, SIN = 0, 1


def _canon_sign(kind: int, h: sp.Expr, idx, coef: sp.Expr):
    """Choose the sign of ``h`` (cos even, sin odd) so that equal terms share a key."""
    coeffs, const = linear_form(h, tuple(s for s, _ in idx))
    lead = next((c for c in coeffs if c), const)
    if lead < 0:
        h = -h
        if kind == SIN:
            coef = -coef
    return h, coef


class SymFourier:
    """Sum of (possibly infinite) families of harmonics with sympy coefficients."""

    __slots__ = ("terms",)

    def __init__(self, terms: dict | None = None):
        # key: (kind, harmonic expr, ((index, lower), ...)) -> coefficient
        self.terms = {k: v for k, v in (terms or {}).items() if v != 0}

    # -- construction -----------------------------------------------------------------
    @classmethod
    def constant(cls, c: sp.Expr) -> "SymFourier":
        return cls({(COS, sp.Integer(0), ()): sp.sympify(c)})

    @classmethod
    def harmonic_term(cls, kind: int, m: int, c: sp.Expr) -> "SymFourier":
        if kind == SIN and m == 0:
            return cls()
        if m < 0:
            m, c = -m, (-c if kind == SIN else c)
        return cls({(kind, sp.Integer(m), ()): sp.sympify(c)})

    def is_zero(self) -> bool:
        return not self.terms

    # -- arithmetic -----------------------------------------------------------------
    @staticmethod
    def _put(out: dict, kind: int, h: sp.Expr, idx, c: sp.Expr) -> None:
        if kind == SIN and not idx and h == 0:
            return
        h, c = _canon_sign(kind, h, idx, c)
        key = (kind, h, idx)
        out[key] = out[key] + c if key in out else c

    def __add__(self, other: "SymFourier") -> "SymFourier":
        out = dict(self.terms)
        for (kind, h, idx), c in other.terms.items():
            self._put(out, kind, h, idx, c)
        return SymFourier(_clean(out))

    def __neg__(self) -> "SymFourier":
        return SymFourier({k: -v for k, v in self.terms.items()})

    def __sub__(self, other: "SymFourier") -> "SymFourier":
        return self + (-other)

    def scale(self, c: sp.Expr) -> "SymFourier":
        return SymFourier(_clean({k: sp.expand(v * c) for k, v in self.terms.items()}))

    def scale_q(self, q) -> "SymFourier":
        q = sp.Rational(q)
        return SymFourier({k: v * q for k, v in self.terms.items()})

    def __mul__(self, other: "SymFourier") -> "SymFourier":
        out: dict = {}
        half = sp.Rational(1, 2)
        for (k1, h1, i1), c1 in self.terms.items():
            for (k2, h2, i2), c2 in other.terms.items():
                if len(i1) + len(i2) > len(INDEX):
                    raise OrderError("too many nested Bessel sums for this order")
                # rename the indices of the second factor after those of the first
                ren = {INDEX[j]: INDEX[len(i1) + j] for j in range(len(i2))}
                h2r = h2.xreplace(ren)
                c2r = c2.xreplace(ren)
                i2r = tuple((ren[s], lo) for s, lo in i2)
                idx = i1 + i2r
                c = sp.expand(c1 * c2r * half)
                if k1 == COS and k2 == COS:
                    self._put(out, COS, h1 - h2r, idx, c)
                    self._put(out, COS, h1 + h2r, idx, c)
                elif k1 == SIN and k2 == SIN:
                    self._put(out, COS, h1 - h2r, idx, c)
                    self._put(out, COS, h1 + h2r, idx, -c)
                elif k1 == SIN and k2 == COS:
                    self._put(out, SIN, h1 + h2r, idx, c)
                    self._put(out, SIN, h1 - h2r, idx, c)
                else:  # cos * sin
                    self._put(out, SIN, h1 + h2r, idx, c)
                    self._put(out, SIN, h2r - h1, idx, c)
        return SymFourier(_clean(out))

    # -- calculus -------------------------------------------------------------------
    def dpsi(self) -> "SymFourier":
        out: dict = {}
        for (kind, h, idx), c in self.terms.items():
            if kind == COS:
                self._put(out, SIN, h, idx, sp.expand(-h * c))
            else:
                self._put(out, COS, h, idx, sp.expand(h * c))
        return SymFourier(_clean(out))

    def da(self, a: sp.Symbol) -> "SymFourier":
        return SymFourier(_clean({k: sp.expand(sp.diff(v, a)) for k, v in self.terms.items()}))

    # -- harmonic balance -------------------------------------------------------------
    def harmonic(self, m: int) -> tuple[sp.Expr, sp.Expr]:
        """Coefficients of ``cos(m psi)`` and ``sin(m psi)`` (single sums where infinite)."""
        cos_parts: list[sp.Expr] = []
        sin_parts: list[sp.Expr] = []
        for (kind, h, idx), c in self.terms.items():
            targets = [(m, 1)] if m == 0 else [(m, 1), (-m, 1 if kind == COS else -1)]
            for target, sign in targets:
                val = line_sum(c, h, idx, target, INDEX[0])
                if val != 0:
                    (cos_parts if kind == COS else sin_parts).append(sign * val)
        return sp.Add(*cos_parts), sp.Add(*sin_parts)

    def solve_without_first(self, omega0: sp.Expr) -> "SymFourier":
        """Solve ``omega0**2 (u'' + u) = self`` term by term, leaving out ``cos/sin psi``.

        Single families lose their points with ``|h| = 1`` (split off as
        ordinary harmonics); double families keep a ``Piecewise`` that is zero
        on the lines ``|h| = 1``.
        """
        out: dict = {}
        w2 = omega0**2
        for (kind, h, idx), c in self.terms.items():
            if not idx:
                if h != 1:
                    self._put(out, kind, h, idx, c / (w2 * (1 - h**2)))
                continue
            syms = tuple(s for s, _ in idx)
            coeffs, const = linear_form(h, syms)
            if len(idx) == 2 and coeffs[0] == -coeffs[1] != 0:
                # the harmonic depends on n1 - n2 only: resum along diagonals, so that
                # each harmonic gets one coefficient (an inner sum) and |h| = 1 is a point
                for k2, h2, idx2, c2 in _diagonalize(kind, h, idx, c):
                    part = SymFourier({(k2, h2, idx2): c2}).solve_without_first(omega0)
                    for key, val in part.terms.items():
                        self._put(out, key[0], key[1], key[2], val)
                continue
            if len(idx) == 1:
                (s, lo), p = idx[0], coeffs[0]
                bad = sorted(n for n in {(1 - const) / p, (-1 - const) / p}
                             if float(n).is_integer() and n >= lo)
                if not bad:
                    self._put(out, kind, h, idx, c / (w2 * (1 - h**2)))
                    continue
                top = int(bad[-1])
                for n in range(lo, top + 1):
                    hn = int(h.subs(s, n))
                    if abs(hn) != 1:
                        cn = c.subs(s, n)
                        self._put(out, kind, sp.Integer(hn), (), cn / (w2 * (1 - hn**2)))
                self._put(out, kind, h, ((s, top + 1),), c / (w2 * (1 - h**2)))
            else:
                has_line = any(line_points_exist(h, idx, t) for t in (1, -1))
                term = c / (w2 * (1 - h**2))
                if has_line:
                    term = sp.Piecewise((term, sp.Ne(h**2, 1)), (0, True))
                self._put(out, kind, h, idx, term)
        return SymFourier(_clean(out))

    def as_expr(self, psi: sp.Symbol) -> sp.Expr:
        """The series as a sympy expression with ``Sum`` over display indices."""
        finite: dict[tuple[int, int], sp.Expr] = {}
        families = []
        for (kind, h, idx), c in self.terms.items():
            if not idx:
                key = (kind, int(h))
                finite[key] = finite.get(key, 0) + c
            else:
                families.append((kind, h, idx, c))
        parts = []
        for (kind, m) in sorted(finite):
            trig = sp.cos if kind == COS else sp.sin
            parts.append(tidy(finite[(kind, m)]) * trig(m * psi))
        for kind, h, idx, c in sorted(families, key=lambda f: (len(f[2]), f[0], sp.default_sort_key(f[1]))):
            trig = sp.cos if kind == COS else sp.sin
            ren = {s: DISPLAY_INDEX[i] for i, (s, _) in enumerate(idx)}
            body = (tidy(c) * trig(h * psi)).xreplace(ren)
            limits = [(ren[s], lo, sp.oo) for s, lo in idx]
            parts.append(sp.Sum(body, *limits))
        return sp.Add(*parts)


#: bound index of the inner sums made by :func:`_diagonalize`
INNER = sp.Symbol("m")


def _diagonalize(kind: int, h: sp.Expr, idx, c: sp.Expr):
    """Rewrite a double family whose harmonic depends on ``d = n1 - n2`` as single families in d.

    ``sum_{n1>=l1, n2>=l2} c(n1, n2) trig((p (n1 - n2) + q) psi)`` becomes
    ``sum_{d >= l1-l2} trig((p d + q) psi) sum_{m>=l2} c(m + d, m)`` plus
    ``sum_{e >= l2-l1+1} trig((q - p e) psi) sum_{m>=l1} c(m, m + e)``.
    """
    (s1, l1), (s2, l2) = idx
    d = INDEX[0]
    (p1, _), q = linear_form(h, (s1, s2))
    d0 = l1 - l2
    pieces = []
    inner_a = sp.Sum(sp.expand(c.xreplace({s1: INNER + d, s2: INNER})), (INNER, l2, sp.oo))
    pieces.append((kind, p1 * d + q, ((d, d0),), inner_a))
    inner_b = sp.Sum(sp.expand(c.xreplace({s1: INNER, s2: INNER + d})), (INNER, l1, sp.oo))
    pieces.append((kind, q - p1 * d, ((d, 1 - d0),), inner_b))
    return pieces


def _clean(d: dict) -> dict:
    return {k: v for k, v in d.items() if v != 0}


def tidy(expr: sp.Expr) -> sp.Expr:
    """A light, deterministic simplification for display: factor rational parts."""
    expr = sp.expand(expr)
    if expr.has(sp.Sum):
        expr = expr.replace(lambda e: isinstance(e, sp.Sum), _pull_constants)
    atoms = sorted(expr.atoms(sp.besselj) | expr.atoms(sp.Sum), key=sp.default_sort_key)
    return sp.collect(expr, atoms, func=sp.factor)


def _pull_constants(s: sp.Sum) -> sp.Expr:
    """``Sum(c f(n))`` -> ``c Sum(f(n))`` for factors ``c`` free of the summation indices."""
    body = tidy(s.function)
    idx = {lim[0] for lim in s.limits}
    outside, inside = [], []
    for f in sp.Mul.make_args(body):
        (inside if f.free_symbols & idx else outside).append(f)
    return sp.Mul(*outside) * sp.Sum(sp.Mul(*inside), *s.limits)


def jacobi_anger(z: sp.Expr) -> tuple[SymFourier, SymFourier]:
    """``(sin(z cos psi), cos(z cos psi))`` as families of harmonics (A&S 9.1.44-45)."""
    n = INDEX[0]
    sin_s = SymFourier({(COS, 2 * n + 1, ((n, 0),)): 2 * (-1)**n * sp.besselj(2 * n + 1, z)})
    cos_s = SymFourier({(COS, sp.Integer(0), ()): sp.besselj(0, z),
                        (COS, 2 * n, ((n, 1),)): 2 * (-1)**n * sp.besselj(2 * n, z)})
    return sin_s, cos_s


# ----------------------------------------------------------------------------- the adapter
def tidy_sums(expr: sp.Expr) -> sp.Expr:
    """Rename summation indices to n, merge sums with equal limits, tidy the rest."""
    expr = sp.expand(expr)
    sums: dict[tuple, list[sp.Expr]] = {}
    rest = []
    for term in sp.Add.make_args(expr):
        coeff, sm = sp.Integer(1), None
        for f in sp.Mul.make_args(term):
            if isinstance(f, sp.Sum) and sm is None:
                sm = f
            else:
                coeff *= f
        if sm is None:
            rest.append(term)
            continue
        limits = sm.limits
        ren = {lim[0]: DISPLAY_INDEX[i] for i, lim in enumerate(limits)}
        body = sm.function.xreplace(ren) * coeff
        key = tuple((ren[l[0]], l[1], l[2]) for l in limits)
        sums.setdefault(key, []).append(body)
    out = [tidy(sp.Add(*rest))]
    for key in sorted(sums, key=sp.default_sort_key):
        out.append(sp.Sum(tidy(sp.Add(*sums[key])), *key))
    return sp.Add(*out)


class SymAlgebra:
    """sympy coefficients and infinite Jacobi-Anger families of harmonics.

    Implements :class:`~kbm.algebra.base.FourierAlgebra` with series
    :class:`SymFourier` and sympy expressions as coefficients.
    """

    exact = False

    def __init__(self, model: Oscillator):
        self.w0 = model.omegas[0]

    def zero(self) -> SymFourier:
        return SymFourier()

    def const(self, expr: sp.Expr) -> SymFourier:
        return SymFourier.constant(expr)

    def coef(self, expr: sp.Expr) -> sp.Expr:
        return sp.sympify(expr)

    def x0(self) -> SymFourier:
        return SymFourier.harmonic_term(COS, 1, a)

    def scale(self, f: SymFourier, c: sp.Expr) -> SymFourier:
        return f.scale(c)

    def dpsi(self, f: SymFourier) -> SymFourier:
        return f.dpsi()

    def da(self, f: SymFourier) -> SymFourier:
        return f.da(a)

    def secular(self, R: SymFourier) -> tuple[sp.Expr, sp.Expr]:
        c1, s1 = R.harmonic(1)
        return -s1 / (2 * self.w0), -c1 / (2 * self.w0 * a)

    def solve(self, R: SymFourier) -> SymFourier:
        return R.solve_without_first(self.w0)

    def coef_expr(self, c: sp.Expr) -> sp.Expr:
        return tidy_sums(c)

    def series_expr(self, f: SymFourier) -> sp.Expr:
        return f.as_expr(psi)

    def trig(self, kind: str, c: sp.Expr) -> list[SymFourier]:
        """Fourier series of ``f^(m)(c a cos psi)``, m = 0..3, for f = sin or cos."""
        s, co = jacobi_anger(c * a)
        seq = [s, co, -s, -co]  # sin, sin', sin'', sin'''
        return seq if kind == "sin" else seq[1:] + seq[:1]
