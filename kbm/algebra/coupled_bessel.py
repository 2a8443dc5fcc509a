"""``sin(c x_l)`` and ``cos(c x_l)`` in the coupled expansion at first order: Jacobi-Anger.

At order one the KBM recursion evaluates ``F_i`` on ``x_l = a_l cos(psi_l)``, where

``sin(z cos psi) = 2 sum_{m>=0} (-1)**m J_{2m+1}(z) cos((2m+1) psi)``,
``cos(z cos psi) = J_0(z) + 2 sum_{m>=1} (-1)**m J_{2m}(z) cos(2m psi)``

(Abramowitz & Stegun 9.1.44-45), ``z = c a_l``.  The first-order rates ``A_{i,1}``,
``B_{i,1}`` take the resonant harmonics only, and when every term of ``F`` holds at most
one such factor, times a polynomial, only finitely many of its harmonics can be resonant:
a harmonic ``r = n e_l + p`` of the term, ``|p|_1 <= d`` (the polynomial's degree, with
the forcing angle's harmonics), lies within ``tol omega_i`` of ``+-omega_i`` only if

``|n| <= ((1 + tol) + d) omega_max/omega_l + d``

(``r_j = p_j`` for ``j != l``).  So the series are cut above that bound
(:func:`harmonic_bound`) and the rates are *exact*, each ``J_n(c a_l)`` a symbol of the
ring until the end; every harmonic that could meet a small divisor is inside the cut and
is checked as the polynomial ones are.  The corrections ``u_{i,1}`` are the harmonics up
to the cut, computed with the rest, plus the series above it, written as sums over the
harmonic index (:meth:`JacobiAnger.tail`): exact too.  Orders above one are not given:
their products of infinite series are lattice sums (:mod:`kbm.algebra.bessel_fourier`
forms them for one angle; the jets :mod:`kbm.backend.jets` give the rates numerically to
any order).

References
----------
M. D'Acunto, "Friction force for self-excited systems", eqs. (5)-(6): the Bessel term of
one slider, which the case ``N = 1`` reproduces (``tests/test_coupled_bessel.py``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import sympy as sp

from .lazy_series import Const
from .multi_angle import MultiAngle
from ..errors import OrderError, UnsupportedTermError
from ..model.constants import linear_argument
from ..model.coupled import amplitudes

__all__ = ["JacobiAnger", "jacobi_anger_plan", "harmonic_bound", "trig_of_state"]

_THETA = sp.Symbol("theta")
_NUMERIC_HINT = ("other smooth F, and orders above one with sin or cos of the state: "
                 "kbm derive --numeric --order N --at a1=..,a2=.. with -p values "
                 "(kbm.backend.jets), or the true orbits with kbm cycle")


def trig_of_state(expr: sp.Expr, state: set) -> list[sp.Expr]:
    """The ``sin``/``cos`` factors of a product ``expr`` whose argument holds the state (a
    power counted as often as its exponent)."""
    out = []
    for f in sp.Mul.make_args(expr):
        base, e = (f.base, f.exp) if f.is_Pow else (f, sp.S.One)
        if isinstance(base, (sp.sin, sp.cos)) and base.args[0].free_symbols & state:
            out += [base] * (int(e) if e.is_Integer and e > 0 else 2)
    return out


def _theta_degree(expr: sp.Expr) -> int:
    """A bound on the forcing angle's harmonics in a product: the sum of ``|k|`` over its
    factors ``cos(k theta + c)``, ``sin(k theta + c)`` (powers counted)."""
    deg = 0
    for f in sp.Mul.make_args(expr):
        base, e = (f.base, f.exp) if f.is_Pow else (f, sp.S.One)
        if isinstance(base, (sp.sin, sp.cos)) and base.has(_THETA):
            k = sp.expand(base.args[0]).coeff(_THETA)
            deg += int(abs(k)) * (int(e) if e.is_Integer else 1) if k.is_Integer else 0
    return deg


def harmonic_bound(omega: tuple, l: int, degree: int, tol: float) -> int:
    """The highest harmonic ``n`` of ``psi_l`` in the Jacobi-Anger series of ``sin(c x_l)``
    (``cos``) that a term with a polynomial factor of harmonic degree ``degree`` can turn
    into a harmonic within ``tol omega_i`` of any ``omega_i`` (module docstring)."""
    w = [float(v) for v in omega]
    return int(math.floor(((1 + tol) + degree) * max(w) / w[l])) + degree + 1


@dataclass(frozen=True)
class JacobiAnger:
    """The cut Jacobi-Anger series of the ``sin``/``cos`` factors of a model's ``F``.

    Attributes
    ----------
    cuts
        ``{(kind, c, l): H}``: the factor ``kind(c x_{l+1})`` and its highest harmonic.
    symbols
        ``{(c, l, n): J}``: the ring's symbol for ``J_n(c a_{l+1})``, ``n = 0..H``.
    """

    cuts: dict
    symbols: dict

    def generators(self) -> list[sp.Symbol]:
        """The Bessel symbols, in a fixed order (for the ring)."""
        return [self.symbols[k] for k in sorted(self.symbols, key=lambda k: self.symbols[k].name)]

    def series(self, alg, factor: sp.Expr):
        """The lazy node of ``factor`` = ``sin(c x_l)`` or ``cos(c x_l)`` at order one: its
        cut Jacobi-Anger series in the angle ``psi_l`` (higher coefficients are never
        asked for: the expansion stops at order one)."""
        kind, c, l = _key(factor, alg.model.state)
        ring = alg.ring
        out = alg.zero()
        for n in range(1 if kind == "sin" else 0, self.cuts[(kind, c, l)] + 1, 2):
            coef = ring.gen(ring.gens.index(self.symbols[(c, l, n)]))
            scale = (1 if n == 0 else 2) * (-1) ** (n // 2)
            h = tuple(n if j == l else 0 for j in range(alg.n))
            out = out + MultiAngle.harmonic(ring, h, coef.scale(scale), "cos")
        return Const(alg.zero, out)

    def tail(self, alg, row: sp.Expr, i: int, angles: tuple, builder) -> sp.Expr:
        """The part of ``u_{i,1}`` from the harmonics above the cut: for every term
        ``R sin(c x_l)`` (``cos``) of ``F_i`` and every harmonic ``r cos(h . psi)``
        (``sin``) of ``R``, the series ``sum_n J-A_n r cos(h psi +- n psi_l)/2`` over the
        ``n`` above the cut, each harmonic over its divisor ``omega_i**2 - (h . omega +- n
        omega_l)**2`` (none vanishes there: the cut is above every resonance).

        ``builder(expr)`` gives the multi-angle series of a polynomial ``R`` at order one;
        ``angles`` are ``psi_1..psi_N`` (and ``theta``).
        """
        m = sp.Symbol("m", integer=True, nonnegative=True)
        state = alg.model.state
        omega = [sp.Rational(w) for w in alg.omega]
        parts = []
        for term in sp.Add.make_args(sp.expand(row)):
            trig = trig_of_state(term, set(state))
            if not trig:
                continue
            kind, c, l = _key(trig[0], state)
            H = self.cuts[(kind, c, l)]
            n = 2 * m + 1 if kind == "sin" else 2 * m
            start = (H + 1) // 2 if kind == "sin" else H // 2 + 1
            ja = 2 * (-1) ** m * sp.besselj(n, c * amplitudes(l + 1)[l])
            rest = builder(sp.Mul(*[g for g in sp.Mul.make_args(term) if g != trig[0]]))
            w_i = omega[i]
            for fn, table in ((sp.cos, rest.cos), (sp.sin, rest.sin)):
                for h in sorted(table):
                    r = table[h].as_primitive_expr()
                    hw = sum((v * w for v, w in zip(h, omega)), sp.Integer(0))
                    phase = sp.Add(*[v * g for v, g in zip(h, angles) if v])
                    # cos(h psi) cos(n psi_l) = (cos(h psi + n psi_l) + cos(h psi - n psi_l))/2
                    # (one term when h = 0); sin likewise
                    for sign in ((1,) if not any(h) else (1, -1)):
                        half = 1 if not any(h) else sp.Rational(1, 2)
                        divisor = sp.factor(w_i**2 - (hw + sign * n * omega[l])**2)
                        body = r * ja * half * fn(phase + sign * n * angles[l])
                        parts.append(sp.Sum(body / divisor, (m, start, sp.oo)))
        return sp.Add(*parts)

    def substitution(self) -> dict:
        """``{J symbol: besselj(n, c a_l)}``."""
        a = amplitudes(max((l for _, l, _ in self.symbols), default=0) + 1)
        return {s: sp.besselj(n, c * a[l]) for (c, l, n), s in self.symbols.items()}


def _key(factor: sp.Expr, state: tuple) -> tuple[str, sp.Expr, int]:
    """``(kind, c, l)`` of ``sin(c x_{l+1})``/``cos(c x_{l+1})``, or an error that says what
    the averaging takes."""
    form = linear_argument(factor.args[0], state)  # the phase d is split off before
    if form is not None and form[2] == 0 and form[0] in state[:len(state) // 2]:
        xl, c, _ = form
        if c.has(sp.Float):
            raise UnsupportedTermError(
                f"the argument of {factor} holds a float: the exact coupled averaging takes "
                "exact numbers; write it as a fraction (0.5 as 1/2)")
        return type(factor).__name__, c, state.index(xl)
    raise UnsupportedTermError(
        f"the term {factor} is not supported by the exact coupled averaging: it takes "
        "polynomials in the state and, at order one, sin(c x_i + d) and cos(c x_i + d) "
        f"of one position with a constant c (Jacobi-Anger); {_NUMERIC_HINT}")


def jacobi_anger_plan(rows: list[list[sp.Expr]], model, order: int, tol: float
                      ) -> JacobiAnger | None:
    """The cut series for the ``sin``/``cos`` factors of ``rows`` (``rows[i][k]``: the
    coefficient of ``mu**k`` of ``F_i``), or ``None`` when ``F`` is polynomial.

    Raises
    ------
    kbm.errors.UnsupportedTermError
        For a term with more than one such factor (a product of two infinite series, whose
        resonant part is an infinite sum), an argument that is not ``c x_i``, or a hard
        forcing on the model.
    kbm.errors.OrderError
        For an order above one.
    """
    state = model.state
    sset = set(state)
    omega = model.omegas + ((model.nu0,) if model.forced else ())
    cuts: dict = {}
    for row in rows:
        for f in row:
            for term in sp.Add.make_args(sp.expand(f)):
                trig = trig_of_state(term, sset)
                if not trig:
                    continue
                if len(trig) > 1:
                    raise UnsupportedTermError(
                        f"the term {term} holds {len(trig)} factors sin or cos of the state: "
                        "its first-order rates are infinite sums of products of Bessel "
                        "functions, which the coupled symbolic averaging does not form "
                        f"(one such factor per term); {_NUMERIC_HINT}")
                key = _key(trig[0], state)
                rest = sp.Mul(*[g for g in sp.Mul.make_args(term) if g != trig[0]])
                try:
                    d = sp.Poly(rest, *state).total_degree() if rest.free_symbols & sset \
                        else 0
                except sp.PolynomialError:
                    raise UnsupportedTermError(
                        f"the term {term} is not a polynomial in the state times one sin or "
                        f"cos of a position; {_NUMERIC_HINT}") from None
                d += _theta_degree(rest)
                cuts[key] = max(cuts.get(key, 0), harmonic_bound(omega, key[2], d, tol))
    if not cuts:
        return None
    if model.hards:
        raise UnsupportedTermError(
            f"{model.name!r} has a hard forcing and sin or cos of the state: the shifted "
            f"position x_i + Lambda_i cos(theta) makes a double Bessel series; {_NUMERIC_HINT}")
    if order != 1:
        raise OrderError(
            f"the exact coupled averaging takes sin and cos of the state (Bessel functions) "
            f"at order 1, got order {order}: above it products of infinite series make "
            f"lattice sums (for one degree of freedom kbm.derive(model, N) forms them); "
            f"{_NUMERIC_HINT}")
    cs = sorted({c for _, c, _ in cuts}, key=sp.default_sort_key)
    symbols = {}
    for (kind, c, l), H in sorted(cuts.items(), key=lambda kv: (kv[0][2], cs.index(kv[0][1]),
                                                                  kv[0][0])):
        for n in range(0, H + 1):
            symbols.setdefault((c, l, n), sp.Symbol(f"_J{cs.index(c)}_{l}_{n}"))
    return JacobiAnger(cuts, symbols)
