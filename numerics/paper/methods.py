"""Where the methods meet: classical KBM and the energy method against the true SEDF cycle.

:func:`methods_map` computes the true limit cycle of the SEDF (paper eq. 3,
``Omega = lam = 1``) on a grid of ``(mu, Delta, beta)`` with ONE sweep
(:func:`numerics.cycles.sweep`, as :func:`numerics.paper.validity.validity_map`,
which then gives the errors of classical KBM orders 1 and 2 on the same cycles)
and the cycles of the energy method's orders 1 and 2
(:func:`numerics.energy.map_predictions`, one column per ``(beta, Delta)``; the
predicted cycle whose first-harmonic amplitude is closest to the true one).  The
error of a method at a point is the largest relative error of the first-harmonic
amplitude, the maximum of ``x`` and the frequency (as in the validity map).

Classical KBM expands in ``mu`` at fixed ``delta = Delta/mu`` and holds for small
``Delta``; the energy method keeps ``Delta sin(2 pi x)`` in the conservative
orbit and holds for small ``mu`` at any ``Delta`` where the cycle exists.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from kbm.output.strict_json import finite, json_fields
from numerics.comparison.prediction import numeric_value
from numerics.energy import map_predictions
from numerics.paper.validity import (VALIDITY_KEYS, error_grid, sedf_sweep, short_reason,
                                     validity_map)

__all__ = ["METHODS", "METHODS_GRID", "MethodsPoint", "MethodsMap", "methods_map"]

#: the methods compared, in the order of the tables
METHODS = ("KBM order 1", "KBM order 2", "energy order 1", "energy order 2")

#: the grid of the documentation's figure (7 x 11 x 2 = 154 true cycles)
METHODS_GRID: Mapping[str, tuple[float, ...]] = {
    "mu": (0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.5),
    "Delta": (0.001, 0.003, 0.01, 0.03, 0.1, 0.3, 0.6, 1.0, 1.5, 2.0, 3.0),
    "beta": (0.25, 1.0),
}

_ENERGY_KEYS = {"amplitude": "amplitude_first_harmonic", "amplitude_max": "amplitude_max",
                "frequency": "frequency"}


@dataclass(frozen=True, eq=False)
class MethodsPoint:
    """One grid point: the true cycle and each method's largest relative error.

    Attributes
    ----------
    params : Mapping[str, float]
        ``mu``, ``Delta``, ``beta``.
    success : bool
        Whether a true cycle was found.
    message : str
        Why not (empty otherwise).
    amplitude, frequency : float
        First-harmonic amplitude and frequency of the true cycle.
    errors : Mapping[str, float]
        Per method of :data:`METHODS`: the largest relative error of amplitude, max
        ``x`` and frequency (nan where the method has no cycle).
    """

    params: Mapping[str, float]
    success: bool
    message: str
    amplitude: float
    frequency: float
    errors: Mapping[str, float]


@dataclass(frozen=True, eq=False)
class MethodsMap:
    """Errors of classical KBM and energy orders over a grid (see :func:`methods_map`)."""

    axes: Mapping[str, tuple]
    points: tuple

    def within(self, tol: float, method: str) -> list[MethodsPoint]:
        """The points where ``method`` is within ``tol`` (relative) of the true cycle."""
        return [p for p in self.points if p.success and p.errors[method] <= tol]

    def array(self, method: str, beta: float) -> np.ndarray:
        """Errors ``[i_Delta, i_mu]`` at one ``beta`` (nan where no cycle)."""
        return error_grid(self.axes, self.points, beta, lambda p: p.errors[method])

    def summary(self, tols: Sequence[float] = (1e-2, 1e-3)) -> dict:
        """Per ``beta``, method and tolerance: the number of points within it, of those
        with a true cycle, and the largest ``Delta`` within it at each ``mu``."""
        out = {}
        for b in self.axes["beta"]:
            pts = [p for p in self.points if p.params["beta"] == b and p.success]
            row = {"true cycles": len(pts)}
            for m in METHODS:
                for t in tols:
                    ok = [p for p in pts if p.errors[m] <= t]
                    row[f"{m} within {t:g}"] = len(ok)
                    row[f"{m} largest Delta within {t:g}"] = {
                        f"{mu:g}": max((p.params["Delta"] for p in ok if p.params["mu"] == mu),
                                       default=None) for mu in self.axes["mu"]}
            out[f"{b:g}"] = row
        return out

    def table(self) -> str:
        """One line per point (errors per method), then the counts within 1 % and 1e-3."""
        lines = [f"{'mu':>6}{'Delta':>8}{'beta':>6}{'a (true)':>11}"
                 + "".join(f"{m:>16}" for m in METHODS)]
        for p in self.points:
            pr = p.params
            head = f"{pr['mu']:>6g}{pr['Delta']:>8g}{pr['beta']:>6g}"
            if not p.success:
                lines.append(f"{head}  no true cycle: {short_reason(p.message)}")
                continue
            lines.append(f"{head}{p.amplitude:>11.6f}"
                         + "".join(f"{p.errors[m]:>16.2e}" if np.isfinite(p.errors[m])
                                   else f"{'no cycle':>16}" for m in METHODS))
        lines.append("(no cycle: the method predicts no cycle near the true one there)")
        for b, row in self.summary().items():
            lines.append(f"beta = {b}: {row['true cycles']} true cycles; within 1 % / 1e-3: "
                         + ", ".join(f"{m} {row[f'{m} within 0.01']}/{row[f'{m} within 0.001']}"
                                     for m in METHODS))
        return "\n".join(lines)

    def to_json(self) -> dict:
        """Strict-JSON dict (nan becomes ``None``)."""
        return finite({"methods": list(METHODS),
                       "axes": {k: list(v) for k, v in self.axes.items()},
                       "error": "max relative error of " + ", ".join(VALIDITY_KEYS),
                       "summary": self.summary(),
                       "points": [json_fields(p) for p in self.points]})


def _energy_error(pred, cyc) -> float:
    """Largest relative error of the predicted cycle nearest the true first harmonic."""
    if not pred.cycles:
        return float("nan")
    a = cyc.amplitude_first_harmonic
    c = min(pred.cycles, key=lambda c: abs(c.amplitude_first_harmonic - a))
    return max(abs(getattr(c, e) - numeric_value(cyc, k)) / abs(numeric_value(cyc, k))
               for k, e in _ENERGY_KEYS.items())


def methods_map(mu: Sequence[float] = METHODS_GRID["mu"],
                Delta: Sequence[float] = METHODS_GRID["Delta"],
                beta: Sequence[float] = METHODS_GRID["beta"], *, lam: float = 1.0,
                workers: int | None = None, progress: bool | None = None,
                swept=None, x_start: float = 4.0) -> MethodsMap:
    """Errors of classical KBM orders 1, 2 and energy orders 1, 2 on ``mu x Delta x beta``.

    Parameters
    ----------
    mu, Delta, beta : sequence of float
        Grid axes (physical parameters of the paper's eq. 3).
    lam : float
    workers : int, optional
        Processes of the sweep and of :func:`numerics.energy.map_predictions`.
    progress : bool, optional
        Progress bar of the sweep.
    swept : list of numerics.cycles.SweepPoint, optional
        The sweep, if already computed (the order of :func:`numerics.grid` with axes
        ``beta, mu, Delta``).
    x_start : float
        See :func:`numerics.paper.validity.validity_map`.

    Returns
    -------
    MethodsMap
    """
    axes, swept = sedf_sweep(mu, Delta, beta, lam, swept, workers=workers, progress=progress,
                             x_start=x_start)
    vm = validity_map(axes["mu"], axes["Delta"], axes["beta"], orders=(1, 2), lam=lam,
                      swept=swept)
    energy = {}
    for b in axes["beta"]:
        for N in (1, 2):
            cols = map_predictions("sedf", {"beta": b, "lam": lam}, axes["mu"], "Delta",
                                   axes["Delta"], order=N, workers=workers)
            for i, D in enumerate(axes["Delta"]):
                for j, m in enumerate(axes["mu"]):
                    energy[(b, m, D, N)] = cols[i][j]
    out = []
    for sp_, vp in zip(swept, vm.points):
        pr = vp.params
        if not vp.success:
            out.append(MethodsPoint(pr, False, vp.message, np.nan, np.nan,
                                    dict.fromkeys(METHODS, np.nan)))
            continue
        errs = {f"KBM order {N}": vp.error(N) for N in (1, 2)}
        for N in (1, 2):
            errs[f"energy order {N}"] = _energy_error(
                energy[(pr["beta"], pr["mu"], pr["Delta"], N)], sp_.cycle)
        out.append(MethodsPoint(pr, True, "", vp.amplitude, vp.frequency, errs))
    return MethodsMap(axes=axes, points=tuple(out))
