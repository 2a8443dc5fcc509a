"""Step 5 of the stationary ladder of
:func:`._stationary_orthonormal.stationary_orthonormal` predicted (:func:`direct_grid`):
for a folded model with saddles whose Hermite ladder on the first grid has come within
:data:`._stationary_orthonormal.EARLY_CHECK`, the grid is chosen by the layers'
resolution rule (:data:`GRID_RULE`) and solved at once with its check pair beside it,
instead of every grid 1.25 times finer in turn.

The rule.  The error of the grid sits in the separatrices' layers
(:mod:`._stationary_points`), of width ``l = (D/omega_b)^(1/2)/omega_b`` at a saddle of
frequency ``omega_b``; the map of the points puts a fixed share of them within a few
``l`` of each saddle, so the intervals for a given error grow like ``L/l``.  The grids
of the 1.25 ladder that first moved ``<x^2>`` and ``<v^2>`` by less than ``tol = 1e-8``
(SEDF at rest, Delta = 3, D = mu/2, the 1.25 ladder before this prediction): mu = 0.1,
128 functions, 448 intervals (6.5e-9 from 358), ``L/l`` = 258; mu = 0.05, 704 (6.3e-9
from 562; 562 moved them by 5.0e-8), ``L/l`` = 365; mu = 0.02, beyond the budget's 740
(5.4e-7 from 592), ``L/l`` = 577.  ``GRID_RULE`` ``L/(12 l)`` (``12 l``, the width the
map gives a saddle, :data:`._stationary_points.LAYER_WIDTHS`) is 430, 608 and 961
intervals there: the grids 448, 704 and (the budget's) 740 of the ladder, each solved
with the grid 1.25 times coarser (the Chebyshev change) and the next Hermite rung on the
finest grid below it that the budget affords (the Hermite change), the same three
solves the ladder ended with, so the same solution and bytes.  The prediction does not
state the error: when the Chebyshev change exceeds ``tol`` the ladder goes on from there
as before (one grid 1.25 times finer at a time), and the checks of step 6 and the climbs
of step 7 follow as they did.

Cost (2-core AMD EPYC, workers 2, SEDF mu = 0.02, D = 0.01): the grids 376 and 472
(2.3 s CPU) are not solved, and the Hermite check (258 x 592, 3.6 s) runs beside the
solution (182 x 740) and its coarser grid (182 x 592) instead of after them.
"""

from __future__ import annotations

import math

__all__ = ["GRID_RULE", "FUNCTION_RULE", "direct_grid", "direct_climb"]

#: the intervals of the predicted grid per width the map gives a saddle's layer
#: (``12 l``, :data:`._stationary_points.LAYER_WIDTHS`) in the half-range ``L``: the
#: module docstring's fit of the grids where the SEDF's ladder met ``tol = 1e-8``
GRID_RULE = 20.0
#: the share of the rule's ``pi V/delta`` functions (:func:`._stationary_points.rule_functions`,
#: at the pilot's ``<v^2>``) from which the Hermite change of the next rung is within six
#: digits (SEDF at rest, Delta = 3, D = mu/2: the rungs 182, 258, 364 at mu = 0.015,
#: 0.01, 0.005 are 0.32, 0.36 and 0.35 of it and their changes to the next rung within
#: six digits; the rungs below, 182 and 258 at mu = 0.01 and 0.005, 0.25 of it, moved
#: the moments by 1e-5 and 2.7e-6); the predicted climb takes the first rung at least
#: this share, halfway between
FUNCTION_RULE = 0.28


def direct_grid(solve, start, moved, cost, plan: list, sol, nh: int, nc: int,
                m_rule: float, max_cost: float):
    """The grid of the rule and its checks: ``(plan, sol, nc, cheb_change, rungs)`` for
    the ladder of :func:`._stationary_orthonormal.stationary_orthonormal` to go on with.

    ``plan`` (the folded ladder's grids above the first, ``nc``, 1.25 apart) gives the
    grid: the first at least ``m_rule`` (the last when none is).  ``nh`` functions are
    solved there and on the grid below it (the Chebyshev change, ``cheb_change``), and on
    the finest grid below it where ``nh 2^(1/2)`` functions are affordable too, whose
    solve (the Hermite check of step 6, collected by the caller) starts first in the
    second process (``start``, :mod:`._ahead`).  ``rungs`` maps those grids to their
    ``nh``-function solutions; ``plan`` keeps the grids above the chosen one.
    ``solve(n, m)``, ``moved(coarse, fine)`` and ``cost(n, m)`` are the caller's;
    ``sol`` is the solution on ``nc``."""
    grids = [nc] + list(plan)
    i = max(1, next((j for j, g in enumerate(grids) if g >= m_rule), len(grids) - 1))
    m, below = grids[i], grids[i - 1]
    up = 2 * int(round(nh * math.sqrt(2) / 2))
    fit = [g for g in grids[:i] if cost(up, g) <= max_cost]
    if fit:
        start(up, max(fit))  # the largest solve, beside the two below
    fine = solve(nh, m)
    coarse = solve(nh, below) if below != nc else sol
    rungs = {below: coarse}
    if fit and max(fit) != below:
        rungs[max(fit)] = solve(nh, max(fit)) if max(fit) != nc else sol
    return grids[i + 1:], fine, m, moved(coarse, fine), rungs


def _rung(n: int) -> int:
    """The Hermite rung above ``n``: ``n 2^(1/2)``, even."""
    return 2 * int(round(n * math.sqrt(2) / 2))


def direct_climb(solve_well, start, moved, cost, nh: int, nc: int, n_rule: float,
                 max_cost: float, stated):
    """Step 7 predicted: when the first grid's last Hermite step moved the moments by
    more than :data:`._stationary_orthonormal.EARLY_CHECK` (the functions are far from
    six digits), the rung of the rule, the first of ``nh 2^(k/2)`` (``k`` = 1 or 2) at
    least :data:`FUNCTION_RULE` ``n_rule``, solved at once as :func:`._stationary_climb.
    climb_rung` would end: on the largest grid within ``max_cost`` (the climb's budget)
    and the one 1.25 times coarser (the Chebyshev change), with the well's points
    (``solve_well``), and the next rung on the finest grid of 1.25 steps down from that
    coarser one it affords, against the rung there (the Hermite change; the largest
    grid's solve starts first, in the second process).  When that Hermite change exceeds six
    digits the prediction was short: the next rung is solved so in turn where affordable,
    and the solution of the smaller ``stated(hermite, grid)`` is kept.

    Returns ``(solution, hermite change, chebyshev change, pairs)`` as
    :func:`._stationary_climb.climb_rung`, or ``None`` (the ladder then checks and climbs
    as before) when the rule's rung is more than two above ``nh`` (a friction whose six
    digits are beyond the budget) or ``nh`` itself (the ladder's check at ``nh``, the
    climb of a grid: SEDF mu = 0.015) or its grids are not finer than ``nc``."""
    from ._energy_density import SIX_DIGITS

    if nh >= FUNCTION_RULE * n_rule:  # the rule's rung is ``nh``: the ladder's check
        return None
    n = _rung(nh)
    if n < FUNCTION_RULE * n_rule:
        n = _rung(n)
        if n < FUNCTION_RULE * n_rule:
            return None
    best = None
    for _ in range(2):
        here = _climbed(solve_well, start, moved, cost, n, nc, max_cost)
        if here is None:
            break
        if best is None or stated(here[1], here[2]) < stated(best[1], best[2]):
            best = here
        if here[1] <= SIX_DIGITS:
            break
        n = _rung(n)
    return best


def _climbed(solve_well, start, moved, cost, n: int, nc: int, max_cost: float):
    """``n`` functions on the largest grid within ``max_cost`` and the one 1.25 times
    coarser, and the next rung's check (:func:`direct_climb`), or ``None``."""
    top = 2 * int(math.sqrt(max_cost / n))
    below = 2 * int(top / 2.5)
    up = _rung(n)
    k = below
    while k > nc and cost(up, k) > max_cost:
        k = 2 * int(k / 2.5)
    if below <= nc or k <= nc:
        return None
    start(n, top, True)  # the largest solve, beside the two others (SEDF mu = 0.01:
    # 258 x 1040 5.3 s beside 364 x 832 and 258 x 832, 4.6 s and 3.2 s)
    check = solve_well(up, k)
    coarse = solve_well(n, below)
    pair = (coarse if k == below else solve_well(n, k), check)
    fine = solve_well(n, top)
    return fine, moved(*pair), moved(coarse, fine), [(coarse, fine), pair]
