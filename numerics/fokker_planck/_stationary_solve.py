"""The stationary Kramers equation of a nonlinearly damped model in orthonormal Hermite
functions of the velocity (:func:`orthonormal_stationary`, one solve at given sizes; the
ladder that chooses and measures the sizes is :mod:`._stationary_orthonormal`), and the
integrals of those functions that give the moments and ``P(E)``
(:class:`OrthonormalKramersSolution`; the functions themselves in :mod:`._hermite_functions`).

Why this basis: :mod:`._orthonormal` (Risken's pair ``He_n(u) exp(-u^2/2)`` grows every high
order where the local friction is negative; the SEDF at rest, mu = 0.1, Delta = 3,
D = 0.05, gave ``<x^2>`` = 2.2164, 2.2770, 2.3148 at 64, 128, 256 orders).  Here
``P(x, v) = sum_n c_n(x) h_n(v/s)/s`` with
``h_n(xi) = H_n(xi) exp(-xi^2/2)/(2^n n! sqrt(pi))^(1/2)``, every order projected on the
same functions (Galerkin), every ``c_n`` zero at ``x = +-L``.

The truncated Galerkin operator does not conserve the mass exactly (the constant is not in
the span of ``h_0 .. h_{N-1}``), so it is not singular: its eigenvalue nearest zero is a
truncation error, ``lambda_0``, and the stationary density is its eigenvector, found by
inverse iteration with the LU of :mod:`._pentadiagonal` (order by order, its factors on
disk when they would exceed a memory cap, :mod:`._pentadiagonal_disk`; :mod:`._blocks`
for a damping of higher powers of the velocity) (the next eigenvalue, the slowest
relaxation, is ``O(mu)`` or the escape rate, far from ``lambda_0``).  ``|lambda_0|`` is
reported as the solution's ``residual``.

The integrals of those functions (the marginal, ``<v^2>``, the mass below an energy)
are in :mod:`._hermite_functions`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ._blocks import on_one_blas_thread
from ._hermite_functions import hermite_integrals, orthonormal_band_masses
from ._solution import KramersSolution

__all__ = ["OrthonormalKramersSolution", "orthonormal_stationary"]


@dataclass(frozen=True, eq=False, repr=False)  # the base class's short repr
class OrthonormalKramersSolution(KramersSolution):
    """:class:`.KramersSolution` with ``P = sum c_n h_n(v/sigma)/sigma`` in the orthonormal
    Hermite functions (``sigma`` is the scale ``s``): the marginal is ``sum m_n c_n``,
    ``<v^2> = sigma^2 int sum q_n c_n dx`` and the velocity band integrals are
    :func:`orthonormal_band_masses`.  The points are those of
    :func:`._bases.cheb_mapped` with :attr:`alpha` (``x = L arcsin(alpha t)/arcsin(alpha)``).
    """

    alpha: float = 0.0
    centres: tuple = ()
    widths: tuple = ()
    weight: float = 0.0
    #: the inverse iteration's last relative change of the coefficients (at most the
    #: solve's ``rtol`` when it converged; larger when it stopped at its ``iterations``)
    iteration_change: float = 0.0
    basis = "orthonormal"

    def _t(self, xs: np.ndarray) -> np.ndarray:
        """The inverse of the map of :func:`._bases.cheb_centred` (or
        :func:`._bases.cheb_mapped` without centres)."""
        L = float(self.x[0])
        xs = np.asarray(xs, float)
        if self.centres:
            c, w = np.asarray(self.centres), np.asarray(self.widths)

            def psi(z):
                q = np.asarray(self.weight, float)
                return z / L + (q * np.arctan((z[..., None] - c) / w)).sum(axis=-1)

            lo, hi = psi(np.array([-L, L]))
            u = -1 + 2 * (psi(xs) - lo) / (hi - lo)
        else:
            u = xs / L
        if self.alpha == 0:
            return u
        return np.sin(math.asin(self.alpha) * u) / self.alpha

    def _integrals(self):
        if "integrals" not in self._cache:
            self._cache["integrals"] = hermite_integrals(self.coef.shape[0])
        return self._cache["integrals"]

    @on_one_blas_thread
    def marginal(self) -> np.ndarray:
        """The density of ``x`` at the points :attr:`x`."""
        return self._integrals()[0] @ self.coef

    @property
    def x2(self) -> float:
        """``<x^2>``."""
        return float(np.sum(self.weights * self.x**2 * self.marginal()))

    @property
    @on_one_blas_thread
    def v2(self) -> float:
        """``<v^2> = sigma^2 int sum_n q_n c_n dx``."""
        return float(self.sigma**2 * np.sum(self.weights * (self._integrals()[1] @ self.coef)))

    def _band(self, n: int, U) -> np.ndarray:
        return orthonormal_band_masses(n, U)


@on_one_blas_thread
def orthonormal_stationary(split, D: float, s: float, half: float, nh: int, nc: int, G,
                           omega0: float, *, alpha: float = 0.95, centres=(), widths=(),
                           weight=0.0, iterations: int = 8, rtol: float = 1e-14,
                           fold: bool | None = None,
                           mixed: bool | None = None) -> OrthonormalKramersSolution:
    """One stationary solve in ``nh`` orthonormal Hermite functions of ``v/s`` times
    ``nc + 1`` Chebyshev points on ``[-half, half]``: inverse iteration on the Galerkin
    operator (every ``c_n(+-half) = 0``) from the Maxwellian ``exp(-G/s^2)`` in ``h_0``,
    until the normalised coefficients change by less than ``rtol`` (at most
    ``iterations`` solves; the last change is the solution's ``iteration_change``, which
    the ladders of :mod:`._stationary_orthonormal` count as a change of the moments, so
    that an iteration that did not converge never ends a ladder).  The residual is the
    eigenvalue estimate ``|lambda_0|``.
    ``fold`` (default: whenever :func:`._parity.reflection_symmetric` holds) solves on the
    points ``x >= 0`` only (:mod:`._parity`: the same density, an eighth of the work);
    ``weight`` is one number or one per centre.  ``mixed`` (default: from
    :data:`._bordered.MIXED_POINTS` points per order on) solves by the single-precision
    factorisation and GMRES of :mod:`._bordered` where the LU is order by order (its
    factors in single precision, on disk beyond
    :data:`._pentadiagonal_disk.FACTOR_MEMORY`), the direct solve when that does not
    converge."""
    from ._bases import cheb_centred, cheb_mapped, clenshaw_curtis
    from ._blocks import BlockTridiagonalLU, TermBlocks, one_blas_thread
    from ._orthonormal import orthonormal_terms
    from ._parity import fold_terms, fold_weights, reflection_symmetric, unfold
    from ._pentadiagonal import pentadiagonal_applies
    from ._bordered import MIXED_POINTS
    from ._pentadiagonal_disk import pentadiagonal_lu

    centres, widths = tuple(map(float, centres)), tuple(map(float, widths))
    if centres:
        xs, Dx = cheb_centred(nc, half, alpha, centres, widths, weight)
    else:
        xs, Dx = cheb_mapped(nc, half, alpha)
    t = np.cos(np.pi * np.arange(nc + 1) / nc)
    w = clenshaw_curtis(nc, 1.0) / (Dx @ t)  # dx/dt = 1/(D_x t), D_t t = 1
    full = xs.size
    terms = orthonormal_terms(split, D, s, xs, Dx, nh)
    if fold is None:
        fold = reflection_symmetric(split, xs)
    if fold:
        terms, wq, m, pins = fold_terms(terms, full), fold_weights(w), full // 2 + 1, (0,)
    else:
        wq, m, pins = w, full, (0, full - 1)
    keep = np.ones(nh * m)
    keep[np.concatenate([[k * m + p for p in pins] for k in range(nh)])] = 0.0
    mass, _ = hermite_integrals(nh)
    Gx = np.asarray(G(xs[:m]), float)
    c = np.zeros(nh * m)
    c[:m] = np.exp(-(Gx - Gx.min()) / s**2)
    c *= keep
    c /= float(np.sum(wq * (mass @ c.reshape(nh, m))))
    lam = last = math.nan
    with one_blas_thread():
        penta = pentadiagonal_applies(terms)
        if mixed is None:
            mixed = m >= MIXED_POINTS
        done = _mixed(terms, m, pins, c, keep, wq, mass, iterations, rtol) \
            if mixed and penta else None
        if done is not None:
            c, lam, last = done
            iterations = 0
        elif penta:
            lu = pentadiagonal_lu(terms, m, pins)
        else:
            lu = BlockTridiagonalLU(TermBlocks(terms, m, None, pins, 0), m)
        for _ in range(iterations):
            new = lu.solve(keep * c)
            norm = float(np.sum(wq * (mass @ new.reshape(nh, m))))
            new /= norm
            lam = 1.0 / norm  # A new = c / norm, both normalised: A c ~ lam c
            last = float(np.max(np.abs(new - c))) / float(np.max(np.abs(new)))
            done = last <= rtol
            c = new
            if done:
                break
    c = unfold(c.reshape(nh, m), full) if fold else c.reshape(nh, m)
    return OrthonormalKramersSolution(xs, w, c, s, G, float(omega0), abs(lam),
                                      alpha=float(alpha), centres=centres, widths=widths,
                                      iteration_change=last,
                                      weight=float(weight) if np.ndim(weight) == 0 else
                                      tuple(map(float, weight)))


def _mixed(terms, m: int, pins, c: np.ndarray, keep: np.ndarray, wq: np.ndarray, mass,
           iterations: int, rtol: float):
    """The inverse iteration of :func:`orthonormal_stationary` by
    :func:`._bordered.bordered_inverse_iteration` on the single-precision order-by-order
    LU (in memory or on disk, :func:`._pentadiagonal_disk.pentadiagonal_lu`):
    ``(c, lambda_0, last change)``, or ``None`` (the direct solve then) when it did not
    converge or a single-precision Schur complement was singular."""
    from ._bordered import bordered_inverse_iteration
    from ._pentadiagonal_disk import pentadiagonal_lu

    nh = c.size // m
    try:
        with np.errstate(over="ignore", invalid="ignore"):  # judged by the finite check
            single = pentadiagonal_lu(terms, m, pins, single=True)
    except np.linalg.LinAlgError:
        return None
    return bordered_inverse_iteration(
        lambda r: single.solve(r, refine=False), single.matvec, c, keep,
        lambda v: float(np.sum(wq * (mass @ v.reshape(nh, m)))), iterations, rtol)
