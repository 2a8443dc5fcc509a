"""Step 7 of the stationary ladder of
:func:`._stationary_orthonormal.stationary_orthonormal` (its docstring says when and why):
the climb of a Hermite rung (:func:`climb_rung`) or of a grid (:func:`climb_grid`) on the
points with a centre at the deepest well (:func:`._stationary_points.stationary_points`
with ``well``), and the ladders' next number of intervals (:func:`finer_intervals`).  The
solves come from the caller (``solve(n, m)``, ``solve_well(n, m)``), as the measure of a
change (``moved(coarse, fine)``) and the cost of a size (``cost(n, m)``)."""

from __future__ import annotations

import math

__all__ = ["climb_rung", "climb_grid", "finer_intervals"]


def climb_rung(solve, solve_well, moved, cost, pairs, up: int, k: int, change: float,
               nc: int, max_cost: float):
    """The climb of a Hermite rung: when the Hermite change of step 6 (``up`` functions
    against the last rung on ``k`` intervals, the last pair of ``pairs``) exceeds six
    digits (the caller's test), the rung ``up`` on the largest grid within ``max_cost``
    and the one 1.25 times coarser (both finer than the last grid ``nc``) on the well's
    points (``solve_well``), and the rung above ``up`` on ``k``.  Returns ``(solution,
    hermite change, chebyshev change, pairs)``, or ``None`` when the grids are not
    affordable.  When that rung above moves the moments by more than six digits, it is
    solved again on the coarser climb grid (the well's points), whose change is stated."""
    top = 2 * int(math.sqrt(max_cost / up))
    below = 2 * int(top / 2.5)
    up2 = 2 * int(round(up * math.sqrt(2) / 2))
    if below <= nc or cost(up2, k) > max_cost:
        return None
    coarse, fine = solve_well(up, below), solve_well(up, top)
    above = solve(up2, k)
    pair = (pairs[-1][1], above)
    if moved(*pair) > 1e-6 and cost(up2, below) <= max_cost:
        # the rung above on the coarser climb grid instead: at low friction ``k`` does not
        # resolve the layers of ``up2`` functions (SEDF mu = 0.002, D = 0.001, scale 0.191:
        # 258 against 364 functions moved <x^2> by 1.9e-3 on 592 intervals, where 364
        # lost the solution, and by 1.5e-4 on 832 with the well's points)
        pair = (coarse, solve_well(up2, below))
    return fine, moved(*pair), moved(coarse, fine), [(coarse, fine), pair]


def climb_grid(solve_well, moved, cost, pairs, n: int, nc: int, change: float,
               max_cost: float):
    """The climb of a grid, when the grid's change, not the Hermite change of step 6
    (``change``, the last pair of ``pairs``), exceeds six digits (the caller's test):
    the ``n`` functions on the last grid ``nc`` and on one 1.25 times finer, both with the
    points at the deepest well.  Returns as :func:`climb_rung`, or ``None`` when the finer
    grid costs more than ``max_cost``."""
    finer = finer_intervals(nc)
    if cost(n, finer) > max_cost:
        return None
    coarse, fine = solve_well(n, nc), solve_well(n, finer)
    return fine, change, moved(coarse, fine), [(coarse, fine), pairs[-1]]


def finer_intervals(nc: int) -> int:
    """The Chebyshev ladder's next number of intervals: 1.25 times, even."""
    return 2 * math.ceil(0.625 * nc)
