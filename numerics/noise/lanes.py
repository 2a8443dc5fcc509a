"""The kernels' loops over several trajectories at once, printed for a model.

A Langevin step is a chain of dependent operations (the kick waits for the force at the
new ``x``, the next position for the kick), so one trajectory a loop leaves the core mostly
idle; ``lanes`` independent trajectories in one loop body fill it.  numba has no register
arrays, so the loop of ``final_states`` is written out lane by lane as source
(:func:`lanes_source`) and appended by :mod:`numerics.noise.codegen` after the kernels it
calls (:mod:`numerics.noise._kernels`).  Each lane performs the operations of its
trajectory alone, on its own generator, so every number is the one the trajectory has
alone (``tests/test_noise_kernels.py``).  The number of lanes is chosen from the library
calls of one step (:func:`lane_count`).
"""

from __future__ import annotations

import sympy as sp

from kbm.model.builtins import Oscillator
from kbm.symbols import xdot as V

__all__ = ["lane_count", "lanes_source"]


def lane_count(model: Oscillator, scheme: str) -> int:
    """Trajectories per loop by the library calls (``sin``, ``exp``, ...) of one step (BAOAB
    one force, Kloeden-Platen two accelerations): none, 6 (polynomial forces: each chain a
    few arithmetic latencies, six fill the core); one, 3 (three chains hide a call's
    latency, a fourth spills more than it gains); more, 2.  Measured on one core of a shared
    machine (CPU time, medians; ``benchmarks/bench_noise.py``): BAOAB on the CDC at rest
    with 2, 3, 4, 6 lanes 47, 52, 45, 44 M steps/s; on the quartic oscillator ``x'' = -x' -
    x - x^3`` 136, 203, 221, 298; Kloeden-Platen on the CDC 37, 34, 34, 33."""
    acc = model.acceleration()
    calls = len(sp.sympify(acc.subs(V, 0) if scheme == "baoab" else acc).atoms(sp.Function))
    calls *= 2 if scheme == "kp" else 1
    return 6 if calls == 0 else 3 if calls == 1 else 2


def _final(lanes: int) -> list[str]:
    js = range(lanes)
    lines = ["@njit(cache=True)",
             "def _advance_lanes(p, y0, t0, h, n, states, i, amp, out):",
             f'    """Trajectories ``i .. i + {lanes - 1}`` of ``final_states``, {lanes} a '
             'loop."""']
    for j in js:
        lines += [f"    s{j} = states[i + {j}].copy()",
                  f"    x{j}, v{j} = y0[i + {j}, 0], y0[i + {j}, 1]",
                  f"    f{j} = _first(t0, x{j}, v{j}, p)"]
    lines += ["    for k in range(n):", "        t = t0 + k * h"]
    lines += [f"        x{j}, v{j}, f{j} = _step(t, x{j}, v{j}, f{j}, h, _increment(s{j}, amp), p)"
              for j in js]
    lines += [f"    out[i + {j}, 0], out[i + {j}, 1] = _finite(x{j}, v{j})" for j in js]
    return lines


def lanes_source(lanes: int) -> str:
    """The source of ``LANES`` and of ``_advance_lanes(p, y0, t0, h, n, states, i, amp,
    out)``: ``n`` steps of trajectories ``i .. i + lanes - 1`` of ``final_states`` in one
    loop, every lane with its own generator (a copy of ``states[i + j]``) and scalar state,
    the final states written to ``out`` (NaN when non-finite).

    The stationary kernels (``_stats`` of :mod:`numerics.noise._pair_kernels`) stay two a
    loop: written out the same way in six lanes for van der Pol (Kloeden-Platen) and three
    for the CDC (BAOAB), they ran 1.02x and 0.99x as fast as two a loop (medians of 21
    interleaved rounds, CPU time, the same bytes).

    Raises
    ------
    ValueError
        For ``lanes < 1``.
    """
    if lanes < 1:
        raise ValueError(f"lanes must be >= 1, got {lanes}")
    return f"LANES = {lanes}\n\n\n" + "\n".join(_final(lanes)) + "\n"
