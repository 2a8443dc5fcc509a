"""Saddle connections by shooting the invariant manifolds, not the cycle.

A branch of cycles that ends at a homoclinic (or, for an odd model, heteroclinic) loop
ends where the unstable manifold of one saddle meets the stable manifold of the next
(Kuznetsov, *Elements of Applied Bifurcation Theory*, sec. 6.2).  For a one-degree-of-
freedom model at the parameter value ``p``:

- the saddles are refined by Newton on ``f(x, 0) = 0`` from the guesses;
- the unstable manifold of the first is followed forward from ``x_s + eps e_u`` (the
  branch that leaves on the given side), the stable manifold of the second backward from
  ``x_t + eps e_s`` (the branch that arrives from the given side), each to where it first
  turns (``x' = 0``; DOP853 with the crossing located by Newton on the last step, rtol
  1e-12: compiled, or scipy's with event location);
- the turning points differ by ``d(p)``; the connection is the root of ``d``
  (Brent), independent of the continuation and of the period law of
  :mod:`numerics.cycles.homoclinic`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from kbm.slowflow.roots import brentq

from numerics.errors import ConvergenceError
from numerics.flow import compile_model, template_flow
from numerics.flow.line_card import compiled_line

__all__ = ["SaddleConnection", "saddle_connection", "connection_gap"]

#: distance from the saddle along its eigenvector where a manifold is started
EPS = 1e-7


@dataclass(frozen=True)
class SaddleConnection:
    """The parameter of a saddle connection and its bracket.

    ``parameter`` is the root of ``d(p)``; ``error`` half the final bracket plus the effect
    of starting the manifolds ``EPS`` away from the saddles (``|d'|^-1 EPS^2``-sized);
    ``saddles`` the connected saddles at the root.
    """

    parameter: float
    error: float
    saddles: tuple[float, float]
    evaluations: int


def _field(model, params: Mapping[str, object], cm=None):
    """``acc(x, v)``, ``d acc/dx`` and ``d acc/dv`` of the autonomous model at ``params``
    (the compiled model's functions: lambdified once per model; ``cm`` the compiled model
    at ``params`` when the caller has it)."""
    if cm is None:
        cm = compile_model(model, params)

    def acc(x, v):
        return cm.acc(0.0, x, v)
    acc.compiled = cm

    f_jac, pv = cm.template.f_jac, cm.pvec  # the rows of cm.jac, without the array

    def fx(x, v):
        return float(f_jac(0.0, x, v, *pv)[1][0])

    def fv(x, v):
        return float(f_jac(0.0, x, v, *pv)[1][1])
    return acc, fx, fv


def _saddle(acc, fx, fv, guess: float) -> tuple[float, float, float]:
    """``(x_s, lambda_u, lambda_s)`` from Newton on ``f(x, 0) = 0``."""
    xs = float(guess)
    for _ in range(50):
        step = acc(xs, 0.0) / fx(xs, 0.0)
        xs -= step
        if abs(step) < 1e-15 * max(1.0, abs(xs)):
            break
    a, b = fx(xs, 0.0), fv(xs, 0.0)
    disc = b * b + 4 * a
    if a <= 0 or disc <= 0:
        raise ConvergenceError(f"x = {xs:.10g} is not a saddle (f_x = {a:.4g})")
    r = math.sqrt(disc)
    return xs, (b + r) / 2, (b - r) / 2


def _to_turn(acc, y0, direction: float, t_max: float) -> float:
    """``x`` where the orbit from ``y0`` (forward, or backward for ``direction = -1``) first
    turns (``x' = 0``): the compiled DOP853 (:mod:`numerics.flow.jit`) where available,
    else scipy's, at the same tolerances."""
    cm = acc.compiled
    fl = template_flow(cm.template)
    if fl is not None:
        x, _, _, status = fl.to_turn(y0, direction, t_max, cm.pvec, 1e-12, 1e-13)
        if status:
            raise ConvergenceError(f"the manifold from x = {y0[0]:.6g} did not turn within "
                                   f"t = {t_max:g}")
        return x

    from scipy.integrate import solve_ivp  # only without the compiled flow (issue 39)

    def rhs(t, y):
        return [direction * y[1], direction * acc(y[0], y[1])]

    def turn(t, y):
        return y[1]
    turn.terminal = True
    sol = solve_ivp(rhs, (0.0, t_max), y0, method="DOP853", rtol=1e-12, atol=1e-13,
                    events=turn)
    if not sol.t_events[0].size:
        raise ConvergenceError(f"the manifold from x = {y0[0]:.6g} did not turn within "
                               f"t = {t_max:g}")
    return float(sol.y_events[0][0][0])


def connection_gap(model, params: Mapping[str, object], x_from: float, x_to: float,
                   leave: int, arrive: int, t_max: float = 200.0, *, compiled=None
                   ) -> tuple[float, float, float]:
    """``(d, x_s, x_t)``: where the unstable manifold of the saddle near ``x_from`` (the
    branch leaving towards ``leave`` = -1, left, or +1, right) first turns, minus where the
    stable manifold of the saddle near ``x_to`` (the branch arriving from ``arrive`` = -1,
    the left, or +1, the right), followed backward, first turns.  ``compiled``: the
    compiled model at ``params`` (:class:`numerics.flow.CompiledLine` along a parameter),
    else compiled here."""
    acc, fx, fv = _field(model, params, compiled)
    xs, lu, _ = _saddle(acc, fx, fv, x_from)
    xt, _, ls = _saddle(acc, fx, fv, x_to)
    yu = [xs + leave * EPS, leave * EPS * lu]      # eigenvector (1, lambda_u)
    ys = [xt + arrive * EPS, arrive * EPS * ls]    # eigenvector (1, lambda_s)
    return _to_turn(acc, yu, 1.0, t_max) - _to_turn(acc, ys, -1.0, t_max), xs, xt


def saddle_connection(model, params: Mapping[str, object], parameter: str,
                      bracket: tuple[float, float], x_from: float, x_to: float,
                      leave: int, arrive: int, xtol: float = 1e-11) -> SaddleConnection:
    """The value of ``parameter`` in ``bracket`` where the unstable manifold of the saddle near
    ``x_from`` (leaving towards ``leave``) meets the stable manifold of the saddle near
    ``x_to`` (arriving from ``arrive``), compared where each first turns (:func:`connection_gap`).

    Raises
    ------
    numerics.errors.ConvergenceError
        If ``d`` has the same sign at both ends of ``bracket`` (the values are in the
        message), or a manifold does not reach the section.
    """
    count = [0]
    line = compiled_line(model, params, parameter, bracket[0])  # bound once along parameter

    def d(p):
        count[0] += 1
        return connection_gap(model, {**dict(params), parameter: p}, x_from, x_to, leave,
                              arrive, compiled=line(p))[0]

    lo, hi = bracket
    dlo, dhi = d(lo), d(hi)
    if dlo * dhi > 0:
        raise ConvergenceError(f"no saddle connection in {parameter} = [{lo:g}, {hi:g}]: the "
                               f"manifolds' velocity gap is {dlo:.3g} and {dhi:.3g} at the ends")
    # scipy.optimize.brentq's steps and floats (kbm.slowflow.roots), without importing scipy
    root = brentq(d, lo, hi, xtol=xtol, rtol=4 * float(np.finfo(float).eps))
    slope = abs(dhi - dlo) / (hi - lo)
    _, xs, xt = connection_gap(model, {**dict(params), parameter: root}, x_from, x_to, leave,
                               arrive, compiled=line(root))
    return SaddleConnection(float(root), float(xtol + EPS**2 / max(slope, 1e-300) * 10),
                            (xs, xt), count[0])
