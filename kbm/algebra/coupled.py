"""The exact algebra of the coupled recursion: ``N``-angle series with the resonance structure.

:class:`CoupledAlgebra` answers the one recursion (:func:`kbm.expansion.recursion.kbm_recursion`)
for ``N`` coupled oscillators, forced or not: ``N``-angle Fourier series
(:mod:`kbm.algebra.multi_angle`, the forcing angle ``theta`` the last one) with
Laurent-polynomial coefficients over Q in the amplitudes, the parameters and the detunings;
``L0 = sum_l omega_l d/dpsi_l``, the resonant part of ``R_{i,n}`` on the slow lattice of the
declared resonances, and the division of the rest by ``omega_i**2 - (h . omega)**2``.
:class:`MultiBuilder` makes the lazy series of a polynomial ``F_i`` (with Jacobi-Anger at
order one), :func:`coupled_rhs` the right-hand sides of every mode for the recursion.
"""

from __future__ import annotations

import math
from fractions import Fraction

import sympy as sp

from .laurent import LaurentRing, Q
from .lazy_series import Builder, Node, Scaled
from .multi_angle import MultiAngle, forcing_harmonics
from ..errors import ModelError, UnsupportedTermError
from ..expansion.recursion import SlowRates
from .coupled_bessel import _NUMERIC_HINT, JacobiAnger
from ..model.coupled import CoupledOscillators, amplitudes, positions, velocities
from ..expansion.resonance import SlowLattice, frequency, resonant_harmonic

__all__ = ["CoupledAlgebra", "AngleCalculus", "MultiBuilder", "coupled_rhs"]


class AngleCalculus(SlowRates):
    """The derivatives of :func:`kbm.expansion.recursion.kbm_recursion` for ``N``-angle series that
    carry them (``f.diff(l)``: ``d/da_l``, ``f.d_angle(l)``: ``d/dpsi_l``), with the forcing
    angle ``theta`` the last of the algebra's ``n`` angles and the detuning ``sig``: a mixin
    of the exact :class:`CoupledAlgebra` and the sampled
    :class:`~kbm.algebra.coupled_jets.JetAlgebra`."""

    n: int
    sig: object

    def da(self, f, l: int):
        return f.diff(l)

    def dpsi(self, f, l: int):
        return f.d_angle(l)

    def sigma_dtheta(self, f):
        """``sigma df/dtheta`` (``nu = nu0 + mu sigma``)."""
        return f.d_angle(self.n - 1).scale(self.sig)


class CoupledAlgebra(AngleCalculus):
    """``N``-angle series over Laurent coefficients, with the resonance structure (the exact
    multi-angle :class:`~kbm.algebra.base.RecursionAlgebra`)."""

    def __init__(self, model: CoupledOscillators, lattice: SlowLattice, gens: list[sp.Symbol],
                 tolerance: float, *, nu0: sp.Expr | None = None,
                 detuning: sp.Symbol | None = None, amplitude_symbols=None):
        """``nu0``, ``detuning`` and ``amplitude_symbols`` replace the model's forcing
        frequency, its detuning and the amplitudes ``a_i`` (the forced oscillator's
        declared resonance or fixed ``nu``, and its ``a``: :mod:`kbm.algebra.forced`).  The
        frequencies are rational, or rational multiples of one symbol (a symbolic
        ``omega0``), which then scales ``L0`` and the divisors."""
        dof = model.dof
        self.forced = model.forced
        n = dof + (1 if self.forced else 0)  # the forcing angle theta is the last one
        self.n, self.dof, self.model, self.lattice, self.tol = n, dof, model, lattice, tolerance
        if self.forced and nu0 is None:
            nu0 = model.nu0
            detuning = sp.Symbol(model.nu_detuning) if model.nu_detuning else None
        omega = model.omegas + ((nu0,) if self.forced else ())
        self.ring = LaurentRing([*(amplitude_symbols or amplitudes(dof)), *gens])
        self.sig = self.ring.gen(self.ring.gens.index(detuning)) if detuning else None
        scale = next((w.free_symbols.pop() for w in omega if not w.is_Rational), None)
        self.unit = None
        if scale is not None:  # omega_l = r_l * scale: L0 and the divisors carry the scale
            omega = tuple(w / scale for w in omega)
            k = self.ring.gens.index(scale)
            self.unit, self.unit_inv = self.ring.gen(k), self.ring.gen(k, -1)
        self.omega = omega
        self.wq = [Q(int(w.p), int(w.q)) for w in self.omega]
        self.wf = [Fraction(int(w.p), int(w.q)) for w in self.omega]
        self.a_inv = [self.ring.gen(i, -1) for i in range(dof)]
        self.detuned = self.sig is not None
        # integer frequencies (over their common denominator) and, per mode, the exact bound
        # of |h . omega| - omega_i beyond which a harmonic is not resonant (tolerance times
        # omega_i): the quick test of _resonant
        den = math.lcm(*(w.denominator for w in self.wf))
        self._w_int = [int(w * den) for w in self.wf]
        self._bound = [Fraction(tolerance) * w for w in self._w_int]
        self._memo: dict = {}

    # -- the ring protocol of the lazy series --------------------------------------------
    def zero(self) -> MultiAngle:
        return MultiAngle(self.ring, self.n)

    def _laurent(self, expr: sp.Expr):
        try:
            return self.ring.from_expr(sp.expand(expr))
        except (TypeError, sp.PolynomialError, sp.GeneratorsNeeded):
            hint = ("write each float as a fraction (0.1 as 1/10)" if expr.has(sp.Float) else
                    "a denominator may be a monomial in the parameters at most")
            raise ModelError(f"the coefficient {expr} is not a polynomial in the parameters "
                             "with exact numbers (rationals; constants such as sqrt(2), pi, "
                             f"cos(phi)): {hint}") from None

    def const(self, expr: sp.Expr) -> MultiAngle:
        """A coefficient free of the state: parameters, and a trigonometric polynomial in the
        forcing angle ``theta`` for a forced system."""
        theta = sp.Symbol("theta")
        zero = (0,) * self.n
        if not expr.has(theta):
            return MultiAngle(self.ring, self.n, {zero: self._laurent(expr)})
        out = self.zero()
        for k, kind, c in forcing_harmonics(expr, theta):
            out = out + MultiAngle.harmonic(self.ring, zero[:self.dof] + (k,),
                                            self._laurent(c), kind)
        return out

    def x0(self, i: int) -> MultiAngle:
        """``a_i cos(psi_i)``."""
        h = tuple(1 if l == i else 0 for l in range(self.n))
        return MultiAngle(self.ring, self.n, {h: self.ring.gen(i)})

    def L0(self, f: MultiAngle) -> MultiAngle:
        out = self.zero()
        for l, w in enumerate(self.wq):
            out = out + f.d_angle(l).scale_q(w)
        return out if self.unit is None else out.scale(self.unit)

    # -- resonance structure ----------------------------------------------------------
    def _resonant(self, h: tuple, i: int, n: int) -> tuple[tuple, int] | None:
        """``(k, s)`` with ``h . psi = s (psi_i + k . psi)``, ``k`` slow, or ``None``;
        raises for an undeclared (near) resonance (:func:`resonant_harmonic`, asked only
        when ``h . omega`` is within the tolerance of ``+-omega_i``; its answers kept)."""
        key = (h, i)
        if key in self._memo:
            return self._memo[key]
        f = sum(w * v for w, v in zip(self._w_int, h))
        out = None
        if abs(abs(f) - self._w_int[i]) <= self._bound[i]:
            out = resonant_harmonic(h, i, n, self.omega, self.lattice, self.tol, self.forced)
        self._memo[key] = out
        return out

    def secular(self, R: MultiAngle, i: int, n: int) -> tuple[MultiAngle, MultiAngle]:
        """``(A_{i,n}, B_{i,n})``: the resonant part of ``R_{i,n}`` as slow series."""
        ring = self.ring
        P, Qs = self.zero(), self.zero()
        for kind, table in (("cos", R.cos), ("sin", R.sin)):
            for h, c in table.items():
                res = self._resonant(h, i, n)
                if res is None:
                    continue
                k, s = res
                if kind == "cos":  # cos(psi_i + k psi) = cos psi_i cos k - sin psi_i sin k
                    P = P + MultiAngle.harmonic(ring, k, c, "cos")
                    Qs = Qs + MultiAngle.harmonic(ring, k, -c, "sin")
                else:  # sin(h psi) = s sin(psi_i + k psi) = s (sin psi_i cos k + cos psi_i sin k)
                    cs = c if s > 0 else -c
                    Qs = Qs + MultiAngle.harmonic(ring, k, cs, "cos")
                    P = P + MultiAngle.harmonic(ring, k, cs, "sin")
        half = Q(-1, 2) / self.wq[i]
        if self.unit is not None:
            Qs, P = Qs.scale(self.unit_inv), P.scale(self.unit_inv)
        return Qs.scale_q(half), P.scale(self.a_inv[i]).scale_q(half)

    def solve(self, R: MultiAngle, i: int, n: int) -> MultiAngle:
        """``u_{i,n}``: every non-resonant harmonic over ``omega_i**2 - (h . omega)**2``."""
        _, rest = R.split(lambda h: self._resonant(h, i, n) is not None)
        w2 = self.wf[i] ** 2

        def divide(h, c):
            d = w2 - frequency(h, self.omega) ** 2
            return c.scale(Q(d.denominator, d.numerator))

        out = rest.map_coefficients(divide)
        return out if self.unit is None else out.scale(self.unit_inv * self.unit_inv)


class MultiBuilder(Builder):
    """The lazy-series tree of a polynomial ``F_i`` along the leaves ``x_l``, ``xdot_l``
    (the skeleton of :meth:`kbm.algebra.lazy_series.Builder.build`), with Jacobi-Anger
    (``bessel``) for ``sin`` and ``cos`` of a position at order one."""

    def __init__(self, alg: CoupledAlgebra, leaves: dict, bessel: JacobiAnger | None = None):
        self.alg, self.leaves, self.bessel = alg, leaves, bessel
        self.zero = alg.zero
        self._pow: dict = {}
        self._state = set(leaves)

    def varies(self, expr: sp.Expr) -> bool:
        return bool(expr.free_symbols & self._state)

    def scaled(self, node: Node, const: sp.Expr) -> Node:
        c = self.alg.const(const)
        return Scaled(self.zero, node, lambda s, c=c: s * c)

    def other(self, expr: sp.Expr) -> Node:
        if self.bessel is not None and isinstance(expr, (sp.sin, sp.cos)):
            return self.bessel.series(self.alg, expr)  # Jacobi-Anger, order one
        raise UnsupportedTermError(
            f"the term {expr} is not supported by the exact coupled averaging: it takes "
            "polynomials in the state and, at order one, sin(c x_i + d) and cos(c x_i + d) "
            f"of one position (Jacobi-Anger); {_NUMERIC_HINT}")


def coupled_rhs(alg, F: list[list[sp.Expr]], builder=MultiBuilder):
    """The right-hand sides of the ``N`` modes for :func:`kbm.expansion.recursion.kbm_recursion`.

    ``F[i][k]`` is the coefficient of ``mu**k`` of mode ``i``'s right-hand side;
    ``builder(alg, leaves)`` makes the lazy series of one of them along the leaves
    ``{x_l: X[l], xdot_l: V[l]}`` (:class:`MultiBuilder` for exact polynomials; the sampled
    algebra of :mod:`kbm.backend.jets` passes its Taylor expansion).
    """
    def rhs(X, V):
        n = alg.dof
        leaves = {**dict(zip(positions(n), X)), **dict(zip(velocities(n), V))}
        b = builder(alg, leaves)
        return [[(k, b.build(sp.expand(Fk))) for k, Fk in enumerate(Fi) if Fk != 0]
                for Fi in F]

    return rhs
