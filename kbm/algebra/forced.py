"""The algebra of the forced recursion: the coupled algebra at ``N = 1`` with a forcing angle.

:class:`ForcedAlgebra` is :class:`~kbm.algebra.coupled.CoupledAlgebra` for one oscillator
and the forcing angle ``theta`` (two-angle series in ``(psi, theta)``, the slow lattice of
the declared resonance ``p psi - q theta``), with the forced engine's words: a non-resonant
expansion (fixed ``nu``, no resonance declared) that meets a small divisor raises
:class:`SmallDivisorError` naming the resonance ``nu = (p/q) omega0`` to declare, and a
coefficient that is not rational is refused with the forced engine's message.
"""

from __future__ import annotations

from fractions import Fraction

import sympy as sp

from .coupled import CoupledAlgebra
from ..errors import ModelError
from ..expansion.resonance import UndeclaredResonanceError

__all__ = ["ForcedAlgebra", "SmallDivisorError"]


class SmallDivisorError(UndeclaredResonanceError):
    """A harmonic of the expansion is (nearly) resonant but the resonance was not declared
    (the coupled engine's :class:`~kbm.expansion.resonance.UndeclaredResonanceError`, in the
    words of one forced oscillator)."""


class ForcedAlgebra(CoupledAlgebra):
    """:class:`~kbm.algebra.coupled.CoupledAlgebra` of one forced oscillator; ``ratio`` is
    ``nu0/omega0``."""

    def __init__(self, *args, ratio: Fraction, **kwargs):
        super().__init__(*args, **kwargs)
        self.r = ratio

    def _laurent(self, expr: sp.Expr):
        try:
            return self.ring.from_expr(sp.expand(expr))
        except (TypeError, sp.PolynomialError, sp.GeneratorsNeeded):
            raise ModelError(f"the coefficient {expr} is not a rational function of the "
                             "parameters with a monomial denominator; the exact forced "
                             "averaging needs rational numbers (no pi, no sqrt, no floats)") \
                from None

    def _resonant(self, h: tuple, i: int, n: int):
        try:
            return super()._resonant(h, i, n)
        except UndeclaredResonanceError:
            raise SmallDivisorError(small_divisor_message(*h, self.r, n)) from None


def small_divisor_message(m: int, k: int, r: Fraction, n: int) -> str:
    """The harmonic ``cos(m psi + k theta)`` of ``R_n`` at ``nu = r omega0`` is within the
    tolerance of ``+-omega0``: the resonance ``nu = (1 -+ m)/k omega0`` named."""
    f = m + k * r
    gap = abs(abs(f) - 1)
    near = abs(Fraction(1 - m, k) if f > 0 else Fraction(-1 - m, k))
    what = "exactly at" if gap == 0 else f"within {float(gap):.3g} omega0 of"
    arg = " + ".join(t for t in (_times(m, "psi"), _times(k, "theta")) if t)
    return (f"the forcing frequency nu = {r} omega0 is {what} the resonance "
            f"nu = {near} omega0: the harmonic cos({arg}) of R_{n} has the small "
            f"divisor omega0^2 (1 - ({m} + {k} nu/omega0)^2) and the non-resonant expansion "
            f"breaks down; declare it: resonance='{near.numerator}/{near.denominator}' "
            f"with the detuning sigma = (nu - {near} omega0)/mu")


def _times(c: int, name: str) -> str:
    return "" if c == 0 else name if c == 1 else f"-{name}" if c == -1 else f"{c}*{name}"
