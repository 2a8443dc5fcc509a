"""Limit cycles of the averaged equations ``da/dt = sum mu**n A_n(a)``.

A limit cycle of the KBM approximation is a positive root ``a*`` of
``A(a) = sum_{n=1}^N mu**n A_n(a)``; it is stable when ``dA/da(a*) < 0``, its
frequency is ``omega* = omega0 + sum mu**n B_n(a*)`` and the non-trivial
Floquet multiplier it predicts is ``exp(T dA/da(a*))`` with ``T = 2 pi/omega*``.

The roots are found numerically here, for given values of ``mu`` and the
parameters; for polynomial ``F`` they are also expanded as exact series in
``mu`` by :mod:`kbm.slowflow.series`.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np
import sympy as sp

from ..errors import ParameterError
from ..output.evaluate import numpy_function
from ..expansion.result import KBMResult
from ..symbols import a, mu

__all__ = ["AveragedCycle", "AveragedRates", "averaged_cycles", "averaged_rates"]


@dataclass(frozen=True)
class AveragedCycle:
    """A limit cycle of the order-``order`` averaged equations.

    Attributes
    ----------
    amplitude
        ``a*``, the predicted first-harmonic amplitude.
    frequency, period
        ``omega* = omega0 + sum mu**n B_n(a*)`` and ``2 pi/omega*``.
    dA_da
        Slope of the amplitude equation at ``a*``.
    stable
        ``dA_da < 0``.
    floquet_multiplier
        The predicted non-trivial Floquet multiplier ``exp(period * dA_da)``.
    """

    order: int
    amplitude: float
    frequency: float
    period: float
    dA_da: float
    stable: bool
    floquet_multiplier: float


def _values(result: KBMResult, values: Mapping[str, object]) -> tuple[float, list[float]]:
    vals = dict(values)
    if "mu" not in vals:
        raise ParameterError("the averaged limit cycle needs a value of mu")
    missing = [p for p in result.params if p not in vals]
    if missing:
        raise ParameterError(f"give values for {', '.join(missing)} (e.g. values="
                             f"{{'{missing[0]}': 1}})")
    extra = set(vals) - set(result.params) - {"mu"}
    if extra:
        raise ParameterError(f"unknown parameter(s) {', '.join(sorted(extra))}; this result has "
                             f"{', '.join(result.params) or 'no parameters'} and mu")
    return float(sp.sympify(vals["mu"])), [float(sp.sympify(vals[p])) for p in result.params]


def averaged_cycles(result: KBMResult, values: Mapping[str, object], *,
                    order: int | None = None, a_max: float = 20.0,
                    n_grid: int = 4000) -> tuple[AveragedCycle, ...]:
    """All limit cycles ``0 < a* <= a_max`` of the averaged amplitude equation.

    Parameters
    ----------
    result
        A KBM derivation.
    values
        ``mu`` and every parameter left symbolic in ``result`` (numbers).
    order
        Use ``A_1..A_order`` (default: all of ``result``).
    a_max, n_grid
        Roots are bracketed by sign changes of ``A(a)/a`` on ``n_grid`` points of
        ``(0, a_max]`` and refined with Brent's method to ``1e-14``; roots
        closer together than the grid spacing can be missed.

    Returns
    -------
    tuple of AveragedCycle
        In increasing amplitude; empty when the averaged equation has no cycle
        (e.g. pure damping).  Roots where the averaged frequency
        ``omega0 + sum mu**n B_n`` is not positive are left out: the truncated
        expansion has broken down there.

    Examples
    --------
    >>> from kbm import derive
    >>> c, = averaged_cycles(derive("vdp", 2), {"mu": 0.1})
    >>> round(c.amplitude, 12), c.stable
    (2.0, True)
    """
    return averaged_rates(result, order=order).cycles(values, a_max=a_max, n_grid=n_grid)


@dataclass(frozen=True)
class AveragedRates:
    """The averaged equations of a derivation as numerical functions of ``(a, mu, *params)``.

    Lambdifying is the costly step of :func:`averaged_cycles`; an
    ``AveragedRates`` is built once (:func:`averaged_rates`) and evaluated for
    many parameter values (as the limit-cycle guesses of a sweep do).

    Attributes
    ----------
    order, params
        The truncation order and the names of the parameters after ``mu``.
    rate, slope, frequency
        ``A(a) = sum_{n<=order} mu**n A_n(a)``, ``dA/da`` and
        ``omega0 + sum mu**n B_n(a)`` (vectorised in ``a``).
    """

    order: int
    params: tuple[str, ...]
    rate: Callable
    slope: Callable
    frequency: Callable
    result: KBMResult

    def cycles(self, values: Mapping[str, object], *, a_max: float = 20.0,
               n_grid: int = 4000) -> tuple[AveragedCycle, ...]:
        """The cycles ``0 < a* <= a_max`` at ``values``; see :func:`averaged_cycles`."""
        from .roots import amplitude_roots

        m, pars = _values(self.result, values)
        df, phase = self.slope, self.frequency
        roots = amplitude_roots(self.rate, m, pars, a_max=a_max, n_grid=n_grid)
        cycles = []
        for root in roots:
            slope = float(df(root, m, *pars))
            omega = float(phase(root, m, *pars))
            if not omega > 0:
                # the truncated phase equation gives no rotation here: the expansion has
                # broken down at this amplitude, so this root is not a cycle it predicts
                continue
            T = 2 * np.pi / omega
            cycles.append(AveragedCycle(order=self.order, amplitude=float(root),
                                        frequency=omega, period=T, dA_da=slope,
                                        stable=slope < 0,
                                        floquet_multiplier=float(np.exp(T * slope))))
        return tuple(cycles)


def averaged_rates(result: KBMResult, *, order: int | None = None) -> AveragedRates:
    """Lambdify the averaged equations of ``result`` up to ``order`` (default: all).

    Lambdified on the first call for an order and kept on ``result`` (an attribute outside
    its fields, as :meth:`~kbm.expansion.result.KBMResult.functions`; no process-wide cache), so
    the many :func:`averaged_cycles` of one derivation over a grid of parameters lambdify once."""
    N = result.resolve_order(order)
    return result._computed_once(("averaged_rates", N), lambda: _averaged_rates(result, N))


def _averaged_rates(result: KBMResult, N: int) -> AveragedRates:
    """:func:`averaged_rates` at the resolved order ``N``, lambdified afresh."""
    rate = sp.Add(*[mu**n * result.A[n] for n in range(1, N + 1)])
    args = [a, mu, *[sp.Symbol(p) for p in result.params]]
    return AveragedRates(
        order=N, params=tuple(result.params), result=result,
        rate=numpy_function(rate, args), slope=numpy_function(sp.diff(rate, a), args),
        frequency=numpy_function(sp.Add(*[mu**n * result.B[n] for n in range(0, N + 1)]),
                                 args))
