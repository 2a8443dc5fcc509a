"""The order-``N`` prediction against the true periodic response, as ``mu`` shrinks.

At a fixed detuning the KBM amplitude ``a`` of order ``N`` (a fixed point of the slow flow
truncated at ``mu**N``) differs from the true response's amplitude at the frequency
``(q/p) nu`` by ``O(mu**N)``; the fold (jump) detunings likewise.  :func:`amplitude_study`
and :func:`fold_study` measure both for a list of ``mu`` and fit the slopes of
``log(error)`` against ``log(mu)`` (least squares).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from kbm.errors import ParameterError
from kbm.forced import ForcedKBMResult, forced_expansion, get_forced_model
from kbm.forced.steady import fixed_points, response_curve

from numerics.errors import NoCycleError
from numerics.forced.response import guess_from, numeric_response
from numerics.forced.shooting import periodic_response
from numerics.forced.system import ForcedSystem

__all__ = ["ConvergenceTable", "amplitude_study", "fold_study", "slope"]


def slope(mus: Sequence[float], errors: Sequence[float]) -> float:
    """The least-squares slope of ``log(error)`` against ``log(mu)``."""
    lm, le = np.log(np.asarray(mus, float)), np.log(np.asarray(errors, float))
    return float(np.polyfit(lm, le, 1)[0])


@dataclass(frozen=True)
class ConvergenceTable:
    """Errors ``errors[N][i]`` of order ``N`` at ``mus[i]`` and the fitted slopes."""

    quantity: str
    mus: tuple[float, ...]
    true: tuple[float, ...]
    errors: Mapping[int, tuple[float, ...]]

    @property
    def slopes(self) -> dict[int, float]:
        """The fitted slope per order (the expected slope of order ``N`` is ``N``)."""
        return {n: slope(self.mus, e) for n, e in self.errors.items()}

    def to_json(self) -> dict:
        return {"quantity": self.quantity, "mu": list(self.mus), "true": list(self.true),
                "errors": {str(n): list(e) for n, e in self.errors.items()},
                "slopes": {str(n): s for n, s in self.slopes.items()}}


def _result(model, orders, result, values, amplitudes) -> ForcedKBMResult:
    """The expansion to the highest order (exact, or numeric on the amplitude window)."""
    if result is not None:
        return result
    return forced_expansion(model, max(orders), dict(values), a_range=amplitudes)


def _model(model, res):
    """The model to integrate: the one given (a numeric expansion holds it with its
    parameters substituted, which the system would not recognise)."""
    if isinstance(model, str):
        return get_forced_model(model)
    return model if model is not None else res.model


def amplitude_study(model, values: Mapping[str, object], sigma: float, mus: Sequence[float],
                    orders: Sequence[int] = (1, 2), *, amplitudes=(1e-3, 5.0),
                    result: ForcedKBMResult | None = None) -> ConvergenceTable:
    """Errors of the order-``N`` amplitude at detuning ``sigma`` for each ``mu``.

    The response followed is the largest-amplitude fixed point of the highest order's slow
    flow, corrected by shooting; each order's prediction is its own fixed point nearest to
    that response.

    Raises
    ------
    numerics.errors.NoCycleError
        If an order has no fixed point in the amplitude window.
    """
    res = _result(model, orders, result, values, amplitudes)
    true, errs = [], {n: [] for n in orders}
    for m in mus:
        vals = {**values, "mu": m}
        system = ForcedSystem(_model(model, res), vals, resonance=res.resonance)
        fps = fixed_points(res.slow_flow(vals, order=max(orders)), sigma, amplitudes)
        if not fps:
            raise NoCycleError(f"no fixed point of the order-{max(orders)} slow flow at sigma = "
                               f"{sigma} for mu = {m}")
        fp = fps[-1]
        orb = periodic_response(system, sigma, guess_from(system, fp.amplitude, fp.phase, sigma))
        true.append(orb.amplitude)
        for n in orders:
            cand = fixed_points(res.slow_flow(vals, order=n), sigma, amplitudes)
            if not cand:
                raise NoCycleError(f"no fixed point of the order-{n} slow flow at sigma = "
                                   f"{sigma} for mu = {m}")
            errs[n].append(min(abs(c.amplitude - orb.amplitude) for c in cand))
    return ConvergenceTable(f"amplitude at sigma = {sigma:g}", tuple(mus), tuple(true),
                            {n: tuple(e) for n, e in errs.items()})


def fold_study(model, values: Mapping[str, object], sigmas: tuple[float, float],
               mus: Sequence[float], orders: Sequence[int] = (1, 2), *, which: int = 0,
               amplitudes=(1e-3, 5.0), result: ForcedKBMResult | None = None) -> ConvergenceTable:
    """Errors of the fold (jump) detuning number ``which`` (sorted by ``sigma``) for each ``mu``.

    Raises
    ------
    kbm.errors.ParameterError
        If the true or a predicted curve has fewer folds in ``sigmas``.
    """
    res = _result(model, orders, result, values, amplitudes)
    true, errs = [], {n: [] for n in orders}
    for m in mus:
        vals = {**values, "mu": m}
        system = ForcedSystem(_model(model, res), vals, resonance=res.resonance)
        nr = numeric_response(system, res.slow_flow(vals, order=max(orders)), sigmas,
                              amplitudes, n_points=200, seeds_at=2)
        if len(nr.folds) <= which:
            raise ParameterError(f"the true response has {len(nr.folds)} fold(s) in sigma "
                                 f"{sigmas} at mu = {m}; widen the range")
        s_true = nr.folds[which].sigma
        true.append(s_true)
        for n in orders:
            rc = response_curve(res.slow_flow(vals, order=n), sigmas, amplitudes, seeds_at=2)
            if len(rc.folds) <= which:
                raise ParameterError(f"the order-{n} response has {len(rc.folds)} fold(s) at "
                                     f"mu = {m}")
            errs[n].append(abs(rc.folds[which].sigma - s_true))
    return ConvergenceTable(f"fold {which} detuning", tuple(mus), tuple(true),
                            {n: tuple(e) for n, e in errs.items()})
