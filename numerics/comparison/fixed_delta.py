"""Convergence at fixed physical ``Delta``: the energy method converges, classical KBM cannot.

Classical KBM expands the SEDF (paper eq. 3) in ``mu`` at fixed ``delta = Delta/mu``
(:func:`numerics.comparison.convergence.convergence_study`); at a fixed physical
``Delta`` the parameter ``delta = Delta/mu`` grows as ``mu -> 0`` and its error
tends to a non-zero limit (the error of linearising ``Delta sin(2 pi x/lam)``).
The energy method keeps the whole conservative force ``g = Omega**2 x + Delta
sin(2 pi x/lam)`` and averages only ``mu h``: at fixed ``Delta`` it is a genuine
expansion in ``mu``.  :func:`fixed_delta_study` shoots the true cycle for each
``mu`` (:func:`numerics.compare`, energy orders as ``extra`` rows), records the
errors of every row and fits log-log slopes with
:func:`~numerics.comparison.convergence.fit_slope`.

Predicted orders of the energy method (``h = -(beta x**2 - 1) x'`` odd in ``x'``)
--------------------------------------------------------------------------------
After ``N`` integrations (order ``N``, :mod:`numerics.energy.position`) the energy
along the cycle is correct to ``O(mu**(N+1))``; the period, frequency, maximum
of ``x`` and first-harmonic amplitude inherit that error.  The symmetry
``(t, x', mu) -> (-t, -x', -mu)``, kept by the scheme, makes them even in
``mu``: the order rounds up to even, ``2, 4, 4`` for ``N = 1, 2, 3``.  The
Floquet exponent ``L = mu oint h_v dt`` over the curve has the curve's error
times ``mu``, ``O(mu**(N+2))``, and is odd in ``mu``: ``3, 5, 5``.

Errors below ``floor * max(|true value|, 1)`` (the accuracy of the shooting,
``rtol = 1e-12``, whose Floquet multiplier is good to about ``1e-10``, and of
the quadratures) are left out of the fit (``errors`` holds nan there,
``relative`` the value).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from kbm.errors import KBMError

from kbm.output.strict_json import Rendered, jsonable
from numerics.comparison.comparison import compare
from numerics.comparison.convergence import by_pair, fit_slope
from numerics.comparison.predict import energy_prediction
from numerics.comparison.prediction import derived, numeric_value

__all__ = ["FIXED_DELTA_KEYS", "DEFAULT_EPS", "energy_orders_predicted", "FixedDeltaStudy",
           "fixed_delta_study", "FixedDeltaConvergence", "fixed_delta_convergence"]

#: the quantities fitted
FIXED_DELTA_KEYS = ("frequency", "amplitude_max", "amplitude", "floquet_exponent")
#: the values of ``mu`` (from 0.2 down to 0.005)
DEFAULT_EPS = (0.2, 0.1, 0.05, 0.025, 0.0125, 0.005)


def energy_orders_predicted(order: int) -> dict[str, int]:
    """Predicted error orders of the energy method (``h`` odd in ``x'``; module docstring).

    Examples
    --------
    >>> energy_orders_predicted(2)["frequency"], energy_orders_predicted(2)["floquet_exponent"]
    (4, 5)
    """
    even = order + 1 + (order + 1) % 2
    odd = order + 2 + (order + 1) % 2
    return {"frequency": even, "amplitude_max": even, "amplitude": even,
            "floquet_exponent": odd}


@dataclass(frozen=True, eq=False)
class FixedDeltaStudy:
    """Errors of energy and classical KBM orders along ``mu`` at one ``(Delta, beta)``.

    Attributes
    ----------
    Delta, beta : float
        Physical parameters (``Omega = lam = 1``).
    eps : tuple of float
        The values of ``mu``.
    rows : tuple of str
        Row labels, ``"energy order N"`` and ``"KBM order N"``.
    keys : tuple of str
        Quantities (:data:`FIXED_DELTA_KEYS`).
    errors, relative : dict
        ``[(row, key)]``: absolute and relative errors along ``eps`` (nan where there
        is no true cycle or the row has no cycle; ``errors`` also where it lies below
        the numerical floor).
    slopes : dict
        ``[(row, key)]``: fitted log-log slope (nan with fewer than two points).
    predicted : dict
        ``[(row, key)]``: the predicted order; ``None`` for classical KBM (no convergence
        at fixed ``Delta``).
    messages : tuple of str
        Per ``mu``: empty, or why there is no true cycle.
    floor : float
    """

    Delta: float
    beta: float
    eps: tuple
    rows: tuple
    keys: tuple
    errors: dict
    relative: dict
    slopes: dict
    predicted: dict
    messages: tuple
    floor: float

    def limit(self, row: str, key: str) -> float:
        """The relative error at the smallest ``mu`` with a true cycle."""
        r = self.relative[(row, key)]
        ok = np.nonzero(np.isfinite(r))[0]
        return float(r[ok[-1]]) if len(ok) else float("nan")

    def table(self) -> str:
        """Slopes (predicted order) per row and key, then each missing true cycle."""
        lines = [f"Delta = {self.Delta:g}, beta = {self.beta:g}: fitted slope of log|error| vs "
                 f"log mu (predicted order; '-': none, no convergence) [relative error at the "
                 f"smallest mu]", f"{'':16}" + "".join(f"{k:>28}" for k in self.keys)]
        for row in self.rows:
            cells = []
            for k in self.keys:
                p = self.predicted[(row, k)]
                cells.append(f"{self.slopes[(row, k)]:6.2f} ({'-' if p is None else p}) "
                             f"[{self.limit(row, k):8.1e}]")
            lines.append(f"{row:16}" + "".join(f"{c:>28}" for c in cells))
        lines += [f"  mu = {e:g}: {m}" for e, m in zip(self.eps, self.messages) if m]
        return "\n".join(lines)

    def to_json(self) -> dict:
        """Strict-JSON dict (nan becomes ``None``), the tables keyed ``"row:quantity"``."""
        return jsonable({"Delta": self.Delta, "beta": self.beta, "eps": self.eps,
                         "rows": self.rows, "keys": self.keys, "errors": by_pair(self.errors),
                         "relative": by_pair(self.relative), "slopes": by_pair(self.slopes),
                         "predicted": by_pair(self.predicted), "messages": self.messages,
                         "floor": self.floor})


def fixed_delta_study(Delta: float, beta: float, eps: Sequence[float] = DEFAULT_EPS, *,
                      energy_orders: Sequence[int] = (1, 2, 3),
                      kbm_orders: Sequence[int] = (1, 2),
                      keys: Sequence[str] = FIXED_DELTA_KEYS, floor: float = 1e-9,
                      x_start: float = 4.0, **cycle_kwargs) -> FixedDeltaStudy:
    """Errors of the energy method and classical KBM against ``mu`` at fixed ``Delta``.

    Parameters
    ----------
    Delta, beta : float
        SEDF parameters (paper eq. 3, ``Omega = lam = 1``).
    eps : sequence of float
        Values of ``mu``.
    energy_orders, kbm_orders : sequence of int
        Orders of the energy method (position scheme) and of classical KBM (<= 2).
    keys : sequence of str
        Quantities compared (keys of :data:`numerics.comparison.prediction.ERROR_KEYS`).
    floor : float
        Errors below ``floor * max(|true value|, 1)`` are left out of the fits
        (numerical accuracy).
    x_start : float
        Transient start when Newton from the KBM guess fails (see
        :func:`numerics.paper.validity.validity_map`).
    cycle_kwargs
        Passed to :func:`numerics.limit_cycle`.

    Returns
    -------
    FixedDeltaStudy
    """
    kbm_orders = tuple(sorted(int(n) for n in kbm_orders))
    res = derived("sedf", kbm_orders[-1])
    fns = res.functions("numpy")
    extra = [energy_prediction(int(n)) for n in energy_orders]
    rows = tuple(f"energy order {int(n)}" for n in energy_orders) + tuple(
        f"KBM order {n}" for n in kbm_orders)
    keys = tuple(keys)
    nan = np.full(len(eps), np.nan)
    errors = {(r, k): nan.copy() for r in rows for k in keys}
    relative = {(r, k): nan.copy() for r in rows for k in keys}
    messages = []
    for i, mu in enumerate(eps):
        try:
            comp = compare("sedf", {"mu": mu, "Delta": Delta, "beta": beta, "lam": 1},
                           orders=kbm_orders, extra=extra, result=res, functions=fns,
                           x_start=x_start, **cycle_kwargs)
        except KBMError as exc:
            messages.append(f"no true cycle ({exc})")
            continue
        messages.append("")
        for p in comp.predictions:
            if not p.success:
                continue
            for k in keys:
                relative[(p.label, k)][i] = comp.relative_error(p, k)
                err = abs(comp.error(p, k))
                # an error at the numerical accuracy is noise: left out of the fit
                scale = max(abs(numeric_value(comp.numeric, k)), 1.0)
                errors[(p.label, k)][i] = err if err >= floor * scale else np.nan
    slopes, predicted = {}, {}
    for r in rows:
        orders = (energy_orders_predicted(int(r.split()[-1])) if r.startswith("energy")
                  else dict.fromkeys(keys))
        for k in keys:
            slopes[(r, k)] = fit_slope(eps, errors[(r, k)])
            predicted[(r, k)] = orders[k]
    return FixedDeltaStudy(float(Delta), float(beta), tuple(float(e) for e in eps), rows, keys,
                           errors, relative, slopes, predicted, tuple(messages), float(floor))


@dataclass(frozen=True, eq=False)
class FixedDeltaConvergence(Rendered):
    """One :class:`FixedDeltaStudy` per ``(Delta, beta)``."""

    studies: tuple

    layout = ("studies",)

    def table(self) -> str:
        return "\n\n".join(s.table() for s in self.studies)


def fixed_delta_convergence(Deltas: Sequence[float] = (1.5, 3.0),
                            betas: Sequence[float] = (1.0, 0.5, 0.25),
                            eps: Sequence[float] = DEFAULT_EPS,
                            **kwargs) -> FixedDeltaConvergence:
    """:func:`fixed_delta_study` for every ``(Delta, beta)`` (``kwargs`` passed on)."""
    return FixedDeltaConvergence(tuple(fixed_delta_study(D, b, eps, **kwargs)
                                       for D in Deltas for b in betas))
