"""Chebyshev points, differentiation, coefficients and interpolation on an interval.

The numeric KBM backend (:mod:`kbm.backend.one_dof`) samples every function of the
amplitude ``a`` at the Chebyshev extreme points of ``[lo, hi]``; this module holds the
four things done with such samples, each spectrally accurate for a function analytic
near the interval (Trefethen, *Approximation Theory and Approximation Practice*,
SIAM 2013, chs. 2, 5, 21):

- :func:`points`: ``a_j = (lo + hi)/2 - (hi - lo)/2 cos(j pi/(P - 1))``, ascending;
- :func:`differentiate`: the derivative of the polynomial interpolant ``f`` of the samples
  (by its coefficients);
- :func:`coefficients`: the Chebyshev coefficients of that interpolant (an FFT of the
  even extension), whose decay measures how well the samples resolve ``f``;
- :func:`interpolate`: the barycentric formula of the second kind at any points of the
  interval (stable; exact at the nodes).
"""

from __future__ import annotations

import numpy as np

__all__ = ["points", "coefficients", "interpolate", "barycentric_matrix"]


def _unit_points(P: int) -> np.ndarray:
    """``-cos(j pi/(P - 1))``, ``j = 0..P-1``: the extreme points on ``[-1, 1]``, ascending."""
    if P < 2:
        raise ValueError("at least two Chebyshev points are needed")
    return -np.cos(np.pi * np.arange(P) / (P - 1))


def points(lo: float, hi: float, P: int) -> np.ndarray:
    """The ``P`` Chebyshev extreme points of ``[lo, hi]``, ascending, ends included."""
    return 0.5 * (lo + hi) + 0.5 * (hi - lo) * _unit_points(P)


def _weights(P: int) -> np.ndarray:
    """Barycentric weights of the extreme points: ``(-1)**j``, halved at both ends."""
    w = (-1.0) ** np.arange(P)
    w[0] *= 0.5
    w[-1] *= 0.5
    return w


def coefficients(values: np.ndarray, axis: int = 0) -> np.ndarray:
    """Chebyshev coefficients ``c_0..c_{P-1}`` of the interpolant of samples at :func:`points`.

    ``f(a) = sum_k c_k T_k(x(a))`` with ``x`` the affine map of ``[lo, hi]`` onto
    ``[-1, 1]``; computed along ``axis`` by an FFT of the even extension.
    """
    v = np.moveaxis(np.asarray(values), axis, 0)[::-1]  # descending x = cos(j pi/n)
    n = v.shape[0] - 1
    if n == 0:
        return np.moveaxis(v.copy(), 0, axis)
    ext = np.concatenate([v, v[-2:0:-1]], axis=0)
    c = np.fft.fft(ext, axis=0)[: n + 1].real / n
    c[0] *= 0.5
    c[n] *= 0.5
    return np.moveaxis(c, 0, axis)


def barycentric_matrix(lo: float, hi: float, P: int, at: np.ndarray) -> np.ndarray:
    """The ``len(at) x P`` matrix ``W`` with ``W @ samples`` = the interpolant at ``at``.

    ``at`` must lie in ``[lo, hi]`` (the caller checks); a point that coincides with a
    node takes that node's sample exactly.
    """
    at = np.asarray(at, dtype=float).ravel()
    nodes = points(lo, hi, P)
    w = _weights(P)
    diff = at[:, None] - nodes[None, :]
    exact = diff == 0.0
    diff[exact] = 1.0
    W = w[None, :] / diff
    W /= W.sum(axis=1, keepdims=True)
    rows = np.nonzero(exact.any(axis=1))[0]
    for r in rows:
        W[r] = exact[r].astype(float)
    return W


def interpolate(values: np.ndarray, lo: float, hi: float, at: np.ndarray) -> np.ndarray:
    """The interpolant of ``values`` (samples at the ``len(values)`` points) at ``at``."""
    at = np.asarray(at, dtype=float)
    W = barycentric_matrix(lo, hi, len(values), at)
    return (W @ np.asarray(values)).reshape(at.shape)


def values(coeffs: np.ndarray, axis: int = 0) -> np.ndarray:
    """Samples at :func:`points` of ``sum_k c_k T_k``: the inverse of :func:`coefficients`."""
    c = np.moveaxis(np.asarray(coeffs, dtype=float), axis, 0).copy()
    n = c.shape[0] - 1
    if n == 0:
        return np.moveaxis(c, 0, axis)
    c[0] *= 2.0
    c[n] *= 2.0
    ext = np.concatenate([c, c[-2:0:-1]], axis=0)
    v = np.fft.fft(ext, axis=0)[: n + 1].real * 0.5
    return np.moveaxis(v[::-1], 0, axis)


def derivative_coefficients(coeffs: np.ndarray, lo: float, hi: float,
                            axis: int = 0) -> np.ndarray:
    """Chebyshev coefficients of the derivative (the backward recurrence
    ``c'_{k-1} = c'_{k+1} + 2 k c_k``), scaled to ``[lo, hi]``."""
    c = np.moveaxis(np.asarray(coeffs, dtype=float), axis, 0)
    n = c.shape[0]
    d = np.zeros_like(c)
    for k in range(n - 1, 0, -1):
        d[k - 1] = (d[k + 1] if k + 1 < n else 0.0) + 2.0 * k * c[k]
    d[0] *= 0.5
    return np.moveaxis(d * (2.0 / (hi - lo)), 0, axis)


def differentiate(samples: np.ndarray, lo: float, hi: float, axis: int = 0,
                  chop: float = 0.0) -> np.ndarray:
    """The derivative of the samples along ``axis`` (Chebyshev points of ``[lo, hi]``) by
    their coefficients, those below ``chop`` times the largest dropped first: the
    differentiation multiplies the rounding noise of degree ``k`` by ``~k**2``, and the
    recursions of the numeric backends differentiate results of earlier differentiations,
    so noise above the function's own bandwidth must not survive."""
    c = coefficients(samples, axis=axis)
    c[np.abs(c) < chop * np.max(np.abs(c))] = 0.0
    return values(derivative_coefficients(c, lo, hi, axis=axis), axis=axis)
