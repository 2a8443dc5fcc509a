"""Fourier series sampled on a grid: the algebra of the numeric KBM backend.

A series ``f(a, psi)`` is held as its values on the tensor grid of ``P`` Chebyshev
points ``a_i`` of an amplitude interval (:mod:`~kbm.algebra.chebyshev`) and ``M``
equispaced phases ``psi_j = 2 pi j/M``; a coefficient ``c(a)`` as its ``P`` values.
Products are pointwise, ``d/dpsi`` and the harmonic balance (secular terms, ``u_n``)
act on the discrete Fourier transform in ``psi``, ``d/da`` is the Chebyshev
differentiation matrix.  Everything is spectrally accurate for analytic functions;
the resolution ``(P, M)`` is chosen by :mod:`kbm.numeric_kbm`, which also measures
what was lost (the coefficient tails).

:class:`GridAlgebra` offers the part of :class:`~kbm.algebra.base.FourierAlgebra`
that the recursion :func:`kbm.recursion.one_angle_recursion` asks for; there is no symbolic
display (``coef_expr``, ``series_expr``) and no ``trig``: ``F`` is expanded by
:mod:`~kbm.algebra.smooth`, whatever its functions.
"""

from __future__ import annotations

import numpy as np

from . import chebyshev

__all__ = ["Samples", "PhaseGrid", "GridSeries", "GridCoef", "GridAlgebra"]


class GridCoef:
    """A coefficient ``c(a)``: its values at the ``P`` amplitudes (false when all zero)."""

    __slots__ = ("values",)

    def __init__(self, values: np.ndarray):
        self.values = np.asarray(values, dtype=float)

    def __bool__(self) -> bool:
        return bool(np.any(self.values != 0.0))


class Samples:
    """Values on a grid, ``values is None`` the exact zero, with the ring operations that act
    value by value: the base of every sampled series (the one-angle algebras', the forced
    grid's :class:`kbm.forced.grid.SampledSeries`, the coupled jets'
    :class:`kbm.coupled.jet_algebra.JetSeries`).  Each gives its product; one that carries
    more than its values (a degree, a cap) gives :meth:`_new` and, when a sum is not the sum
    of the values, :meth:`_plus`."""

    __slots__ = ("values",)

    def __init__(self, values: np.ndarray | None):
        self.values = values

    def is_zero(self) -> bool:
        return self.values is None

    def _new(self, values: np.ndarray | None):
        """A series of the same kind with other values."""
        return type(self)(values)

    def _plus(self, other):
        """The sum of two non-zero series."""
        return self._new(self.values + other.values)

    def __add__(self, other):
        if other.values is None:
            return self
        if self.values is None:
            return other
        return self._plus(other)

    def __neg__(self):
        return self if self.values is None else self._new(-self.values)

    def __sub__(self, other):
        return self + (-other)

    def scale_q(self, q):
        return self if self.values is None else self._new(self.values * float(q))


class GridSeries(Samples):
    """Samples ``f(a_i, psi_j)``, shape ``(P, M)``; ``values is None`` is the exact zero."""

    __slots__ = ()

    def __mul__(self, other: "GridSeries") -> "GridSeries":
        if self.values is None or other.values is None:
            return GridSeries(None)
        return GridSeries(self.values * other.values)

    def scale(self, c) -> "GridSeries":
        """``c f`` for a number or a coefficient (``P`` values, one per amplitude)."""
        if self.values is None:
            return self
        if isinstance(c, GridCoef):
            return GridSeries(self.values * c.values[:, None])
        return GridSeries(self.values * float(c))


class PhaseGrid:
    """``M`` equispaced phases ``psi_j`` (the last axis of the samples): the harmonic balance
    of the one-angle sampled algebras.  The first harmonic is left out of every ``u_n``, the
    Nyquist mode (without a sine partner) is dropped."""

    exact = False

    def _phases(self, omega0: float, M: int) -> None:
        self.w0 = float(omega0)
        self.M = int(M)
        self.psi = 2 * np.pi * np.arange(self.M) / self.M
        m = np.arange(self.M // 2 + 1).astype(float)
        div = self.w0**2 * (1.0 - m**2)
        div[1] = np.inf  # the first harmonic is left out of every u_n
        self._inv = 1.0 / div
        self._inv[-1] = 0.0  # the Nyquist mode has no sine partner: dropped
        self._ik = 1j * m
        self._ik[-1] = 0.0

    def scale(self, f: Samples, c) -> Samples:
        """``c f`` for a number or a coefficient."""
        return f.scale(c)

    def harmonic1(self, R: Samples) -> tuple[np.ndarray, np.ndarray]:
        """``(r_c, r_s)``: the coefficients of ``cos psi`` and ``sin psi`` of ``R`` (not zero)."""
        # project on cos and sin directly: one pass, no full transform
        c = R.values @ np.cos(self.psi) * (2.0 / self.M)
        s = R.values @ np.sin(self.psi) * (2.0 / self.M)
        return c, s

    def solve(self, R: Samples) -> Samples:
        """``u_n``: harmonic ``m != 1`` of ``R_n`` over ``omega0**2 (1 - m**2)``."""
        if R.values is None:
            return R
        spec = np.fft.rfft(R.values, axis=-1) * self._inv
        return type(R)(np.fft.irfft(spec, n=self.M, axis=-1))


class GridAlgebra(PhaseGrid):
    """Series sampled on ``P`` Chebyshev amplitudes of ``[lo, hi]`` times ``M`` phases.

    Parameters
    ----------
    omega0
        The linear frequency (a positive number).
    lo, hi
        The amplitude interval, ``0 < lo < hi``.
    P, M
        Chebyshev points in ``a`` and phases in ``psi`` (``M`` even).
    chop
        Chebyshev coefficients below ``chop`` times the largest are dropped before a
        differentiation in ``a`` (:meth:`da`).
    """

    def __init__(self, omega0: float, lo: float, hi: float, P: int, M: int,
                 chop: float = 1e-14):
        self._phases(omega0, M)
        self.chop = float(chop)
        self.lo, self.hi, self.P = float(lo), float(hi), int(P)
        self.a = chebyshev.points(lo, hi, P)

    # -- the recursion's vocabulary ----------------------------------------------------
    def zero(self) -> GridSeries:
        return GridSeries(None)

    def const(self, value) -> GridSeries:
        return GridSeries(np.full((self.P, self.M), float(value)))

    def coef(self, value) -> GridCoef:
        return GridCoef(np.full(self.P, float(value)))

    def x0(self) -> GridSeries:
        return GridSeries(self.a[:, None] * np.cos(self.psi)[None, :])

    def dpsi(self, f: GridSeries) -> GridSeries:
        if f.values is None:
            return f
        spec = np.fft.rfft(f.values, axis=1)
        # as in da: rounding noise above the bandwidth would be multiplied by m (and by
        # the differentiations in a that follow), so it is dropped first
        spec[np.abs(spec) < self.chop * np.max(np.abs(spec))] = 0.0
        return GridSeries(np.fft.irfft(spec * self._ik, n=self.M, axis=1))

    def da(self, f: GridSeries) -> GridSeries:
        """``df/da`` (:func:`~kbm.algebra.chebyshev.differentiate`, coefficients below
        ``chop`` times the largest dropped first)."""
        if f.values is None:
            return f
        return GridSeries(chebyshev.differentiate(f.values, self.lo, self.hi, 0, self.chop))

    def at_amplitudes(self, f) -> np.ndarray:
        """The samples of a series or coefficient at the ``P`` amplitudes."""
        return f.values

    def secular(self, R: GridSeries) -> tuple[GridCoef, GridCoef]:
        if R.values is None:
            return GridCoef(np.zeros(self.P)), GridCoef(np.zeros(self.P))
        rc, rs = self.harmonic1(R)
        return GridCoef(-rs / (2 * self.w0)), GridCoef(-rc / (2 * self.w0 * self.a))
