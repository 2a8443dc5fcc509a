"""Step 7 of the stationary ladder of
:func:`._stationary_orthonormal.stationary_orthonormal` (its docstring says when and why):
the climb of a Hermite rung (:func:`climb_rung`) or of a grid (:func:`climb_grid`) on the
points with a centre at the deepest well (:func:`._stationary_points.stationary_points`
with ``well``), and the ladders' next number of intervals (:func:`finer_intervals`).  The
solves come from the caller (``solve(n, m)``, ``solve_well(n, m)``), as the measure of a
change (``moved(coarse, fine)``) and the cost of a size (``cost(n, m)``)."""

from __future__ import annotations

import math

from ._energy_density import SIX_DIGITS

__all__ = ["climb_rung", "climb_grid", "finer_intervals", "stated_error"]


def climb_rung(solve, solve_well, moved, cost, pairs, up: int, k: int, change: float,
               nc: int, max_cost: float, start=None):
    """The climb of a Hermite rung: when the Hermite change of step 6 (``up`` functions
    against the last rung on ``k`` intervals, the last pair of ``pairs``) exceeds six
    digits (the caller's test), the rung ``up`` on the largest grid within ``max_cost``
    and the one 1.25 times coarser (both finer than the last grid ``nc``) on the well's
    points (``solve_well``), and the rung above ``up`` on ``k``.  Returns ``(solution,
    hermite change, chebyshev change, pairs)``, or ``None`` when the grids are not
    affordable.  When that rung above moves the moments by more than six digits, it is
    solved again on the coarser climb grid (the well's points), whose change is stated;
    when that change too exceeds six digits, the rung above may climb in turn
    (:func:`_climb_again`), and the solution is the one of the smaller stated error.
    ``start(n, m, well, replace)``, where given, begins a solve in a second process
    (:mod:`._ahead`): the largest grid's, beside the coarser one and the rung above."""
    top = 2 * int(math.sqrt(max_cost / up))
    below = 2 * int(top / 2.5)
    up2 = 2 * int(round(up * math.sqrt(2) / 2))
    if below <= nc or cost(up2, k) > max_cost:
        return None
    if start is not None:  # (a solve started for the ladder that climbs is stopped)
        start(up, top, True, replace=True)
    coarse = solve_well(up, below)
    above = solve(up2, k)
    pair = (pairs[-1][1], above)
    again = None
    if moved(*pair) > 1e-6 and cost(up2, below) <= max_cost:
        # the rung above on the coarser climb grid instead: at low friction ``k`` does not
        # resolve the layers of ``up2`` functions (SEDF mu = 0.002, D = 0.001, scale 0.191:
        # 258 against 364 functions moved <x^2> by 1.9e-3 on 592 intervals, where 364
        # lost the solution, and by 1.5e-4 on 832 with the well's points)
        pair = (coarse, solve_well(up2, below))
        again = _climb_again(solve_well, moved, cost, pair, up2, below, change, nc, max_cost)
        if again is not None and stated_error(again[1], again[2]) < moved(*pair):
            return again  # below the least error the rung ``up`` can state
    fine = solve_well(up, top)
    here = fine, moved(*pair), moved(coarse, fine), [(coarse, fine), pair]
    if again is not None and stated_error(again[1], again[2]) < stated_error(here[1], here[2]):
        return again
    return here


def _climb_again(solve_well, moved, cost, pair, up: int, k: int, before: float, nc: int,
                 max_cost: float):
    """The climb of the rung ``up`` above the climbed one, when its change ``moved(*pair)``
    (against the rung below on ``k`` intervals) exceeds six digits and the last two Hermite
    changes, ``before`` and it, extrapolate geometrically to within six digits at the next
    rung: ``up`` on the largest grid within ``max_cost`` and the one 1.25 times coarser
    (the well's points), and the next rung on the finer of ``k`` and that coarser grid where
    it is affordable, against ``up`` there.  Returns as :func:`climb_rung`, or ``None``.
    (SEDF at rest, Delta = 3, D = mu/2: the changes 182 -> 258 -> 364 fell from 4.4e-4 to
    2.7e-6 at mu = 0.005, where the extrapolation is 1.7e-8, but from 4.5e-4 to 1.5e-4 at
    mu = 0.002, where it is 5e-5 and no climb is made.)"""
    change = moved(*pair)
    if not SIX_DIGITS < change < before or change**2 / before > SIX_DIGITS:
        return None
    top = 2 * int(math.sqrt(max_cost / up))
    below = 2 * int(top / 2.5)
    up2 = 2 * int(round(up * math.sqrt(2) / 2))
    checks = [g for g in (k, below) if cost(up2, g) <= max_cost]
    if below <= nc or not checks:
        return None
    at = max(checks)
    check = (solve_well(up, at), solve_well(up2, at))
    coarse, fine = solve_well(up, below), solve_well(up, top)
    return fine, moved(*check), moved(coarse, fine), [(coarse, fine), check]


def stated_error(hermite: float, grid: float) -> float:
    """The stated error of two changes, as :func:`._stationary_orthonormal.stationary_orthonormal`
    states it: their sum (both errors are in the solve)."""
    return hermite + grid


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
