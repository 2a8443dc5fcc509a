"""Energy-averaging predictions over a parameter map, with the work that does not depend
on ``mu`` done once.

At fixed values of the other *physical* parameters (e.g. the slider's ``Delta``,
``beta``) the split ``x'' = -g(x) + mu h(x, x')`` does not depend on ``mu``: the
phase portrait of ``x'' + g(x) = 0`` and the energy-balance roots ``E*``
(``Gamma(E*) = 0``) are shared by every ``mu`` of a column.  Only the stability
(the sign of ``mu``), the multiplier ``exp(mu dGamma/dE)``, the energy swing
(``prop. to |mu|``) and, for order ``>= 2``, the position scheme depend on ``mu``.
:func:`predict_along_mu` therefore

- splits the model at the first and the last ``mu`` and checks numerically that
  ``g``, ``G`` and ``h`` agree (else it falls back to
  :func:`~numerics.energy.predict_cycles` at every ``mu``);
- computes the portrait and the roots once, rescales their ``mu``-dependent numbers;
- runs the position scheme at each ``mu`` in the given order, starting each level
  from the levels of the previous ``mu``'s cycle and the node count from its
  converged one (a warm start: the result is the same fixed point, to ``tol``);
- uses the period tolerance ``tol`` (default ``1e-9`` instead of
  :func:`~numerics.energy.position.position_cycle`'s ``1e-11``).

:func:`map_predictions` runs columns (one per value of another parameter) on a
process pool.
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import replace

import numpy as np
import sympy as sp

from kbm.model.conservative import split_conservative
from kbm.parameters.bound import bind
from kbm.symbols import x as _x, xdot as _xdot

from .balance import balance_cycles
from .portrait import phase_portrait
from .position import PositionError
from .predict import EnergyPrediction, _first_order, _position, predict_cycles

__all__ = ["predict_along_mu", "map_predictions"]


def _same_split(s0, s1, bracket: float) -> bool:
    """Whether two splits have the same ``g``, ``G``, ``h`` (to 1e-12) on sample points."""
    xs = np.linspace(-bracket, bracket, 41)
    vs = np.linspace(-3.0, 3.0, 7)[:, None]
    f0, f1 = s0.numpy_functions(), s1.numpy_functions()
    pairs = [(f0[i](xs), f1[i](xs)) for i in range(3)] + [(f0[3](xs, vs), f1[3](xs, vs))]
    return all(np.allclose(a, b, rtol=1e-12, atol=1e-12 * (1 + np.max(np.abs(a))))
               for a, b in pairs)


def _at_mu(c, mu0: float, mu: float):
    """The energy-balance root ``c`` (computed at ``mu0``) with its numbers at ``mu``."""
    r = abs(mu / mu0)
    return replace(c, stable=bool(mu * c.dgamma_dE < 0),
                   floquet_multiplier=float(np.exp(mu * c.dgamma_dE)),
                   separatrix_margin=c.separatrix_margin / r,
                   period_sensitivity=c.period_sensitivity * r)


def predict_along_mu(model, params: Mapping[str, object], mu: Sequence[float], *,
                     order: int = 2, tol: float = 1e-9,
                     potential=None) -> tuple[EnergyPrediction, ...]:
    """:func:`~numerics.energy.predict_cycles` (position scheme) at every ``mu`` of a column.

    Parameters
    ----------
    model : kbm.model.builtins.Oscillator or str
    params : Mapping[str, object]
        The other parameters, in the names kept fixed (physical ones such as ``Delta``).
    mu : sequence of float
        Values of ``mu``, in the order the warm start follows (monotone is best).
    order : int
        Order of the prediction (``>= 1``).
    tol : float
        Relative tolerance of the period of each position-scheme cycle.
    potential : str or sympy.Expr, optional
        See :func:`~numerics.energy.predict_cycles`.

    Returns
    -------
    tuple of EnergyPrediction
        One per ``mu``; equal to ``predict_cycles(model, {**params, "mu": m}, order=order)``
        to about ``tol`` (checked by the tests).
    """
    mus = [float(m) for m in mu]
    if not mus:
        return ()
    s0 = split_conservative(model, {**params, "mu": mus[0]}, potential=potential)
    s1 = split_conservative(model, {**params, "mu": mus[-1]}, potential=potential)
    portrait = phase_portrait(s0)
    if not _same_split(s0, s1, max(portrait.bracket, 1.0)) or s0.conservative:
        return tuple(predict_cycles(model, {**params, "mu": m}, order=order,
                                    potential=potential) for m in mus)
    first = balance_cycles(portrait)
    if not first:
        p0 = predict_cycles(model, {**params, "mu": mus[0]}, order=order, potential=potential)
        return tuple(replace(p0, params=dict(bind(model, {**params, "mu": m}).floats))
                     for m in mus)
    info = dict(model=s0.model.name, order=int(order),
                annuli=tuple(a.summary() for a in portrait.annuli),
                equilibria=tuple({"x": e.x, "kind": e.kind, "energy": e.energy}
                                 for e in portrait.equilibria))
    odd = sp.expand(s0.h + s0.h.subs(_xdot, -_xdot)) == 0
    hv = sp.lambdify((_x, _xdot), sp.diff(s0.h, _xdot), "numpy")

    def hvf(x, v):
        return np.broadcast_to(np.asarray(hv(x, v), float), np.broadcast(x, v).shape)

    warm: dict[int, tuple] = {}        # per root: (levels, nodes) of the last mu
    out = []
    for m in mus:
        cycles, lost = [], []
        for i, c0 in enumerate(first):
            c = _at_mu(c0, s0.mu, m)
            if order == 1 and odd:
                cycles.append(_first_order(c))
                continue
            levels, nodes = warm.get(i, (None, 256))
            try:
                pc, pos = _position(c, portrait.functions, hvf, m, int(order), tol=tol,
                                    guesses=levels, n_start=max(64, nodes // 2))
            except PositionError as e:
                warm.pop(i, None)
                lost.append(f"{c.annulus.label} (x_max {c.x_max:.6g}): {e}")
                continue
            warm[i] = (pos.levels, pos.nodes)
            cycles.append(pc)
        cycles.sort(key=lambda c: (c.energy, c.amplitude_max))
        out.append(EnergyPrediction(params=dict(bind(model, {**params, "mu": m}).floats),
                                    cycles=tuple(cycles), reason="; ".join(lost), **info))
    return tuple(out)


def _column(args):
    model, params, mus, kwargs = args
    return predict_along_mu(model, params, mus, **kwargs)


def map_predictions(model, params: Mapping[str, object], mu: Sequence[float], axis: str,
                    values: Sequence[float], *, order: int = 2, tol: float = 1e-9,
                    workers: int | None = None) -> list[tuple[EnergyPrediction, ...]]:
    """Energy predictions on the grid ``values x mu``, one column per value of ``axis``.

    Parameters
    ----------
    model : str
        A built-in model name (sent to the worker processes).
    params : Mapping[str, object]
        The parameters fixed over the whole map.
    mu : sequence of float
    axis : str
        The other parameter of the map (e.g. ``"Delta"``).
    values : sequence of float
    order, tol
        See :func:`predict_along_mu`.
    workers : int, optional
        Processes (default: the number of CPUs); 1 runs in this process.

    Returns
    -------
    list of tuple of EnergyPrediction
        ``out[i][j]``: the prediction at ``axis = values[i]``, ``mu = mu[j]``.

    Examples
    --------
    >>> out = map_predictions("sedf", {"beta": 1, "lam": 1}, [0.1, 0.05], "Delta", [0.01],
    ...                       workers=1)
    >>> [round(p.cycles[0].amplitude_max, 4) for p in out[0]]
    [2.0005, 2.0004]
    """
    jobs = [(model, {**params, axis: float(v)}, list(mu), dict(order=order, tol=tol))
            for v in values]
    workers = workers or os.cpu_count() or 1
    if workers == 1 or len(jobs) == 1:
        return [_column(j) for j in jobs]
    with ProcessPoolExecutor(max_workers=workers) as ex:
        return list(ex.map(_column, jobs))
