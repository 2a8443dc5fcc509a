"""Backbone curves of conservative coupled oscillators in internal resonance: averaged and true.

Without damping, the periodic orbits of ``x_i'' + omega_i**2 x_i = mu F_i(x)`` in an
internal resonance ``omega_1 : omega_2 = 1 : q`` come in families (nonlinear normal modes).
Averaged, they are the fixed points of the slow flow with ``sin(gamma) = 0`` (reversibility
keeps only sines of ``gamma`` in the rates ``A``), ``gamma = 0`` or ``pi``, where
``dgamma/dt = 0`` fixes ``a_2`` for each ``a_1``; the frequency of ``x_1`` is
``1 + sum mu**n B_{1,n}``.

True, they are the reversible periodic orbits that start at rest, ``x(0) = (X, x_2(0))``,
``x'(0) = 0``, and come to rest again at ``T/2`` (``x'(T/2) = 0``): Newton on
``(x_2(0), T)`` with the monodromy of :mod:`numerics.flow.coupled_flow`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import sympy as sp
from scipy.optimize import brentq

from kbm.expansion.coupled_result import CoupledKBMResult
from kbm.model.coupled import amplitudes
from numerics.shooting.acceptance import orbit_scale, shoot_newton
from numerics.errors import ConvergenceError
from numerics.flow.coupled_flow import coupled_flow

__all__ = ["BackbonePoint", "averaged_backbone_point", "true_backbone_point"]


@dataclass(frozen=True)
class BackbonePoint:
    """A point of a backbone: the first-harmonic amplitudes of ``x_1`` (at its frequency)
    and ``x_2`` (at ``q`` times it), the frequency of ``x_1``, and ``gamma``."""

    a1: float
    a2: float
    frequency: float
    gamma: float


def averaged_backbone_point(result: CoupledKBMResult, values: Mapping[str, float],
                            a1: float, gamma: float, bracket: tuple[float, float]
                            ) -> BackbonePoint:
    """The averaged backbone at ``a_1`` on the branch ``gamma`` (0 or pi): ``a_2`` is the
    root of ``dgamma/dt = 0`` in ``bracket``.

    Raises
    ------
    numerics.errors.ConvergenceError
        If ``dgamma/dt`` does not change sign over ``bracket``.
    """
    sub = {sp.Symbol(k): v for k, v in values.items()}
    g = result.gammas[0][0]
    A1, A2 = amplitudes(2)
    rate = sum(sp.Symbol("mu")**n * result.gamma_rate(0, n) for n in range(1, result.order + 1))
    rate = sp.lambdify([A2], rate.subs(sub).subs({g: gamma, A1: a1}), "math")
    lo, hi = bracket
    if rate(lo) * rate(hi) > 0:
        raise ConvergenceError(f"dgamma/dt does not change sign for a2 in [{lo:g}, {hi:g}] at "
                               f"a1 = {a1:g}, gamma = {gamma:g}")
    a2 = brentq(rate, lo, hi, xtol=1e-15, rtol=1e-15)
    B1 = sum(sp.Symbol("mu")**n * result.B[0][n] for n in range(result.order + 1))
    w = float(B1.subs(sub).subs({g: gamma, A1: a1, A2: a2}))
    return BackbonePoint(a1, a2, w, gamma)


def true_backbone_point(model, values: Mapping[str, object], x1_max: float, x2_guess: float,
                        period_guess: float, q: int, max_iter: int = 30) -> BackbonePoint:
    """The reversible periodic orbit through ``x_1 = x1_max`` at rest, its first harmonics.

    Raises
    ------
    numerics.errors.ConvergenceError
        If Newton on ``(x_2(0), T)`` does not converge.
    """
    fl = coupled_flow(model, values)

    def evaluate(z):
        yh, Phi, _ = fl.monodromy(np.array([x1_max, z[0], 0.0, 0.0]), z[1] / 2)
        return yh[2:4], np.column_stack([Phi[2:4, 1], fl.rhs(yh)[2:4] / 2]), None

    try:  # the acceptance standard of every shooting, the correction below 1e-9 S
        z, _, _, _ = shoot_newton(evaluate, [float(x2_guess), float(period_guess)],
                                  rtol=1e-11, scale=lambda z: orbit_scale([x1_max, z[0]]),
                                  max_iter=max_iter, accuracy=1e-9,
                                  what=f"reversible through x1 = {x1_max:g}")
    except ConvergenceError as exc:
        raise ConvergenceError(f"no reversible orbit through x1 = {x1_max:g}: {exc}") from None
    x2, T = float(z[0]), float(z[1])
    n_s = 1024
    ys = fl.states(np.array([x1_max, x2, 0.0, 0.0]), T, n_s)[:-1]
    c = np.fft.rfft(ys[:, :2], axis=0) / n_s * 2
    a1, a2 = abs(c[1, 0]), abs(c[q, 1])
    gamma = float(np.angle(c[q, 1] * np.conj(c[1, 0]) ** q))
    return BackbonePoint(float(a1), float(a2), 2 * math.pi / T, gamma)
