"""The escape rate from the well at the origin by the Kramers equation: the slowest decay
rate of the density when everything that passes a saddle is removed.

Beyond the saddles ``x_l < 0 < x_r`` bounding the well a sink ``kappa(x) = kappa_0 [1 +
tanh((|x| - x_s - 3 w)/w)]/2`` is added to the Kramers operator (:mod:`.kramers`), on
``[x_l - m, x_r + m]``.  The population between the saddles then decays as ``exp(-r t)``
with ``r`` the smallest eigenvalue of ``-(L - kappa)`` (shift-invert Arnoldi on the sparse
Hermite-Chebyshev matrix, its constrained rows a zero block of the mass matrix): the rate
of first passage beyond the saddle, at any damping (Hanggi, Talkner and Borkovec, Rev.
Mod. Phys. 62 (1990) 251, sec. II.C: the rate as the lowest nonvanishing eigenvalue).
As ``kappa_0 -> oo`` and ``w -> 0`` the sink becomes the absorbing line ``|x| = x_s`` of
the simulated first passages; the rate is given at two sinks and two Hermite truncations,
and their differences are its stated errors.

It is compared (tests/test_fokker_planck_escape.py, docs/noise.rst) with the energy-
diffusion MFPT of the averaged energy, Kramers' low-friction rate and the Mel'nikov-
Meshkov rate across the turnover.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sps

from kbm.conservative import split_conservative
from kbm.errors import ModelError, ParameterError

from .kramers import _linear_temperature, kramers_operator, velocity_terms

__all__ = ["KramersEscape", "kramers_escape"]


@dataclass(frozen=True)
class KramersEscape:
    """The escape rate from the well at the origin by the Kramers equation.

    Attributes
    ----------
    rate : float
        The slowest decay rate with the sharper sink and the larger truncation.
    sink_error, truncation_error : float
        Its change from the softer sink, and from half the Hermite functions.
    saddles : tuple of float
    hermite, chebyshev : int
    """

    rate: float
    sink_error: float
    truncation_error: float
    saddles: tuple
    hermite: int
    chebyshev: int

    def __repr__(self) -> str:
        return (f"KramersEscape(rate={self.rate:.7g} +- {self.sink_error:.2g} (sink) +- "
                f"{self.truncation_error:.2g} (truncation))")


def _slowest(split, D, sigma, saddles, nh, nc, kappa0, width, margin):
    import scipy.sparse.linalg as spla

    xl, xr = saddles
    half = max(-xl, xr) + margin
    A, xs, _ = kramers_operator(split, D, sigma, half, nh, nc)
    m = xs.size
    edge = np.where(xs > 0, xr, -xl)
    kappa = kappa0 * 0.5 * (1 + np.tanh((np.abs(xs) - edge - 3 * width) / width))
    A = A - sps.kron(sps.identity(nh), sps.diags(kappa))
    keep = np.ones(nh * m)
    ends = np.concatenate([[k * m, k * m + m - 1] for k in range(2, nh)])
    keep[ends] = 0.0
    C = sps.csr_matrix((np.ones(ends.size), (ends, ends)), shape=A.shape)
    B = sps.diags(keep).tocsc()
    lu = spla.splu((sps.diags(keep) @ A + C).tocsc())
    op = spla.LinearOperator(A.shape, matvec=lambda v: lu.solve(B @ v), dtype=float)
    theta = spla.eigs(op, k=3, which="LM", return_eigenvectors=False, tol=1e-12)
    lam = 1.0 / theta
    lam = lam[np.argsort(np.abs(lam))]
    return float(-lam[0].real)


def kramers_escape(model, params: dict, D: float, saddles: tuple, *, n_hermite: int = 64,
                   n_cheb: int = 160, margin: float = 0.6) -> KramersEscape:
    """The rate of escape beyond the saddles from the Kramers equation with a sink.

    Parameters
    ----------
    model : str or kbm.models.Oscillator
        An autonomous model with a well at the origin (a slider at ``v = 0``).
    params : dict
        Its parameters with ``mu``.
    D : float
        Noise intensity, ``> 0``.
    saddles : (float, float)
        The saddles ``x_l < 0 < x_r`` bounding the well.
    n_hermite, n_cheb : int
        Hermite functions and Chebyshev intervals (the truncation error is the change
        from ``n_hermite/2``).
    margin : float
        How far past the saddles the range reaches (the sink lives there).

    Returns
    -------
    KramersEscape
    """
    if not (math.isfinite(D) and D > 0):
        raise ParameterError(f"D = {D}: the escape needs noise D > 0")
    xl, xr = map(float, saddles)
    if not (math.isfinite(xl) and math.isfinite(xr) and xl < 0 < xr):
        raise ModelError(f"saddles {saddles}: need x_l < 0 < x_r (a well at the origin "
                         "bounded on both sides)")
    split = split_conservative(model, {k: v for k, v in dict(params).items() if k != "D"})
    mu = float(split.mu)
    if not mu > 0:
        raise ParameterError(f"mu = {mu:g} must be > 0")
    kT = _linear_temperature(velocity_terms(split), D)
    sigma = math.sqrt(kT if kT is not None else D / mu)
    scale = 1.0 / max(-xl, xr)
    sharp = (100.0, 0.02 / scale)
    soft = (30.0, 0.04 / scale)
    r = _slowest(split, D, sigma, (xl, xr), n_hermite, n_cheb, *sharp, margin)
    r_soft = _slowest(split, D, sigma, (xl, xr), n_hermite, n_cheb, *soft, margin)
    r_half = _slowest(split, D, sigma, (xl, xr), n_hermite // 2, n_cheb, *sharp, margin)
    return KramersEscape(r, abs(r - r_soft), abs(r - r_half), (xl, xr), n_hermite,
                         n_cheb + 1)
