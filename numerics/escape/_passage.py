"""First passages of Langevin trajectories across two lines ``x = x_l``, ``x = x_r``, on the
executor.

Trajectory ``i`` has its own spawned seed (:mod:`numerics.noise.seeds`), so the times
are the same on any executor and chunking.  A trajectory starts at the well bottom, or
at a state drawn by ``start`` (e.g. :class:`numerics.escape.transitions.WellBoltzmann`)
from the first child of the trajectory's ``SeedSequence``.
"""

from __future__ import annotations

import numpy as np

from ..executor import chunk, map_chunks
from ..noise.langevin import langevin_system, steps_of
from ..noise.seeds import trajectory_states

__all__ = ["first_passages"]


def _task(task) -> list:
    model, params, D, first, count, dt, n_max, xl, xr, seed, start, stream = task
    system = langevin_system(model, params, D)
    y0 = np.zeros((count, 2)) if start is None else start.draw(seed, first, count, stream)
    times, hit = system.kernels.first_passages(system._p(), system.sigma, y0, 0.0, dt, n_max,
                                               xl, xr,
                                               trajectory_states(seed, first, count, stream))
    return [(float(times[i]), bool(hit[i])) for i in range(count)]


def first_passages(split, D: float, saddles, *, trajectories: int, t_end: float, dt: float,
                   seed: int = 0, executor=None, workers: int | None = None,
                   progress: bool = False, start=None,
                   stream: tuple = ()) -> tuple[np.ndarray, np.ndarray]:
    """``(min(tau_i, t_end), escaped_i)``: the first time ``x <= x_l`` or ``x >= x_r``.

    Parameters
    ----------
    split : kbm.model.conservative.ConservativeSplit
    D : float
    saddles : (x_l, x_r)
        The lines (the saddles, or the next wells' bottoms).
    trajectories : int
    t_end, dt : float
        ``t_end`` is rounded up to a whole number of steps.
    seed : int
    start : object or None
        ``None``: every trajectory starts at the well bottom ``x = x' = 0``; else an object
        whose ``draw(seed, first, count, stream)`` gives the ``(count, 2)`` starting states.
    stream : tuple of int
        Prefix of the trajectories' spawn keys (:func:`numerics.noise.seeds.trajectory_states`).
    """
    n_max = int(np.ceil(t_end / dt - 1e-9))
    steps_of(n_max * dt, dt)
    params = {**{k: float(v) for k, v in split.params.items()}, "mu": float(split.mu)}
    groups = chunk(list(range(int(trajectories))))
    tasks = [(split.model, params, float(D), g[0], len(g), float(dt), n_max,
              float(saddles[0]), float(saddles[1]), int(seed), start, tuple(stream))
             for g in groups]
    rows = map_chunks(_task, tasks, executor=executor, workers=workers, progress=progress,
                      desc="escapes", unit="trajectory", sizes=[len(g) for g in groups])
    return np.array([r[0] for r in rows]), np.array([r[1] for r in rows], dtype=bool)
