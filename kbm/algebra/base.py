"""The contracts between the KBM recursion and its algebras of Fourier series.

The one recursion (:func:`kbm.expansion.recursion.kbm_recursion`) never looks inside a Fourier
series or a rate: it asks a :class:`RecursionAlgebra` (``N`` modes, an optional forcing angle) for
the few operations it names.  Its algebras are

- the exact multi-angle algebra of coupled systems
  (:class:`kbm.algebra.coupled.CoupledAlgebra`: Laurent coefficients, the slow lattice of
  the declared resonances, Jacobi-Anger at order one);
- its case of one forced oscillator, two angles ``(psi, theta)``
  (:class:`kbm.algebra.forced.ForcedAlgebra`);
- the sampled ones: one or two angles on a grid (:class:`kbm.algebra.grid.SampledAlgebra`,
  forced or not) and
  ``N`` angles with Taylor jets in the amplitudes (:class:`kbm.algebra.coupled_jets.JetAlgebra`,
  forced or not; one unforced mode at a batch of amplitudes, with Jacobi-Anger series for
  ``sin(k x)``, is the evaluated backend :func:`kbm.derive_values`);
- every one-angle :class:`FourierAlgebra` below, through the adapter
  :class:`kbm.expansion.recursion.OneAngle` (the case ``N = 1`` without forcing, whose rates are
  coefficients ``c(a)`` rather than series).

The one-angle contract :class:`FourierAlgebra` is answered by two exact algebras

- :class:`~kbm.algebra.poly_fourier.PolyAlgebra`: finite Fourier series in
  ``psi`` whose coefficients are exact Laurent polynomials in ``a``, the
  parameters and ``omega0`` (polynomial ``F``; any order);
- :class:`~kbm.algebra.bessel_fourier.SymAlgebra`: Fourier series with infinite
  Jacobi-Anger families of harmonics and sympy coefficients (``F`` with
  ``sin(k x)``, ``cos(k x)``; order <= 2).

Two kinds of object cross the contract: a *series* ``f(a, psi) = sum_m c_m(a)
cos(m psi) + s_m(a) sin(m psi)`` (type ``S``, see :class:`FourierSeries`) and a
*coefficient* ``c(a)``, a function of the amplitude and the parameters only
(type ``C``, opaque to the recursion).
"""

from __future__ import annotations

from typing import Any, Protocol, TypeVar, runtime_checkable

import sympy as sp

__all__ = ["FourierSeries", "FourierAlgebra", "RecursionAlgebra"]

S = TypeVar("S", bound="FourierSeries")
C = TypeVar("C")


@runtime_checkable
class FourierSeries(Protocol):
    """A Fourier series in ``psi`` with coefficients depending on ``a`` (and parameters).

    The ring operations are the pointwise ones in ``psi``; the lazy
    eps-series of :mod:`~kbm.algebra.lazy_series` need nothing else.
    """

    def __add__(self: S, other: S) -> S:
        """``f + g``."""

    def __sub__(self: S, other: S) -> S:
        """``f - g``."""

    def __neg__(self: S) -> S:
        """``-f``."""

    def __mul__(self: S, other: S) -> S:
        """``f g``, harmonics combined by the product-to-sum formulas."""

    def is_zero(self) -> bool:
        """Whether every harmonic of ``f`` has a zero coefficient."""

    def scale_q(self: S, q: Any) -> S:
        """``q f`` for a rational number ``q``."""

    def scale(self: S, c: Any) -> S:
        """``c f`` for a coefficient ``c`` independent of ``psi``."""


@runtime_checkable
class FourierAlgebra(Protocol[S, C]):
    """What the KBM recursion asks of an algebra of Fourier series ``S`` over coefficients ``C``.

    Attributes
    ----------
    w0
        The linear frequency ``omega0`` as a coefficient.
    exact
        ``True`` when every coefficient is exact rational algebra (the polynomial
        algebra), ``False`` when infinite Bessel sums appear; recorded as
        :attr:`kbm.KBMResult.exact`.
    """

    w0: C
    exact: bool

    def zero(self) -> S:
        """The zero series ``0``."""

    def const(self, expr: sp.Expr) -> S:
        """The series ``expr`` (no ``psi``: only the harmonic ``m = 0``) from a sympy
        expression in the parameters."""

    def coef(self, expr: sp.Expr) -> C:
        """The coefficient ``expr`` (a sympy expression in ``a`` and the parameters)."""

    def x0(self) -> S:
        """The leading term ``x_0 = a cos(psi)`` of the displacement."""

    def scale(self, f: S, c: C) -> S:
        """``c f``: a series times a coefficient independent of ``psi``."""

    def dpsi(self, f: S) -> S:
        """``df/dpsi``: harmonic ``m`` gains the factor ``m`` and swaps cos and sin."""

    def da(self, f: S) -> S:
        """``df/da``: the coefficients are differentiated, the harmonics kept."""

    def secular(self, R: S) -> tuple[C, C]:
        """``(A_n, B_n)`` that remove the first harmonic of ``R_n``.

        With ``R_n = r_c cos(psi) + r_s sin(psi) + ...`` (the other harmonics
        left out): ``A_n = -r_s/(2 omega0)``, ``B_n = -r_c/(2 omega0 a)``.
        """

    def solve(self, R: S) -> S:
        """``u_n`` with ``omega0**2 (u_n'' + u_n) = R_n`` minus its first harmonic.

        Harmonic ``m != 1`` is divided by ``omega0**2 (1 - m**2)``; ``m = 1`` is
        left out (the convention: no ``u_n`` holds a first harmonic).
        """

    def coef_expr(self, c: C) -> sp.Expr:
        """The coefficient ``c`` as a sympy expression, in the display form of
        :class:`kbm.KBMResult` (deterministic)."""

    def series_expr(self, f: S) -> sp.Expr:
        """The series ``f`` as a sympy expression in ``a`` and ``psi`` (deterministic)."""

    def trig(self, kind: str, c: sp.Expr) -> list[S]:
        """``[g(c x_0), g'(c x_0), g''(c x_0), g'''(c x_0)]`` for ``g = sin`` or ``cos``.

        ``kind`` is ``"sin"`` or ``"cos"``, ``c`` the coefficient ``k`` of
        ``g(k x)``; the series are the Jacobi-Anger expansions of
        ``g^(m)(k a cos psi)``.  An algebra without them raises
        :class:`~kbm.errors.UnsupportedTermError`.
        """


@runtime_checkable
class RecursionAlgebra(Protocol[S, C]):
    """What the one KBM recursion (:func:`kbm.expansion.recursion.kbm_recursion`) asks of an
    algebra.

    The series ``S`` are functions of the amplitudes ``a_1..a_N``, the phases
    ``psi_1..psi_N`` and, for a forced system, the forcing angle ``theta``; the rates ``C``
    (``A_{i,n}``, ``B_{i,n}``) are what :meth:`secular` returns: slow series for the
    multi-angle algebras, coefficients ``c(a)`` for the one-angle ones.

    Attributes
    ----------
    dof
        The number ``N`` of modes (degrees of freedom).
    detuned
        Whether ``D_1`` holds the detuning term ``sigma d/dtheta`` (``nu = nu0 + mu sigma``
        near a declared resonance of the forcing).
    """

    dof: int
    detuned: bool

    def zero(self) -> S:
        """The zero series."""

    def x0(self, i: int) -> S:
        """The leading term ``a_i cos(psi_i)`` of mode ``i``."""

    def L0(self, f: S) -> S:
        """``L0 f = sum_l omega_l df/dpsi_l (+ nu0 df/dtheta)``: the unperturbed flow."""

    def da(self, f: S, l: int) -> S:
        """``df/da_l``."""

    def dpsi(self, f: S, l: int) -> S:
        """``df/dpsi_l``."""

    def sigma_dtheta(self, f: S) -> S:
        """``sigma df/dtheta`` (asked for only when :attr:`detuned`)."""

    def times(self, c: C, f: S) -> S:
        """``c f``: a rate times a series."""

    def rate_vanishes(self, c: C) -> bool:
        """Whether the rate ``c`` is zero (its term of ``D_j`` is skipped)."""

    def secular(self, R: S, i: int, n: int) -> tuple[C, C]:
        """``(A_{i,n}, B_{i,n})`` that remove the resonant part of ``R_{i,n}``.

        With that part ``P cos(psi_i) + Q sin(psi_i)`` (``P``, ``Q`` slow):
        ``A_{i,n} = -Q/(2 omega_i)``, ``B_{i,n} = -P/(2 omega_i a_i)``.
        """

    def solve(self, R: S, i: int, n: int) -> S:
        """``u_{i,n}``: every non-resonant harmonic ``h`` of ``R_{i,n}`` over
        ``omega_i**2 - (h . omega)**2``; the resonant ones are left out (the convention)."""
