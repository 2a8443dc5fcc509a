"""Where is KBM accurate?  Relative errors of KBM orders over a grid of sedf parameters.

:func:`validity_map` computes the true limit cycle of the SEDF (paper eq. 3,
``v = 0``, ``Omega = 1``, ``lam = 1``) on a grid of ``(mu, Delta, beta)`` with
:func:`numerics.cycles.sweep` (all cores) and, at each point, the cycle predicted by
KBM orders 1 and 2 (:func:`numerics.comparison.comparison.kbm_prediction`, the root closest to
the true first-harmonic amplitude).  The error of a point is the largest of the
relative errors of the first-harmonic amplitude, the maximum of ``x`` and the
frequency.  The small parameter of the expansion is ``mu`` at fixed
``delta = Delta/mu``; along a line of fixed ``Delta`` the expansion degrades as
``mu`` decreases, because ``Delta/mu`` grows.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from kbm.output.strict_json import json_fields

from numerics.comparison.prediction import derived, kbm_prediction, numeric_value
from numerics.cycles.sweep import grid, sweep

__all__ = ["ValidityPoint", "ValidityMap", "validity_map", "DEFAULT_GRID", "VALIDITY_KEYS",
           "short_reason", "sedf_sweep"]

#: the quantities whose relative errors define the error of a point
VALIDITY_KEYS = ("amplitude", "amplitude_max", "frequency")

#: the grid of the documentation's figure
DEFAULT_GRID: Mapping[str, tuple[float, ...]] = {
    "mu": (0.01, 0.02, 0.05, 0.1, 0.2, 0.5),
    "Delta": (0.001, 0.003, 0.01, 0.03, 0.1, 0.3, 1.0, 1.5, 3.0),
    "beta": (0.25, 1.0),
}


_ATTEMPT = re.compile(r"transient from x = ([^:]+): no limit cycle: ")


def short_reason(message: str) -> str:
    """Why a sweep found no cycle, once: the attempts of a message such as ``transient from
    x = 2: no limit cycle: the motion settles to rest at x = 1.89 (...); start elsewhere
    ...; transient from x = 4: ...`` become ``the motion settles to rest at x = 1.89
    (from x = 2, 4)``, distinct reasons joined by ``or``; other messages are returned
    unchanged."""
    parts = _ATTEMPT.split(message)
    if len(parts) < 3 or parts[0].strip(" ;"):
        return message
    starts, reasons = parts[1::2], []
    for text in parts[2::2]:
        text = text.strip(" ;").replace("; start elsewhere (x_start) to look for a cycle", "")
        reason = re.sub(r"\s*\([^()]*\)", "", text).strip(" ;")
        if reason not in reasons:
            reasons.append(reason)
    return " or ".join(reasons) + f" (from x = {', '.join(s.strip() for s in starts)})"


@dataclass(frozen=True, eq=False)
class ValidityPoint:
    """One grid point: parameters, the true cycle's numbers and each order's errors.

    Attributes
    ----------
    params
        ``mu``, ``Delta``, ``beta`` (``lam = 1``).
    success, message
        Whether a true cycle was found (and the KBM orders have a cycle), or why not.
    amplitude, frequency
        First-harmonic amplitude and frequency of the true cycle.
    errors
        ``errors[N][key]``: relative error of KBM order ``N`` (``key`` in
        :data:`VALIDITY_KEYS`, plus ``"max"``, the largest of them); nan if the
        order has no cycle.
    """

    params: Mapping[str, float]
    success: bool
    message: str
    amplitude: float
    frequency: float
    errors: Mapping[int, Mapping[str, float]]

    def error(self, order: int) -> float:
        return float(self.errors.get(order, {}).get("max", np.nan))


def error_grid(axes: Mapping[str, Sequence[float]], points: Sequence, beta: float,
               error) -> np.ndarray:
    """``error(point)`` of the points with a true cycle at ``beta`` as an array
    ``[i_Delta, i_mu]`` over ``axes`` (nan where no cycle)."""
    mus, Ds = list(axes["mu"]), list(axes["Delta"])
    out = np.full((len(Ds), len(mus)), np.nan)
    for p in points:
        if p.params["beta"] == beta and p.success:
            out[Ds.index(p.params["Delta"]), mus.index(p.params["mu"])] = error(p)
    return out


@dataclass(frozen=True, eq=False)
class ValidityMap:
    """Relative errors of KBM orders over a parameter grid (see :func:`validity_map`)."""

    orders: tuple[int, ...]
    axes: Mapping[str, tuple[float, ...]]
    points: tuple[ValidityPoint, ...]

    def within(self, tol: float, order: int) -> list[ValidityPoint]:
        """The points where order ``order`` is within ``tol`` (relative) of the truth."""
        return [p for p in self.points if p.success and p.error(order) <= tol]

    def array(self, order: int, beta: float) -> np.ndarray:
        """Errors as an array ``[i_Delta, i_mu]`` at one ``beta`` (nan where no cycle)."""
        return error_grid(self.axes, self.points, beta, lambda p: p.error(order))

    def table(self) -> str:
        """One line per point: parameters, true amplitude and each order's error."""
        lines = [f"{'mu':>6}{'Delta':>8}{'beta':>6}{'a (true)':>11}"
                 + "".join(f"{'err N=' + str(N):>12}" for N in self.orders)]
        for p in self.points:
            pr = p.params
            if not p.success:
                lines.append(f"{pr['mu']:>6g}{pr['Delta']:>8g}{pr['beta']:>6g}  no cycle: "
                             f"{short_reason(p.message)}")
                continue
            lines.append(f"{pr['mu']:>6g}{pr['Delta']:>8g}{pr['beta']:>6g}{p.amplitude:>11.6f}"
                         + "".join(f"{p.error(N):>12.2e}" for N in self.orders))
        return "\n".join(lines)

    def to_json(self) -> dict:
        return json_fields(self, "orders", "axes", points=[
            json_fields(p, "params", "success", "message", "amplitude", "frequency",
                        errors={str(N): dict(e) for N, e in p.errors.items()})
            for p in self.points])


def sedf_sweep(mu, Delta, beta, lam: float, swept=None, **kwargs) -> tuple[dict, list]:
    """The grid's axes (floats) and the true SEDF cycles on ``beta x mu x Delta``
    (:func:`numerics.cycles.sweep` with ``kwargs``), unless ``swept`` holds them already."""
    axes = {"mu": tuple(float(v) for v in mu), "Delta": tuple(float(v) for v in Delta),
            "beta": tuple(float(v) for v in beta)}
    if swept is None:
        swept = sweep("sedf", grid(beta=axes["beta"], mu=axes["mu"], Delta=axes["Delta"]),
                      fixed={"lam": lam}, continuation=False, **kwargs)
    return axes, swept


def validity_map(mu: Sequence[float] = DEFAULT_GRID["mu"],
                 Delta: Sequence[float] = DEFAULT_GRID["Delta"],
                 beta: Sequence[float] = DEFAULT_GRID["beta"], *,
                 orders: Sequence[int] = (1, 2), lam: float = 1.0,
                 workers: int | None = None, progress: bool | None = None,
                 swept=None, x_start: float = 4.0) -> ValidityMap:
    """Relative errors of KBM orders for the SEDF on the grid ``mu x Delta x beta``.

    Parameters
    ----------
    mu, Delta, beta
        Grid axes (physical parameters of the paper's eq. 3).
    orders
        KBM orders (at most 2 for the SEDF).
    workers, progress
        Passed to :func:`numerics.cycles.sweep`.
    x_start
        Start of the transient when Newton from the first-order KBM cycle fails
        (:func:`numerics.limit_cycle`); from the default ``x = 1`` the SEDF with
        ``Delta = 3`` falls into a side well of the potential instead of the cycle.
    swept
        The result of that sweep, if already computed (the grid order of
        :func:`numerics.grid` with axes ``beta, mu, Delta``).

    Returns
    -------
    ValidityMap

    Examples
    --------
    >>> vm = validity_map([0.05], [0.01], [1.0], workers=1)
    >>> vm.points[0].error(2) < vm.points[0].error(1) < 1e-2
    True
    """
    axes, swept = sedf_sweep(mu, Delta, beta, lam, swept, workers=workers, progress=progress,
                             x_start=x_start)
    orders = tuple(sorted(int(n) for n in orders))
    res = derived("sedf", orders[-1])
    fns = res.functions("numpy")
    out = []
    for sp_ in swept:
        params = {k: float(v) for k, v in sp_.params.items()}
        cyc = sp_.cycle
        if cyc is None or not cyc.success:
            out.append(ValidityPoint(params, False, sp_.error or (cyc.message if cyc else ""),
                                     np.nan, np.nan, {}))
            continue
        if cyc.amplitude_first_harmonic < 1e-6 * abs(cyc.amplitude_max):
            out.append(ValidityPoint(params, False, "the orbit found is an equilibrium "
                                     f"(x = {cyc.amplitude_max:.6g}, no first harmonic), "
                                     "not a cycle", np.nan, np.nan, {}))
            continue
        errs: dict[int, dict[str, float]] = {}
        for N in orders:
            pred = kbm_prediction(res, {**params, "lam": lam}, N,
                                  target_amplitude=cyc.amplitude_first_harmonic,
                                  functions=fns, n_samples=512)
            if not pred.success:
                errs[N] = {k: np.nan for k in (*VALIDITY_KEYS, "max")}
                continue
            e = {k: abs(pred.value(k) - numeric_value(cyc, k)) / abs(numeric_value(cyc, k))
                 for k in VALIDITY_KEYS}
            e["max"] = max(e.values())
            errs[N] = e
        out.append(ValidityPoint(params, True, cyc.message, cyc.amplitude_first_harmonic,
                                 cyc.frequency, errs))
    return ValidityMap(orders=orders, axes=axes, points=tuple(out))
