"""The order-``N`` prediction against the true periodic response, as ``mu`` shrinks.

At a fixed detuning the KBM amplitude ``a`` of order ``N`` (a fixed point of the slow flow
truncated at ``mu**N``) differs from the true response's amplitude at the frequency
``(q/p) nu`` by ``O(mu**N)``; the fold (jump) detunings likewise.  :func:`amplitude_study`
and :func:`fold_study` measure both for a list of ``mu`` and fit the slopes of
``log(error)`` against ``log(mu)`` (least squares).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from kbm.errors import ParameterError
from kbm.expansion.forced_result import ForcedKBMResult
from kbm.model.forced import ForcedOscillator, Resonance
from kbm.backend.forced import forced_expansion
from kbm.model.forced_builtins import get_forced_model
from kbm.slowflow.steady import fixed_points, response_curve
from kbm.output.strict_json import jsonable

from numerics.errors import NoCycleError, NumericsError
from numerics.shooting.forced_branch import guess_from, numeric_response
from numerics.shooting.forced_orbit import periodic_response
from numerics.flow.forced_system import ForcedSystem

__all__ = ["ConvergenceTable", "amplitude_study", "check_mus", "fold_study", "slope"]


def slope(mus: Sequence[float], errors: Sequence[float]) -> float:
    """The least-squares slope of ``log(error)`` against ``log(mu)``.

    Errors that are zero or not finite are left out of the fit (a zero error has no
    logarithm); with fewer than two left the slope is ``nan``.
    """
    m, e = np.asarray(mus, float), np.abs(np.asarray(errors, float))
    ok = np.isfinite(e) & (e > 0)
    if ok.sum() < 2:
        return float("nan")
    return float(np.polyfit(np.log(m[ok]), np.log(e[ok]), 1)[0])


def check_mus(mus: Sequence[float], minimum: int = 2) -> tuple[float, ...]:
    """``mus`` as floats, checked: at least ``minimum`` values, finite, positive, distinct.

    Raises
    ------
    kbm.errors.ParameterError
        Naming the values that break a rule.
    """
    out = tuple(float(m) for m in mus)
    if len(out) < minimum:
        raise ParameterError(f"a convergence study needs at least {minimum} values of mu, got "
                             f"{len(out)} ({', '.join(f'{m:g}' for m in out) or 'none'})")
    bad = [m for m in out if not (math.isfinite(m) and m > 0)]
    if bad:
        raise ParameterError(f"the values of mu must be positive and finite, got "
                             f"{', '.join(f'{m:g}' for m in bad)}")
    dup = sorted({m for m in out if out.count(m) > 1})
    if dup:
        raise ParameterError(f"the values of mu must be distinct, got "
                             f"{', '.join(f'{m:g}' for m in dup)} more than once")
    return out


@dataclass(frozen=True)
class ConvergenceTable:
    """Errors ``errors[N][i]`` of order ``N`` at ``mus[i]`` and the fitted slopes.

    Attributes
    ----------
    quantity
        What is compared, e.g. ``"amplitude at sigma = 0"``.
    mus
        The values of ``mu``.
    true
        The true value (by shooting) at each ``mu``.
    errors
        ``errors[N]``: ``|predicted - true|`` of order ``N`` along ``mus``.
    model, resonance
        The forced model's name and the declared resonance ``p/q``.
    parameters
        The other parameters' values (``mu`` varies).
    setting
        The study's own numbers: ``{"sigma": ...}`` or ``{"sigma_range": [...], "fold": k}``.
    """

    quantity: str
    mus: tuple[float, ...]
    true: tuple[float, ...]
    errors: Mapping[int, tuple[float, ...]]
    model: str = ""
    resonance: str = ""
    parameters: Mapping[str, float] = field(default_factory=dict)
    setting: Mapping[str, object] = field(default_factory=dict)

    @property
    def orders(self) -> tuple[int, ...]:
        """The KBM orders compared, ascending."""
        return tuple(sorted(self.errors))

    @property
    def slopes(self) -> dict[int, float]:
        """The fitted slope per order (the expected slope of order ``N`` is ``N``)."""
        return {n: slope(self.mus, e) for n, e in self.errors.items()}

    def to_json(self) -> dict:
        """``model``, ``resonance``, ``parameters``, the ``setting``'s keys, ``quantity``,
        ``mu``, ``true``, ``errors`` and ``slopes`` (keyed by the order as a string),
        ``expected`` slopes and ``orders`` (NaN as ``None``)."""
        return jsonable({"model": self.model, "resonance": self.resonance,
                         "parameters": self.parameters, **self.setting, "quantity": self.quantity,
                         "mu": self.mus, "true": self.true, "errors": self.errors,
                         "slopes": self.slopes, "expected": {n: n for n in self.errors},
                         "orders": self.orders})

    def table(self) -> str:
        """The errors per ``mu`` (one column per order) and the fitted slopes, as text."""
        head = f"{self.model}, resonance {self.resonance}" if self.model else "forced model"
        pars = ", ".join(f"{k} = {v:g}" for k, v in self.parameters.items())
        true = "true sigma" if "fold" in self.setting else "true a"
        lines = [f"{head}{': ' + pars if pars else ''}",
                 f"{self.quantity}: order-N prediction against the true periodic response by "
                 + "shooting",
                 f"{'mu':>10}  {true:>16}" + "".join(f"  {f'error N={n}':>12}"
                                                    for n in self.orders)]
        for i, m in enumerate(self.mus):
            lines.append(f"{m:>10.6g}  {self.true[i]:>16.10g}"
                         + "".join(f"  {self.errors[n][i]:>12.4e}" for n in self.orders))
        lines.append("fitted slope of log(error) against log(mu):")
        for n, s in sorted(self.slopes.items()):
            lines.append(f"  order {n}: {s:.3f} (expected {n})")
        return "\n".join(lines)


def _setup(model, orders: Sequence[int], values: Mapping[str, object],
           resonance: Resonance | str | None, result: ForcedKBMResult | None, amplitudes):
    """The checked orders, the expansion (exact, or numeric on the amplitude window for a
    non-polynomial ``F``), the resolved parameters (floats, no ``mu``) and the model to
    integrate (the one given: a numeric expansion holds it with its parameters
    substituted, which the system would not recognise)."""
    orders = tuple(sorted({int(n) for n in orders}))
    if not orders or orders[0] < 1:
        raise ParameterError(f"the orders of a convergence study must be >= 1, got "
                             f"{list(orders)}")
    if "mu" in values:
        raise ParameterError("a convergence study sets mu itself: leave it out of the "
                             "parameter values")
    if isinstance(model, str):
        model = get_forced_model(model)
    res = result if result is not None else forced_expansion(
        model, orders[-1], dict(values), resonance=resonance, a_range=amplitudes)
    pars = {k: float(v) for k, v in model.resolve(values).items() if k != "sigma"}
    return orders, res, pars, model


def _stopped_short(nr, lo: float, hi: float) -> list[float]:
    """The detunings where an open branch of true responses ends inside ``(lo, hi)``."""
    tol = 1e-6 * (hi - lo)
    out = []
    for b in nr.branches:
        if len(b) > 2 and np.allclose(b[0].y0, b[-1].y0, atol=1e-6) \
                and abs(b[0].sigma - b[-1].sigma) < tol:
            continue  # a closed curve (an isola)
        out += [o.sigma for o in (b[0], b[-1]) if lo + tol < o.sigma < hi - tol]
    return out


def amplitude_study(model: ForcedOscillator | str, values: Mapping[str, object], sigma: float,
                    mus: Sequence[float], orders: Sequence[int] = (1, 2), *,
                    amplitudes: tuple[float, float] = (1e-3, 5.0),
                    resonance: Resonance | str | None = None,
                    result: ForcedKBMResult | None = None) -> ConvergenceTable:
    """Errors of the order-``N`` amplitude at detuning ``sigma`` for each ``mu``.

    The response followed is the largest-amplitude fixed point of the highest order's slow
    flow, corrected by shooting; each order's prediction is its own fixed point nearest to
    that response.

    Parameters
    ----------
    model
        A forced model or a built-in forced model's name.
    values
        The parameters other than ``mu``.
    sigma
        The detuning.
    mus
        At least two distinct positive values of ``mu``.
    orders
        The KBM orders compared.
    amplitudes
        The amplitude window in which the fixed points are sought.
    resonance
        The declared resonance (default the model's); ignored with ``result``.
    result
        The expansion to the highest order, if already derived.

    Raises
    ------
    numerics.errors.NoCycleError
        If an order has no fixed point in the amplitude window.
    numerics.errors.NumericsError
        If shooting fails (the value of ``mu`` is in the message).
    kbm.errors.ParameterError
        For bad values of ``mu`` or orders.
    """
    mus = check_mus(mus)
    sigma = float(sigma)
    orders, res, pars, model = _setup(model, orders, values, resonance, result, amplitudes)
    window = f"{amplitudes[0]:g} < a < {amplitudes[1]:g}"
    true, errs = [], {n: [] for n in orders}
    for m in mus:
        vals = {**values, "mu": m}
        system = ForcedSystem(model, vals, resonance=res.resonance)
        fps = fixed_points(res.slow_flow(vals, order=orders[-1]), sigma, amplitudes)
        if not fps:
            raise NoCycleError(f"no fixed point of the order-{orders[-1]} slow flow at sigma = "
                               f"{sigma:g} for mu = {m:g} with {window}")
        fp = fps[-1]
        try:
            orb = periodic_response(system, sigma,
                                    guess_from(system, fp.amplitude, fp.phase, sigma))
        except NumericsError as exc:
            raise type(exc)(f"at mu = {m:g}: {exc}") from None
        true.append(orb.amplitude)
        for n in orders:
            cand = fixed_points(res.slow_flow(vals, order=n), sigma, amplitudes)
            if not cand:
                raise NoCycleError(f"no fixed point of the order-{n} slow flow at sigma = "
                                   f"{sigma:g} for mu = {m:g} with {window}")
            errs[n].append(min(abs(c.amplitude - orb.amplitude) for c in cand))
    return ConvergenceTable(f"amplitude at sigma = {sigma:g}", mus, tuple(true),
                            {n: tuple(e) for n, e in errs.items()}, res.model.name,
                            str(res.resonance), pars, {"sigma": sigma})


def fold_study(model: ForcedOscillator | str, values: Mapping[str, object],
               sigmas: tuple[float, float], mus: Sequence[float],
               orders: Sequence[int] = (1, 2), *, which: int = 0,
               amplitudes: tuple[float, float] = (1e-3, 5.0), n_points: int = 200,
               resonance: Resonance | str | None = None,
               result: ForcedKBMResult | None = None) -> ConvergenceTable:
    """Errors of the fold (jump) detuning number ``which`` (sorted by ``sigma``) for each ``mu``.

    Parameters
    ----------
    model, values, mus, orders, amplitudes, resonance, result
        As for :func:`amplitude_study`.
    sigmas
        The detuning range ``(from, to)`` searched for folds.
    which
        The fold's index, counted from the lowest ``sigma`` (0 the first).
    n_points
        About the number of points per branch of the true curve's continuation.

    Raises
    ------
    kbm.errors.ParameterError
        If the true or a predicted curve has fewer folds in ``sigmas``, or for a bad range.
    """
    mus = check_mus(mus)
    lo, hi = float(sigmas[0]), float(sigmas[1])
    if not (math.isfinite(lo) and math.isfinite(hi) and hi > lo):
        raise ParameterError(f"the detuning range must be FROM < TO, got {lo:g} to {hi:g}")
    if which < 0:
        raise ParameterError(f"the fold's index must be >= 0, got {which}")
    orders, res, pars, model = _setup(model, orders, values, resonance, result,
                                      amplitudes)
    true, errs = [], {n: [] for n in orders}
    for m in mus:
        vals = {**values, "mu": m}
        system = ForcedSystem(model, vals, resonance=res.resonance)
        nr = numeric_response(system, res.slow_flow(vals, order=orders[-1]), (lo, hi),
                              amplitudes, n_points=n_points, seeds_at=2)
        if len(nr.folds) <= which:
            ends = _stopped_short(nr, lo, hi)
            why = ("widen the range" if not ends else
                   f"the continuation of the true responses stopped at sigma = "
                   f"{', '.join(f'{e:.6g}' for e in ends)}, inside the range (its step "
                   f"budget), so a fold beyond may be missing")
            raise ParameterError(f"the true response has {len(nr.folds)} fold(s) in sigma "
                                 f"{lo:g} to {hi:g} at mu = {m:g}, no fold {which}; {why}")
        s_true = nr.folds[which].sigma
        true.append(s_true)
        for n in orders:
            rc = response_curve(res.slow_flow(vals, order=n), (lo, hi), amplitudes, seeds_at=2)
            if len(rc.folds) <= which:
                raise ParameterError(f"the order-{n} response has {len(rc.folds)} fold(s) in "
                                     f"sigma {lo:g} to {hi:g} at mu = {m:g}, no fold {which}")
            errs[n].append(abs(rc.folds[which].sigma - s_true))
    return ConvergenceTable(f"detuning of fold {which}", mus, tuple(true),
                            {n: tuple(e) for n, e in errs.items()}, res.model.name,
                            str(res.resonance), pars, {"sigma_range": [lo, hi], "fold": which})
