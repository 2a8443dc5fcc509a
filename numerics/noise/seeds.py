"""One random stream per trajectory, spawned from one root seed.

Trajectory ``i`` of a run with root seed ``s`` draws from the generator whose state
is ``numpy.random.SeedSequence(s, spawn_key=(i,)).generate_state(4, uint64)``: the
``i``-th child of ``SeedSequence(s).spawn(...)`` (numpy's documented spawning rule).
A trajectory's numbers therefore depend on ``(s, i)`` alone, never on the chunk, the
worker or the executor that runs it.
"""

from __future__ import annotations

import numpy as np

from kbm.errors import ParameterError

__all__ = ["trajectory_states", "check_seed"]


def check_seed(seed: object) -> int:
    """The root seed as a non-negative int.

    Raises
    ------
    kbm.errors.ParameterError
    """
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ParameterError(f"the seed must be an integer >= 0, got {seed!r}")
    return int(seed)


def trajectory_states(seed: int, first: int, count: int, stream: tuple = ()) -> np.ndarray:
    """xoshiro256** states (``count`` x 4, uint64) of trajectories ``first .. first+count-1``.

    ``stream`` prefixes the spawn key (e.g. a grid point's index: ``SeedSequence(seed,
    spawn_key=(j, i))`` for trajectory ``i`` of point ``j``)."""
    seed = check_seed(seed)
    out = np.empty((count, 4), dtype=np.uint64)
    for j in range(count):
        st = np.random.SeedSequence(seed, spawn_key=(*stream, first + j)).generate_state(4, np.uint64)
        if not st.any():  # the one state xoshiro cannot leave (probability 2**-256)
            st[0] = np.uint64(1)
        out[j] = st
    return out
