"""Finite real Fourier series in two angles ``(psi, theta)`` with exact Laurent coefficients.

``f(psi, theta) = sum c_{m,k} cos(m psi + k theta) + s_{m,k} sin(m psi + k theta)`` over
*canonical* index pairs (``m > 0``, or ``m = 0`` and ``k >= 0``); each coefficient is a
:class:`~kbm.algebra.laurent.Laurent` polynomial in the amplitude ``a``, the parameters
and the detuning.  This is the representation of the forced KBM recursion
(:mod:`kbm.expansion.forced`): ``psi`` is the oscillator's phase, ``theta = nu t`` the
forcing angle.  It is the multi-angle series of :mod:`kbm.algebra.multi_angle` with
``n = 2`` (the same canonical indices, product-to-sum formulas and derivatives), addressed
by the pair ``(m, k)``.
"""

from __future__ import annotations

import sympy as sp

from .laurent import Laurent, LaurentRing
from .multi_angle import MultiAngle
from .multi_angle import canonical as _canonical

__all__ = ["TwoAngle", "canonical"]


def canonical(m: int, k: int) -> tuple[int, int, int]:
    """``(m', k', sign)`` with ``(m', k')`` canonical and ``m psi + k theta = sign (m' psi +
    k' theta)``."""
    (m2, k2), sign = _canonical((m, k))
    return m2, k2, sign


class TwoAngle(MultiAngle):
    """A finite Fourier series in ``(psi, theta)``; ``cos``/``sin`` map ``(m, k)`` to a
    :class:`Laurent` coefficient."""

    __slots__ = ()

    def __init__(self, ring: LaurentRing, cos: dict | None = None, sin: dict | None = None):
        super().__init__(ring, 2, cos, sin)

    @classmethod
    def harmonic(cls, ring: LaurentRing, m: int, k: int, c: Laurent,
                 kind: str = "cos") -> "TwoAngle":
        """``c cos(m psi + k theta)`` (or ``sin``), any sign of ``(m, k)``."""
        m, k, sign = canonical(m, k)
        if kind == "cos":
            return cls(ring, {(m, k): c})
        return cls(ring, sin={(m, k): c if sign > 0 else -c})

    def _new(self, cos: dict, sin: dict) -> "TwoAngle":
        return TwoAngle(self.ring, cos, sin)

    def da(self) -> "TwoAngle":
        """``d/da`` (``a`` is generator 0 of the ring)."""
        return self.diff(0)

    def split(self, keep) -> tuple["TwoAngle", "TwoAngle"]:
        """``(part with keep(m, k) true, the rest)``."""
        return super().split(lambda mk: keep(*mk))

    def as_expr(self, psi: sp.Symbol, theta: sp.Symbol) -> sp.Expr:
        """The sympy expression, harmonics in a fixed order (deterministic, no factoring)."""
        return super().as_expr((psi, theta))
