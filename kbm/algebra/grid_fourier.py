"""What the sampled algebras share: values on a grid with their ring operations, and the
harmonic balance in one phase.

- :class:`Samples`: the base of every sampled series (the grid algebra's
  :class:`kbm.forced.grid.SampledSeries`, which runs the numeric backends of one degree of
  freedom, forced or not; the jets of :mod:`~kbm.algebra.jet_fourier` and
  :mod:`kbm.coupled.jet_algebra`);
- :class:`GridCoef`: a coefficient ``c(a)`` by its values at the amplitudes;
- :class:`PhaseGrid`: ``M`` equispaced phases, the first harmonic (secular terms) by
  projection and ``u_n`` by the real FFT (the jets of :mod:`~kbm.algebra.jet_fourier`).
"""

from __future__ import annotations

import numpy as np

__all__ = ["Samples", "PhaseGrid", "GridCoef"]


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
