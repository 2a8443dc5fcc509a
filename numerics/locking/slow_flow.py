"""The averaged slow flow of a coupled system with one internal resonance, as numbers: its
rates ``f(y, s, mu)`` in the amplitudes and the phase ``y = (a_1..a_N, gamma)`` and one
followed parameter ``s``, their Jacobian in ``y``, and Newton on its fixed points (the
locked states of :mod:`numerics.locking.mutual`).

The flow comes from the exact engine (:func:`kbm.expansion.coupled.derive_coupled`), or, for a
right-hand side it does not take (``sin``, ``tanh`` coupling), from the numeric backend
(:func:`kbm.backend.coupled.numeric_average`).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import sympy as sp

from kbm.model.coupled import CoupledOscillators, amplitudes
from kbm.expansion.coupled import derive_coupled
from kbm.backend.coupled import numeric_average
from kbm.errors import ParameterError, ResolutionError, UnsupportedTermError
from kbm.output.evaluate import numpy_array_function
from numerics._memo import memo

__all__: list[str] = []


@memo(maxsize=16)
def _slow_flow(model: CoupledOscillators, order: int, fixed: tuple, parameter: str):
    """Lambdified slow flow ``f(y, sigma, mu)`` and its Jacobian in ``y`` (memoised: time).

    For a right-hand side that the exact engine does not take (``sin``, ``tanh`` coupling),
    the flow comes from the numeric backend (:func:`kbm.backend.coupled.numeric_average`: the FFT
    average at order 1, the recursion on jets above, :mod:`kbm.backend.jets`), its
    Jacobian by central differences."""
    try:
        res = derive_coupled(model, order, dict(fixed))
    except UnsupportedTermError:
        from kbm.backend.jets import MAX_ORDER_JETS

        if order > MAX_ORDER_JETS:
            raise ParameterError(f"the averaged flow of {model.name!r} (F not polynomial) "
                                 f"comes from the numeric backend, orders 1 to "
                                 f"{MAX_ORDER_JETS}; ask --order {MAX_ORDER_JETS} at most, not "
                                 f"{order}") from None
        return _numeric_flow(model, dict(fixed), parameter, order)
    rates = res.slow_flow()
    state = [*amplitudes(model.dof), *[g for g, _ in res.gammas]]
    mu, s = sp.Symbol("mu"), sp.Symbol(parameter)
    J = sp.Matrix(rates).jacobian(state)
    # the one lambdify path of KBM expressions: besselj (the potential's sin k x) to scipy
    f = numpy_array_function(list(rates), [state, s, mu])
    jac = numpy_array_function(J.tolist(), [state, s, mu])
    return f, jac, len(state)


def _numeric_flow(model: CoupledOscillators, fixed: dict, parameter: str, order: int = 1):
    n = model.dof
    base = numeric_average(model, {**{k: float(v) for k, v in fixed.items()}, parameter: 0.0})
    m = n + len(base.gammas)

    last: dict = {}

    def both(y, s, mu):
        """The flow and its Jacobian from one expansion with the jets' derivatives
        (kbm.backend.jets; the last point kept: Newton asks for both at the same point)."""
        key = (tuple(y), float(s), float(mu))
        if key not in last:
            last.clear()
            try:
                last[key] = base.at(**{parameter: float(s)}).slow_flow_jacobian(
                    mu, y[:n], y[n:], order)
            except ResolutionError:  # Newton wandered to amplitudes F cannot be averaged at
                last[key] = (np.full(m, np.nan), np.full((m, m), np.nan))
        return last[key]

    def f(y, s, mu):
        y = np.asarray(y, dtype=float)
        if np.any(y[:n] <= 0):
            return np.full(m, np.nan)
        if order > 1:
            return both(y, s, mu)[0]
        return base.at(**{parameter: float(s)}).slow_flow(mu, y[:n], y[n:])

    def jac(y, s, mu):
        y = np.asarray(y, dtype=float)
        if order > 1:  # the jets' derivatives, no differences
            if np.any(y[:n] <= 0):
                return np.full((m, m), np.nan)
            return both(y, s, mu)[1]
        J = np.empty((m, m))
        for k in range(m):
            h = 1e-6 * max(1.0, abs(y[k]))
            yp, ym = y.copy(), y.copy()
            yp[k] += h
            ym[k] -= h
            J[:, k] = (f(yp, s, mu) - f(ym, s, mu)) / (2 * h)
        return J

    return f, jac, m


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
    """The fixed parameters (all but ``parameter`` and ``mu``) as exact values, the key of
    the memoised flow."""
    fixed = tuple(sorted((k, sp.nsimplify(v, rational=True)) for k, v in values.items()
                         if k not in (parameter, "mu")))
    return fixed
