"""Frequency locking of self-excited oscillators: the edges of the locking region, averaged
against true.

A detuning ``sigma`` (frequency ``1 + mu sigma`` of the second oscillator) is followed
from 0 in both directions:

- **averaged**: the locked state is a fixed point of the slow flow ``(a, gamma)`` of
  :func:`kbm.coupled.derive_coupled` at order ``n``; it is continued in ``sigma`` and its
  fold (``f = 0``, ``det J = 0``) is solved by Newton on the augmented system;
- **true**: the locked state is a periodic orbit of the full ``2N``-dimensional system
  (:func:`numerics.coupled.coupled_cycle`, continued from the previous orbit); the edge is
  where it ceases to exist, bracketed by bisection to ``tol``, with the non-trivial
  multiplier nearest 1 going to 1 there (a saddle-node of cycles) as the check.

The amplitude death of the oscillators (the origin made stable by the coupling) is read
from the linearisation of the full system at the origin.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import sympy as sp

from kbm.coupled import CoupledOscillators, amplitudes, derive_coupled
from kbm.errors import ParameterError
from numerics._memo import memo
from numerics.errors import ConvergenceError, NoCycleError
from .cycle import coupled_cycle
from .flow import bind_coupled

__all__ = ["LockingEdge", "averaged_edges", "true_edges", "amplitude_death"]


@dataclass(frozen=True)
class LockingEdge:
    """One edge of the locking region at fixed other parameters.

    ``sigma`` is the edge, ``error`` its uncertainty (the bisection bracket for the true
    edge, Newton's last step for the averaged one), ``side`` +1 or -1, ``state`` the
    locked state (slow-flow fixed point or cycle state) just inside.
    """

    sigma: float
    error: float
    side: int
    state: tuple


@memo(maxsize=16)
def _slow_flow(model: CoupledOscillators, order: int, fixed: tuple, parameter: str):
    """Lambdified slow flow ``f(y, sigma, mu)`` and its Jacobian in ``y`` (memoised: time)."""
    res = derive_coupled(model, order, dict(fixed))
    rates = res.slow_flow()
    state = [*amplitudes(model.dof), *[g for g, _ in res.gammas]]
    mu, s = sp.Symbol("mu"), sp.Symbol(parameter)
    J = sp.Matrix(rates).jacobian(state)
    f = sp.lambdify([state, s, mu], list(rates), "numpy")
    jac = sp.lambdify([state, s, mu], J, "numpy")
    return f, jac, len(state)


def _newton(f, jac, y, s, mu, tol=1e-13, it=40):
    for _ in range(it):
        r = np.asarray(f(y, s, mu), dtype=float)
        J = np.asarray(jac(y, s, mu), dtype=float)
        try:
            dy = np.linalg.solve(J, -r)
        except np.linalg.LinAlgError:
            return None
        y = y + dy
        if not np.all(np.isfinite(y)):
            return None
        if np.max(np.abs(dy)) < tol:
            return y
    return None


def _split(model: CoupledOscillators, values: Mapping[str, float], parameter: str):
    fixed = tuple(sorted((k, sp.nsimplify(v, rational=True)) for k, v in values.items()
                         if k not in (parameter, "mu")))
    return fixed


def averaged_edges(model: CoupledOscillators | str, params: Mapping[str, object], order: int,
                   parameter: str = "sigma", limit: float = 10.0, start=None
                   ) -> list[LockingEdge]:
    """The edges ``sigma_-`` and ``sigma_+`` of locking from the order-``order`` slow flow.

    Parameters
    ----------
    model
        A coupled system with one internal resonance (its phase ``gamma1``).
    params
        Values of every parameter and ``mu`` (``parameter`` is ignored: it is followed).
    order
        The order of the averaged flow.
    parameter
        The detuning's name.
    limit
        ``|sigma|`` up to which an edge is looked for.
    start
        The locked state ``(a_1..a_N, gamma)`` at ``sigma = 0`` (default: all ``a_i = 2``,
        ``gamma = 0``, the in-phase van der Pol cycle).

    Raises
    ------
    numerics.errors.NoCycleError
        If there is no locked state at ``sigma = 0`` to start from.
    """
    model, values = bind_coupled(model, {**dict(params), parameter: 0})
    mu = values["mu"]
    f, jac, m = _slow_flow(model, order, _split(model, values, parameter), parameter)
    y0 = np.array(start if start is not None else [2.0] * model.dof + [0.0] * (m - model.dof),
                  dtype=float)
    y = _newton(f, jac, y0, 0.0, mu)
    if y is None:
        raise NoCycleError(f"the order-{order} slow flow of {model.name} has no locked state "
                           f"near {list(y0)} at {parameter} = 0")
    return [_averaged_edge(f, jac, y, side, mu, limit) for side in (-1, 1)]


def _averaged_edge(f, jac, y, side, mu, limit) -> LockingEdge:
    def locked(s, y):
        trial = _newton(f, jac, y, s, mu)
        return trial if trial is not None and np.all(trial[:-1] > 0) else None

    s, step = 0.0, 0.02
    last = (s, y)
    while True:  # march out until the locked state is lost ...
        if abs(last[0]) >= limit:
            return LockingEdge(math.copysign(math.inf, side), 0.0, side, tuple(last[1]))
        trial = locked(last[0] + side * step, last[1])
        if trial is None:
            break
        last = (last[0] + side * step, trial)
        step = min(step * 1.5, 0.1)
    lo, hi = last[0], last[0] + side * step
    while abs(hi - lo) > 1e-6:  # ... bracket the fold ...
        mid = 0.5 * (lo + hi)
        trial = locked(mid, last[1])
        if trial is None:
            hi = mid
        else:
            lo, last = mid, (mid, trial)
    step = abs(hi - lo)
    # Newton on the augmented system (y, sigma): f = 0, det J = 0
    z = np.concatenate([last[1], [last[0]]])
    dz = np.inf
    for _ in range(30):
        def g(zz):
            yy, ss = zz[:-1], zz[-1]
            return np.concatenate([np.asarray(f(yy, ss, mu), dtype=float),
                                   [np.linalg.det(np.asarray(jac(yy, ss, mu), dtype=float))]])
        g0 = g(z)
        h = 1e-7 * np.maximum(1.0, np.abs(z))
        G = np.empty((len(z), len(z)))
        for k in range(len(z)):
            e = np.zeros(len(z))
            e[k] = h[k]
            G[:, k] = (g(z + e) - g(z - e)) / (2 * h[k])
        try:
            dzv = np.linalg.solve(G, -g0)
        except np.linalg.LinAlgError:
            break
        z = z + dzv
        dz = float(abs(dzv[-1]))
        if dz < 1e-12:
            break
    if not (np.isfinite(z).all() and abs(z[-1] - last[0]) < 1e-2):
        return LockingEdge(last[0], abs(step), side, tuple(last[1]))
    return LockingEdge(float(z[-1]), max(dz, 1e-12), side, tuple(z[:-1]))


def true_edges(model: CoupledOscillators | str, params: Mapping[str, object],
               parameter: str = "sigma", limit: float = 10.0, tol: float = 1e-5,
               guess: Mapping[int, float] | None = None) -> list[LockingEdge]:
    """The edges of locking of the full system: where the locked cycle ceases to exist.

    ``guess`` maps a side (-1, +1) to an estimate of its edge (e.g. the averaged one); the
    continuation then takes large steps up to 90 % of it.

    Raises
    ------
    numerics.errors.NoCycleError, numerics.errors.ConvergenceError
        If there is no locked cycle at ``sigma = 0``.
    """
    p0 = {**dict(params), parameter: 0}
    base = coupled_cycle(model, p0)
    return [_true_edge(model, params, parameter, base, side, limit, tol,
                       (guess or {}).get(side)) for side in (-1, 1)]


def _shoot(model, params, parameter, s, cyc):
    try:
        return coupled_cycle(model, {**dict(params), parameter: s}, start=cyc.state,
                             transient=0, period=cyc.period, max_iter=12)
    except (ConvergenceError, NoCycleError):
        return None


def _true_edge(model, params, parameter, base, side, limit, tol, guess) -> LockingEdge:
    s, cyc = 0.0, base
    step = 0.02 if guess is None else max(0.02, 0.3 * abs(guess))
    while abs(s) < limit:
        nxt = _shoot(model, params, parameter, s + side * step, cyc)
        if nxt is None or not nxt.stable:
            break
        s, cyc = s + side * step, nxt
    else:
        return LockingEdge(math.copysign(math.inf, side), 0.0, side, tuple(cyc.state))
    lo, hi = s, s + side * step
    while abs(hi - lo) > tol:
        mid = 0.5 * (lo + hi)
        nxt = _shoot(model, params, parameter, mid, cyc)
        if nxt is not None and nxt.stable:
            lo, cyc = mid, nxt
        else:
            hi = mid
    return LockingEdge(0.5 * (lo + hi), 0.5 * abs(hi - lo), side, tuple(cyc.state))


def amplitude_death(model: CoupledOscillators | str, params: Mapping[str, object]) -> dict:
    """The origin's stability from the full system's linearisation (exact eigenvalues).

    Returns ``{"dead": bool, "eigenvalues": [[re, im], ...]}``: ``dead`` when every
    eigenvalue has a negative real part (the oscillations are quenched by the coupling).
    """
    model, values = bind_coupled(model, params)
    state = list(model.state)
    n = model.dof
    f = [*state[n:], *model.accelerations()]
    sub = {sp.Symbol(k): v for k, v in values.items()}
    J = sp.Matrix(f).jacobian(state).subs({s: 0 for s in state}).subs(sub)
    ev = np.linalg.eigvals(np.array(J.evalf(), dtype=float))
    ev = ev[np.lexsort((ev.imag, -ev.real))]
    return {"dead": bool(np.all(ev.real < 0)),
            "eigenvalues": [[float(z.real), float(z.imag)] for z in ev]}


def check_lockable(model: CoupledOscillators) -> None:
    """Raise :class:`~kbm.errors.ParameterError` unless the model has exactly one declared
    internal resonance (the phase whose locking is followed)."""
    if len(model.internal) != 1:
        raise ParameterError(f"{model.name!r} declares {len(model.internal)} internal "
                             "resonances; the locking region is computed for one phase "
                             "combination (a model with one declared resonance, e.g. "
                             "coupled-vdp)")
