"""First passages of Langevin trajectories over the saddles, on the executor.

Trajectory ``i`` has its own spawned seed (:mod:`numerics.noise.seeds`), so the times
are the same on any executor and chunking.
"""

from __future__ import annotations

import numpy as np

from ..executor import chunk, map_chunks
from ..noise.langevin import langevin_system, steps_of
from ..noise.seeds import trajectory_states

__all__ = ["first_passages"]


def _task(task) -> list:
    model, params, D, first, count, dt, n_max, xl, xr, seed = task
    system = langevin_system(model, params, D)
    y0 = np.zeros((count, 2))
    times, hit = system.kernels.first_passages(system._p(), system.sigma, y0, 0.0, dt, n_max,
                                               xl, xr, trajectory_states(seed, first, count))
    return [(float(times[i]), bool(hit[i])) for i in range(count)]


def first_passages(split, D: float, saddles, *, trajectories: int, t_end: float, dt: float,
                   seed: int = 0, executor=None, workers: int | None = None,
                   progress: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """``(min(tau_i, t_end), escaped_i)`` of trajectories started at the well bottom.

    Parameters
    ----------
    split : kbm.conservative.ConservativeSplit
    D : float
    saddles : (x_l, x_r)
    trajectories : int
    t_end, dt : float
        ``t_end`` is rounded up to a whole number of steps.
    seed : int
    """
    n_max = int(np.ceil(t_end / dt - 1e-9))
    steps_of(n_max * dt, dt)
    params = {**{k: float(v) for k, v in split.params.items()}, "mu": float(split.mu)}
    groups = chunk(list(range(int(trajectories))))
    tasks = [(split.model, params, float(D), g[0], len(g), float(dt), n_max,
              float(saddles[0]), float(saddles[1]), int(seed)) for g in groups]
    rows = map_chunks(_task, tasks, executor=executor, workers=workers, progress=progress,
                      desc="escapes", unit="trajectory", sizes=[len(g) for g in groups])
    return np.array([r[0] for r in rows]), np.array([r[1] for r in rows], dtype=bool)
