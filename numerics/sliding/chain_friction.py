"""Friction laws of pulled chains of sliders (``sedf-dimer``, ``sedf-chain-N``).

Every slider of the chain hangs on its own spring ``Omega^2 (v t - x_i)`` from the stage,
and neighbours are coupled by springs ``mu kappa``.  The kinetic friction per slider is the
mean spring force ``F = (1/N) sum_i <Omega^2 (v t - x_i)>`` over a window of whole stage
periods ``lam/v`` after a transient; the window is doubled until its two halves agree
(``steady``), as for one slider (:mod:`numerics.sliding.friction`).  The start is the rest
state with each slider displaced by a small amount drawn from its own seed (numpy
``SeedSequence`` spawned per velocity and slider), so that a chain need not stay
synchronised by symmetry and no result depends on the executor or the chunking.

With ``kappa = 0`` the chain is ``N`` independent ``sedf_comoving`` sliders, whose law
:func:`numerics.sliding.friction.friction_point` computes by another route: the check of
``tests/test_coupled_friction.py``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from kbm.model.coupled import CoupledOscillators
from kbm.errors import ParameterError
from kbm.output.strict_json import Rendered
from numerics.executor import chunk, map_chunks
from numerics.flow.coupled_flow import bind_coupled, coupled_flow

__all__ = ["ChainFrictionPoint", "chain_friction_point", "chain_friction_law"]

#: a spring force above this many times ``Delta + Omega^2 lam + mu v`` is a runaway (the
#: criterion of numerics.sliding.friction)
RUNAWAY_FORCE = 10.0

#: amplitude of the seeded displacement of each slider at the start (in units of lam)
KICK = 0.05


@dataclass(frozen=True)
class ChainFrictionPoint(Rendered):
    """The friction of a pulled chain at one stage velocity.

    ``mean_force`` is per slider; ``per_slider`` each slider's mean spring force;
    ``halves`` the mean force over the window's two halves; ``spread`` the largest
    difference between sliders' mean forces (0 when they move in step); ``wells`` the
    stage periods in the window; ``error`` why there is no result, or ``None``.
    """

    model: str
    v: float
    params: Mapping[str, float]
    mean_force: float = math.nan
    per_slider: tuple = ()
    halves: tuple = (math.nan, math.nan)
    steady: bool = False
    spread: float = math.nan
    wells: int = 0
    error: str | None = None

    mappings_as_given = True


def _start(n: int, lam: float, seed: int, index: int) -> np.ndarray:
    y = np.zeros(2 * n)
    for i in range(n):
        rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(index, i)))
        y[i] = KICK * lam * (2 * rng.random() - 1)
    return y


def chain_friction_point(model: CoupledOscillators | str, params: Mapping[str, object],
                         v: float, *, index: int = 0, seed: int = 0,
                         transient_wells: float = 20, transient_damping: float = 20,
                         wells: int = 20, max_doublings: int = 3, per_period: int = 48,
                         tolerance: float = 1e-2) -> ChainFrictionPoint:
    """The steady kinetic friction per slider of a pulled chain at the stage velocity ``v``.

    Parameters
    ----------
    model, params
        A pulled chain (``sedf-dimer``, ``sedf-chain-N``) and its parameters (``mu``,
        ``Delta`` or ``delta``, ``lam``, ``beta``, ``kappa``).
    v
        The stage velocity (> 0).
    index, seed
        The point's place in its law and the seed of the start's displacements.
    transient_wells, transient_damping
        The transient: ``max(transient_wells lam/v, transient_damping/mu)``.
    wells, max_doublings, tolerance
        The window (stage periods), doubled up to ``max_doublings`` times until its halves
        agree within ``tolerance`` (relative, or absolute below a force of 1).
    per_period
        Samples per natural period of the well's oscillation.

    Raises
    ------
    kbm.errors.ParameterError
        For ``v <= 0`` or unknown parameters.  A run that fails is not raised: the point
        carries the ``error``.
    """
    from numerics.errors import IntegrationError

    if not (math.isfinite(v) and v > 0):
        raise ParameterError(f"the stage velocity must be positive, got v = {v}")
    model, values = bind_coupled(model, {**dict(params), "v": v})
    if "v" not in model.parameters:
        raise ParameterError(f"{model.name!r} has no stage velocity v: the chains of sliders "
                             "(sedf-dimer, sedf-chain-N) are pulled")
    fl = coupled_flow(model, {**dict(params), "v": v})
    n = fl.dof
    mu = values["mu"]
    lam = 2 * math.pi / values["k"]
    Tw = lam / v
    t_fast = 2 * math.pi / math.sqrt(1 + values["delta"] * mu * values["k"])
    per_well = max(8, math.ceil(per_period * Tw / t_fast))
    base = dict(model=model.name, v=v, params={k: values[k] for k in sorted(values)})
    skip = math.ceil(max(transient_wells * Tw, transient_damping / mu) / Tw)
    try:
        y = fl.states(_start(n, lam, seed, index), skip * Tw, 1, rtol=1e-9, atol=1e-11)[-1]
        t0 = skip * Tw
        w = wells
        for attempt in range(max_doublings + 1):
            # the flow restarts its clock at 0: shift the state by whole wells (x -> x - m lam
            # and t -> t - m lam/v leave the pulled chain unchanged), keeping t0 for the force
            m = round(t0 / Tw)
            shifted = y.copy()
            shifted[:n] -= m * lam
            ys = fl.states(shifted, w * Tw, w * per_well, rtol=1e-9, atol=1e-11)
            ts = np.arange(w * per_well + 1) * (Tw / per_well)
            force = v * ts[:, None] - ys[:, :n]  # Omega = 1
            limit = RUNAWAY_FORCE * (values["delta"] * mu + lam + mu * v)
            worst = np.max(np.abs(force), axis=0)
            if np.any(worst > limit) or not np.all(np.isfinite(worst)):
                i = int(np.argmax(worst))
                return ChainFrictionPoint(**base, wells=w, error=(
                    f"runaway: the spring force of slider {i + 1} reached {worst[i]:.4g}, "
                    f"above {RUNAWAY_FORCE:g} (Delta + Omega^2 lam + mu v) = {limit:.4g}; the "
                    "self-excitation outgrows the pull, and there is no bounded sliding "
                    "state (as for one slider, regime 'runaway')"))
            wts = np.full(len(ts), 1.0)
            wts[[0, -1]] = 0.5
            wts /= wts.sum()
            # weighted sums by numpy's pairwise summation, not BLAS (whose threads change
            # the order of the additions, and so the last bits, from one machine to another)
            per = np.sum(force * wts[:, None], axis=0)
            half = w * per_well // 2

            def mean_of(rows, weights):
                return float(np.mean(np.sum(rows * (weights / weights.sum())[:, None], axis=0)))

            h1 = mean_of(force[:half + 1], wts[:half + 1])
            h2 = mean_of(force[half:], wts[half:])
            mean = float(np.mean(per))
            steady = abs(h1 - h2) <= tolerance * max(1.0, abs(mean))
            if steady or attempt == max_doublings:
                return ChainFrictionPoint(**base, mean_force=mean,
                                          per_slider=tuple(float(f) for f in per),
                                          halves=(h1, h2), steady=bool(steady),
                                          spread=float(np.ptp(per)), wells=w)
            y = ys[-1].copy()
            y[:n] += m * lam
            t0 += w * Tw
            w *= 2
    except IntegrationError as exc:
        return ChainFrictionPoint(**base, error=str(exc))
    raise AssertionError("unreachable")  # pragma: no cover


def _chunk(job) -> list[ChainFrictionPoint]:
    model, params, items, seed = job
    return [chain_friction_point(model, params, v, index=i, seed=seed) for i, v in items]


def chain_friction_law(model: str, params: Mapping[str, object], velocities: Sequence[float],
                       *, seed: int = 0, executor=None, workers: int | None = None,
                       progress: bool = False) -> list[ChainFrictionPoint]:
    """:func:`chain_friction_point` at every stage velocity, on an executor (a local pool,
    any :class:`concurrent.futures.Executor` or a Dask client); the same points, in order,
    whatever runs them.

    Raises
    ------
    kbm.errors.ParameterError
        For a bad velocity or parameter (checked before anything runs).
    """
    vs = [float(v) for v in velocities]
    bad = [v for v in vs if not (math.isfinite(v) and v > 0)]
    if bad:
        raise ParameterError(f"the stage velocities must be positive, got {bad[0]}")
    bind_coupled(model, {**dict(params), "v": vs[0] if vs else 1.0})
    items = list(enumerate(vs))
    chunks = [(model, dict(params), part, seed) for part in chunk(items, largest=4)]
    return map_chunks(_chunk, chunks, executor=executor, workers=workers, progress=progress,
                      desc=f"{model} friction", sizes=[len(c[2]) for c in chunks])
