"""Callable results of the numeric KBM backend: functions of ``a`` and of ``(a, psi)``.

An :class:`AmplitudeFunction` holds the values of ``A_n`` or ``B_n`` at the Chebyshev
points of the amplitude interval and evaluates their polynomial interpolant
(barycentric formula; vectorised).  A :class:`WaveFunction` holds the Fourier
coefficients in ``psi`` of ``u_n`` at the same points and evaluates
``sum_m c_m(a) cos(m psi) + s_m(a) sin(m psi)``.  Both refuse amplitudes outside the
interval they were computed on: a Chebyshev interpolant does not extrapolate.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..algebra import chebyshev
from ..errors import ParameterError

__all__ = ["AmplitudeFunction", "WaveFunction", "ConstantFunction"]


@dataclass(frozen=True, eq=False)
class _OnInterval:
    """A function of ``a`` on ``[lo, hi]`` from samples at the Chebyshev points of the
    (wider) grid interval ``[grid_lo, grid_hi]``; ``name`` (``"A_2"``, ``"u_3"``, ...) is
    used in error messages."""

    name: str
    lo: float
    hi: float
    grid_lo: float
    grid_hi: float

    def _check(self, a: np.ndarray) -> None:
        """Refuse amplitudes outside ``[lo, hi]``: a Chebyshev interpolant does not
        extrapolate."""
        lo, hi = self.lo, self.hi
        slack = 1e-12 * (hi - lo)
        if a.size and (not np.all(np.isfinite(a)) or a.min() < lo - slack or a.max() > hi + slack):
            bad = a[~np.isfinite(a) | (a < lo - slack) | (a > hi + slack)].ravel()[0]
            raise ParameterError(f"{self.name} was computed for a in [{lo:g}, {hi:g}] and is "
                                 f"not defined at a = {bad:g}; evaluate inside that interval or "
                                 "derive again with a wider a-range")


@dataclass(frozen=True, eq=False)
class AmplitudeFunction(_OnInterval):
    """``f(a)`` on ``[lo, hi]`` from its ``values`` at the Chebyshev points
    :func:`kbm.algebra.chebyshev.points` ``(grid_lo, grid_hi, len(values))``."""

    values: np.ndarray

    def __call__(self, a) -> np.ndarray | float:
        arr = np.asarray(a, dtype=float)
        self._check(arr)
        out = chebyshev.interpolate(self.values, self.grid_lo, self.grid_hi, arr)
        return float(out) if np.ndim(a) == 0 else out


@dataclass(frozen=True, eq=False)
class WaveFunction(_OnInterval):
    """``u(a, psi)`` on ``[lo, hi] x R`` from Fourier coefficients at the Chebyshev points:
    ``cos``, ``sin`` arrays ``(P, H + 1)`` of the coefficients of ``cos(m psi)`` and
    ``sin(m psi)``, ``m = 0..H``, at the ``P`` points."""

    cos: np.ndarray
    sin: np.ndarray

    def __call__(self, a, psi) -> np.ndarray | float:
        a_arr, p_arr = np.broadcast_arrays(np.asarray(a, dtype=float),
                                           np.asarray(psi, dtype=float))
        self._check(a_arr)
        if not np.all(np.isfinite(p_arr)):
            raise ParameterError(f"{self.name} needs finite phases psi")
        flat_a, flat_p = a_arr.ravel(), p_arr.ravel()
        out = np.empty(flat_a.shape)
        m = np.arange(self.cos.shape[1])
        step = 4096
        for s in range(0, flat_a.size, step):
            W = chebyshev.barycentric_matrix(self.grid_lo, self.grid_hi, self.cos.shape[0],
                                             flat_a[s:s + step])
            ph = np.outer(flat_p[s:s + step], m)
            out[s:s + step] = (np.sum((W @ self.cos) * np.cos(ph), axis=1)
                               + np.sum((W @ self.sin) * np.sin(ph), axis=1))
        out = out.reshape(a_arr.shape)
        return float(out) if out.ndim == 0 else out


@dataclass(frozen=True, eq=False)
class ConstantFunction:
    """The order-0 entries: ``A_0 = 0``, ``B_0 = omega0``, ``u_0 = a cos(psi)``."""

    name: str
    value: float
    wave: bool = False

    def __call__(self, a, psi=None):
        arr = np.asarray(a, dtype=float)
        if self.wave:
            out = arr * np.cos(np.asarray(psi, dtype=float))
        else:
            out = np.full(arr.shape, self.value)
        return float(out) if np.ndim(out) == 0 else out
