"""The algebra of the forced recursion: two-angle series with the resonance structure.

:class:`ResonantAlgebra` offers the lazy eps-series of :mod:`kbm.algebra.lazy_series` the
ring operations on :class:`~kbm.algebra.two_angle.TwoAngle` series (constants of ``F`` may
hold ``cos(k theta)``), and the recursion of :mod:`kbm.expansion.forced` the operator
``L0 = omega0 d/dpsi + nu0 d/dtheta``, the split of ``R_n`` into its resonant part (which
gives ``A_n``, ``B_n``) and the division of the rest by ``omega0**2 - (m omega0 + k nu0)**2``
(with the small-divisor check of a non-resonant expansion).
"""

from __future__ import annotations

from fractions import Fraction

import sympy as sp

from .laurent import Laurent, LaurentRing, Q
from .multi_angle import forcing_harmonics
from ..errors import ModelError
from ..expansion.recursion import SlowRates
from ..symbols import a, mu, x, xdot
from ..model.forced import ForcedOscillator, Resonance, sigma, theta
from .two_angle import TwoAngle

__all__ = ["ResonantAlgebra", "SmallDivisorError"]


class SmallDivisorError(ModelError):
    """A harmonic of the expansion is (nearly) resonant but the resonance was not declared."""


class ResonantAlgebra(SlowRates):
    """Two-angle series over Laurent coefficients, with the resonance structure: the case
    ``N = 1`` with a forcing angle of :class:`~kbm.algebra.base.RecursionAlgebra`."""

    dof = 1

    def __init__(self, model: ForcedOscillator, res: Resonance | None, ratio: Fraction,
                 tolerance: float, F: list[sp.Expr] | None = None):
        syms = set().union(*[f.free_symbols for f in (F or [model.F])]) \
            | model.omega0.free_symbols
        gens = sorted(syms - {x, xdot, theta, sigma, mu}, key=lambda s: s.name)
        self.res, self.r, self.tol = res, ratio, tolerance
        self.ring = LaurentRing([a, *gens, *([sigma] if res else [])])
        w0 = model.omega0
        if w0.is_Symbol:
            i = self.ring.gens.index(w0)
            self.w0, self.w0inv = self.ring.gen(i), self.ring.gen(i, -1)
        else:
            self.w0 = self.ring.const(Q(int(w0.p), int(w0.q)))
            self.w0inv = self.ring.const(Q(int(w0.q), int(w0.p)))
        self.nu0 = self.w0.scale(Q(ratio.numerator, ratio.denominator))
        self.a_inv = self.ring.gen(0, -1)
        self.sig = self.ring.gen(len(self.ring.gens) - 1) if res else None
        self.detuned = self.sig is not None
        self.model = model

    # -- the ring protocol of the lazy series ------------------------------------------
    def zero(self) -> TwoAngle:
        return TwoAngle(self.ring)

    def coef(self, expr: sp.Expr) -> TwoAngle:
        return self.const(expr)

    def scale(self, f: TwoAngle, c) -> TwoAngle:
        return f.scale(c)

    def const(self, expr: sp.Expr) -> TwoAngle:
        """A sympy expression in theta (trigonometric polynomial) and the parameters."""
        out = self.zero()
        for k, kind, c in forcing_harmonics(expr, theta):
            out = out + TwoAngle.harmonic(self.ring, 0, k, self._laurent(c, expr), kind)
        return out

    def _laurent(self, c: sp.Expr, where: sp.Expr) -> Laurent:
        try:
            return self.ring.from_expr(c)
        except (TypeError, sp.PolynomialError, sp.GeneratorsNeeded):
            raise ModelError(f"the coefficient {c} (in {where}) is not a rational function "
                             "of the parameters with a monomial denominator; the exact forced "
                             "averaging needs rational numbers (no pi, no sqrt, no floats)") \
                from None

    # -- calculus ------------------------------------------------------------------
    def x0(self, i: int = 0) -> TwoAngle:
        """``a cos(psi)``."""
        return TwoAngle(self.ring, {(1, 0): self.ring.gen(0)})

    def L0(self, f: TwoAngle) -> TwoAngle:
        return f.d_angle(0).scale(self.w0) + f.d_angle(1).scale(self.nu0)

    def da(self, f: TwoAngle, l: int = 0) -> TwoAngle:
        return f.da()

    def dpsi(self, f: TwoAngle, l: int = 0) -> TwoAngle:
        return f.d_angle(0)

    def sigma_dtheta(self, f: TwoAngle) -> TwoAngle:
        """``sigma df/dtheta`` (zero without a declared resonance)."""
        return f.d_angle(1).scale(self.sig) if self.sig is not None else self.zero()

    def resonant(self, m: int, k: int) -> tuple[int, int] | None:
        """``(j, s)`` with ``m psi + k theta = s psi + j (p psi - q theta)``, or ``None``."""
        if self.res is None:
            return (0, 1) if (m, k) == (1, 0) else None
        p, q = self.res.p, self.res.q
        if k % q:
            return None
        j = -k // q
        s = m - j * p
        return (j, s) if s in (1, -1) else None

    def secular(self, R: TwoAngle, i: int = 0, n: int = 0) -> tuple[TwoAngle, TwoAngle]:
        """``(A_n, B_n)``: the resonant part of ``R_n`` as slow series."""
        res, _ = R.split(lambda m, k: self.resonant(m, k) is not None)
        ring = self.ring
        p, q = (self.res.p, self.res.q) if self.res else (1, 0)
        P, Qs = self.zero(), self.zero()
        for kind, table in (("cos", res.cos), ("sin", res.sin)):
            for (m, k), c in table.items():
                j, s = self.resonant(m, k)
                jp, jq = j * p, -j * q
                if kind == "cos":  # cos(s psi + j Phi) = cos psi cos jPhi - s sin psi sin jPhi
                    P = P + TwoAngle.harmonic(ring, jp, jq, c, "cos")
                    Qs = Qs + TwoAngle.harmonic(ring, jp, jq, -c if s > 0 else c, "sin")
                else:  # sin(s psi + j Phi) = s sin psi cos jPhi + cos psi sin jPhi
                    P = P + TwoAngle.harmonic(ring, jp, jq, c, "sin")
                    Qs = Qs + TwoAngle.harmonic(ring, jp, jq, c if s > 0 else -c, "cos")
        half = Q(-1, 2)
        return Qs.scale(self.w0inv.scale(half)), P.scale((self.w0inv * self.a_inv).scale(half))

    def solve(self, R: TwoAngle, i: int, n: int) -> TwoAngle:
        """``u_n``: every non-resonant harmonic over ``omega0**2 - (m omega0 + k nu0)**2``."""
        _, rest = R.split(lambda m, k: self.resonant(m, k) is not None)
        w2inv = self.w0inv * self.w0inv

        def divide(mk, c):
            m, k = mk
            f = m + k * self.r
            d = 1 - f * f
            if self.res is None:
                self._check_divisor(m, k, f, n)
            return (c * w2inv).scale(Q(d.denominator, d.numerator))

        return rest.map_coefficients(divide)

    def _check_divisor(self, m: int, k: int, f: Fraction, n: int) -> None:
        gap = abs(abs(f) - 1)
        if gap > self.tol:
            return
        # m + k r = +-1: the forcing is near nu = (1 -+ m)/k omega0 (or exactly at it)
        near = Fraction(1 - m, k) if f > 0 else Fraction(-1 - m, k)
        near = abs(near)
        what = "exactly at" if gap == 0 else f"within {float(gap):.3g} omega0 of"
        arg = " + ".join(t for t in (_times(m, "psi"), _times(k, "theta")) if t)
        raise SmallDivisorError(
            f"the forcing frequency nu = {self.r} omega0 is {what} the resonance "
            f"nu = {near} omega0: the harmonic cos({arg}) of R_{n} has the small "
            f"divisor omega0^2 (1 - ({m} + {k} nu/omega0)^2) and the non-resonant expansion "
            f"breaks down; declare it: resonance='{near.numerator}/{near.denominator}' "
            f"with the detuning "
            f"sigma = (nu - {near} omega0)/mu")


def _times(c: int, name: str) -> str:
    return "" if c == 0 else name if c == 1 else f"-{name}" if c == -1 else f"{c}*{name}"
