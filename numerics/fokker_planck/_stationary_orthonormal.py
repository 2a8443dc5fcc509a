"""The stationary Kramers equation of a nonlinearly damped model with its sizes chosen and
measured (:func:`stationary_orthonormal`, what :func:`.kramers.stationary_kramers` runs when
the damping is not ``-gamma x'``): the ladders of Hermite truncations and of position grids
over the single solves of :mod:`._stationary_solve` (the basis, the Galerkin operator and
the inverse iteration are described there), and step 7 in :mod:`._stationary_climb`.
"""

from __future__ import annotations

import dataclasses
import functools
import math

from ._solution import moments_moved
from ._energy_density import SIX_DIGITS
from ._ahead import Ahead, Later, fp_workers
from ._stationary_climb import stated_error, climb_grid, climb_rung, finer_intervals
from ._stationary_direct import GRID_RULE, direct_climb, direct_grid
from ._stationary_points import ALPHA, rule_functions, stationary_points
from ._stationary_solve import OrthonormalKramersSolution, orthonormal_stationary

__all__ = ["stationary_orthonormal"]


#: the first Hermite truncation of the ladder (:func:`._problem.hermite_ladder`)
FIRST_HERMITE = 32
#: the share of the last Chebyshev change below which the Hermite change of the previous
#: rung lets the grid ladder go on at that rung (step 5 of :func:`stationary_orthonormal`)
GRID_BOUND = 0.1
#: the largest ``N n_cheb^2`` (unfolded) of a rung of the Hermite ladder, which runs on the
#: first grid: at low friction that grid does not resolve the layers of more functions (SEDF
#: mu = 0.03, D = 0.015 on 266 intervals: <x^2> moved by 2.9e-6 from 128 to 182 functions,
#: by 2.9e-5 to 256, by 2e-3 to 362, and 512 lost the solution)
HERMITE_COST = 2.5e7
#: the budget of step 7 (the Hermite rung up when the check of step 6 exceeds six digits),
#: in units of ``max_cost``: with kbm noise's 2.5e7 the SEDF at mu = 0.01, D = 0.005 climbs
#: to 258 functions on 1040 intervals (folded cost 6.8e7)
CLIMB_COST = 2.8
#: the floor of the stated change: the rounding of the moments of one solve (vdp mu = 0.03,
#: D = 0.015: 90 x 120 and 136 x 180 differ by 1.2e-11 where the ladders moved by 9e-12)
ROUNDING = 1e-10
#: the Hermite change of step 7's check beyond which the climb is not made: no digits of use
#: are within the budget (SEDF at rest, Delta = 3, mu = 0.002, D = 0.001, at the scale of
#: the resolution rule alone, 0.136: 182 against 258 functions on 592 intervals moved
#: <v^2> by 0.36; the climb without the scale's floor to 258 x 1040 then spent 67 s and
#: 2.9 GB in kbm noise on a stated 0.14, <a^2> = 3.669 against 4.005; stopped at the
#: check, 8.6 s CPU, 0.7 GB); the solve keeps no ``refine`` then (no grid step more for P(E))
HOPELESS = 1e-2
#: the last Hermite change on the first grid above which step 6's check is made first, on
#: its grid, and the grids below it at that ``N`` are not solved when it climbs (step 7):
#: the functions are then far from six digits and the grid ladder does not stop at ``tol``
#: before that grid (SEDF at rest, Delta = 3, D = mu/2, 266 intervals, 128 -> 182
#: functions: the moments moved by 4.4e-2 at mu = 0.01, whose grid steps at 182 then moved
#: them by 3.7e-3, 7.0e-5, 6.4e-5 up to 592, where the check climbs; by 8.1e-5 at
#: mu = 0.02, whose check does not climb).  It saves those grids' solves, 1.7 s of 50 at
#: mu = 0.01, the same solution and bytes
EARLY_CHECK = 1e-3
#: the last grid step's change within which the ladder starts step 6's check beside the
#: next grid's solve (:mod:`._ahead`; the check is wasted if the ladder goes on)
AHEAD = 10
#: the fewest position intervals of the Hermite ladder: on fewer the grid's own error
#: moves the moments and the ladder climbs for nothing (vdp mu = 0.3, D = 0.15: on 64
#: intervals it went to 1448 functions, on 88 it stops at 512)
MIN_INTERVALS = 96


def stationary_orthonormal(split, D: float, G, omega0: float, *, n_hermite: int | None,
                           n_cheb: int | None, sigma: float | None, L: float | None,
                           tol: float, max_cost: float, workers: int | None = None,
                           refine_ahead: bool = False) -> OrthonormalKramersSolution:
    """The stationary Kramers solve of a nonlinear damping with its sizes chosen and
    measured (what :func:`.kramers.stationary_kramers` runs for it).

    1. The range ``L``: where ``G`` exceeds its minimum by ``45 D/mu``
       (:func:`.kramers._half_width`; a pilot's marginal is not small enough at its ends
       to place it: a 64-function solve of the SEDF is 1e-5 of its peak there, of either
       sign).  A pilot (32 functions at ``s = (D/mu)^(1/2)``) measures ``<v^2>``.
    2. The velocity scale (:func:`._stationary_points.stationary_points`, as
       :func:`._orthonormal.velocity_scale`): ``N`` functions reach ``s (2N)^(1/2)`` and
       resolve ``pi s/(2N)^(1/2)``; the density reaches ``V = 5 <v^2>^(1/2)`` and has
       velocity structure of width ``delta = (D/omega)^(1/2)``, ``omega^2`` the largest
       ``|g'|`` on the range; both are resolved at ``s = (delta V/(2 pi))^(1/2)``.  (With
       ``V = 6 <v^2>^(1/2)`` the SEDF at mu = 0.1, Delta = 3, D = 0.05 moved by 7e-6 from
       90 to 128 functions, with 5 by 3e-7.)  At least ``2.8 (<v^2>/516)^(1/2)``: below
       mu = 0.01 the rule's functions are beyond the budget and the 258 of the last rung
       must still reach the density (:data:`._stationary_points.TOP_REACH`; SEDF
       mu = 0.002: <a^2> 3.669 at the rule's 0.136, 4.00536 at the floor's 0.191).
    3. The points: :func:`._bases.cheb_centred` around the saddles and their separatrices'
       outer turning points (:mod:`._stationary_points`), else :func:`._bases.cheb_mapped`;
       half the number of :func:`.kramers._chebyshev_size` on ``exp(-G mu/D)``, at least
       :data:`MIN_INTERVALS`.  A model symmetric under ``(x, v) -> (-x, -v)`` is solved
       folded (:mod:`._parity`), and its cost is ``N (n_cheb/2)^2``, else ``N n_cheb^2``
       (the numbers the LU keeps, about; its work is that times the points).
    4. The Hermite ladder (``32 * 2^(k/2)``, from 64 where the budget allows) on those
       intervals until two rungs' ``<x^2>`` and ``<v^2>`` agree to ``tol`` or the next
       would leave no room for a grid 1.25 times finer, or for two once the change is
       below :data:`SIX_DIGITS`, within ``max_cost`` and :data:`HERMITE_COST` counted
       unfolded (the first grid does not resolve the layers of more functions at low
       friction).
    5. The grid ladder at that ``N`` until the moments agree to ``tol`` or the budget
       ends.  Folded, its grids are the largest within ``max_cost`` and those 1.25, 1.25^2,
       ... times coarser (the last step is a whole one: SEDF mu = 0.02, D = 0.01, 182
       functions: 656 -> 740 intervals moved <v^2> by 1.0e-7, and 740 was 1.2e-7 from
       256 x 1026; 592 -> 740 moved it by 5.4e-7).  Unfolded, the intervals grow by 1.25;
       when the next grid is beyond the budget at the last rung but not at the previous
       one, the previous rung is solved on the last points, and if it moved the moments
       by less than :data:`SIX_DIGITS` and a tenth (:data:`GRID_BOUND`) of the last
       Chebyshev change the ladder goes on at that rung.
    6. The Hermite change: folded, the next rung up (``N 2^(1/2)``) on the finest grid of
       the ladder that affords it (at low friction the rung below is too few: SEDF
       mu = 0.02 on 656 intervals, 128 -> 182 functions moved <x^2> by 3.7e-5 but
       182 -> 256 by 1e-9); unfolded, the previous rung on the last points.  The
       solution's ``hermite_change`` is the sum of the Hermite and last Chebyshev
       changes, at least :data:`ROUNDING` (``chebyshev_change`` the second): both errors
       are in the solve (SEDF mu = 0.002, 258 x 1040, the larger, 1.5e-4, is 1.1e-4 to
       1.6e-4 from 362 x 1200 at two scales and 300 x 1100; the sum is 2.9e-4; mu = 0.05,
       128 x 704: <v^2> is 3.1e-8 from 256 x 1200, the Hermite change 2.5e-8 and the
       grid's 6.3e-9, the sum 3.2e-8; before, the larger alone within six digits).  The pairs of
       solutions of those two changes are kept as its ``refinements`` (the same change of
       ``P(E)`` is its stated error, :mod:`._energy_density`), and the same solve on one
       grid step more as its ``refine`` (called only for ``P(E)`` when that change
       exceeds six digits: the grid's error moves ``P(E)`` more than the moments).
    7. The climb (folded, :mod:`._stationary_climb`): when that Hermite change exceeds
       :data:`SIX_DIGITS`, the functions were too few, not the grid.  The check is then
       made as soon as the grid ladder reaches its grid (the finer grids at ``N`` are not
       solved), and the rung ``N 2^(1/2)`` is solved on the largest grid within
       :data:`CLIMB_COST` ``max_cost`` and the one 1.25 times coarser, with points at the
       bottom of the deepest well too (:func:`._stationary_points.stationary_points` with
       ``well``); the rung above it on the check's grid states the Hermite change.  SEDF
       at rest, Delta = 3, D = 0.005 (mu = 0.01), kbm noise's budget: 182 functions
       against 258 on 592 intervals moved <x^2> by 3.6e-6; the climb gives
       258 x 1040, stated 2.9e-7 (the grid's 832 against 1040; 258 against 364 functions
       on 592: 1.3e-8), 1.3e-8 and 4e-9 in <x^2> and <v^2> from 362 x 1602, 26-32 s CPU
       (182 x 740 stated 9.6e-6 and was 7.1e-6 off).  The Hermite change of 256 against
       362 functions is 1e-8 to 6e-8 on every grid from 592 to 1282 intervals, so the
       coarse grid of the check does not understate it.  (Without the well's points,
       820 -> 1026 intervals at 256 functions moved <v^2> by 1.5e-6; at mu = 0.1 those
       points cost 448 -> 704 intervals for the same tol, so the first ladder keeps its
       points.)  When the Hermite change is within six digits but the grid's is not, the
       same ``N`` on the last grid and one 1.25 times finer, with the well's points
       (:func:`._stationary_climb.climb_grid`; mu = 0.015, D = 0.0075: 182 x 740 stated
       2.5e-6, the grid's 592 against 740; now 182 x 926, stated 3.9e-7, the Hermite
       change, 1.4e-7 and 1.8e-7 in <x^2> and
       <v^2> from 258 x 1282, 18 s CPU).  When the rung above the climbed one moves the
       moments by more than six digits on the check's grid, it is solved again on the
       coarser climb grid (:func:`._stationary_climb.climb_rung`); when that change too
       exceeds six digits and the last two Hermite changes extrapolate geometrically to
       within six digits, that rung climbs in turn, checked one rung up, and the solution
       of the smaller stated error is kept (the climb of a raised ``--fp-budget`` at
       mu = 0.005; :func:`._stationary_climb._climb_again`).  When step 7's check
       exceeds :data:`HOPELESS`, the ladder stops there (no climb, no finer grid) and
       states that change.  When the first grid's last Hermite step moved the moments by
       more than :data:`EARLY_CHECK`, the check is made before the grid ladder, on its
       grid, and a climb skips the coarser grids at ``N`` (the same climb, fewer solves).

    Steps 5 and 7 predicted (folded with saddles, :mod:`._stationary_direct`): with the
    first grid's last Hermite step within :data:`EARLY_CHECK`, the grid of the layers'
    rule (:data:`._stationary_direct.GRID_RULE`) is solved at once with its coarser grid
    and step 6's check, and the ladder goes on from there only when its change exceeds
    ``tol``; beyond :data:`EARLY_CHECK` the rung of the rule
    (:data:`._stationary_direct.FUNCTION_RULE`, at most two above ``N``) goes straight to
    the climb's grids and its check one rung up, instead of the check and the climb.  The
    same solutions (SEDF at rest, Delta = 3, D = mu/2, mu = 0.1 to 0.005), fewer solves.

    Each solve factorises order by order (:mod:`._pentadiagonal`) when the damping is
    linear in the velocity, else by pairs of orders (:mod:`._blocks`).  Solves that do not
    depend on each other (step 7's check pair, the climb's largest grid beside its coarser
    one and the rung above, step 6's check beside the grid step it would follow) run side
    by side in a second process (:mod:`._ahead`, ``KBM_FP_WORKERS``, at most ``workers``
    processes; the same bits).  With ``refine_ahead`` (``P(E)`` will be wanted) the second
    process begins with the grid step of a climb's largest grid (``refine``, handed on for
    :func:`._energy_density.energy_density_report`), this process makes that grid and the
    climb's other solves (SEDF at rest, Delta = 3, D = mu/2, CPU per process, mu = 0.01:
    12.6 s beside 16.7 s, where the step after its grid was 19.7 s beside 9.6 s; 0.005,
    ``--fp-budget 8.6e7``: 82-89 s beside 75-77 s, was 112 s beside 45 s).
    """
    # the solves beside others (._ahead)
    with Ahead(orthonormal_stationary, workers=fp_workers(workers), G=G) as ahead:
        return _ladder(split, D, G, omega0, ahead, n_hermite=n_hermite, n_cheb=n_cheb,
                       sigma=sigma, L=L, tol=tol, max_cost=max_cost,
                       refine_ahead=refine_ahead)


def _ladder(split, D: float, G, omega0: float, ahead, *, n_hermite, n_cheb, sigma, L, tol,
            max_cost, refine_ahead=False) -> OrthonormalKramersSolution:
    """The body of :func:`stationary_orthonormal`, with ``ahead`` (:class:`._ahead.Ahead`)
    for the solves started beside others."""
    from ._bases import cheb_centred, cheb_mapped
    from ._model import _chebyshev_size, _half_width
    from ._parity import reflection_symmetric
    from kbm.errors import ModelError

    mu = float(split.mu)
    half = _half_width(G, D / mu) if L is None else float(L)
    nc_h = max(MIN_INTERVALS, 2 * math.ceil(_chebyshev_size(G, D / mu, half) / 4))
    pilot = orthonormal_stationary(split, D, math.sqrt(D / mu), half, FIRST_HERMITE,
                                   nc_h if n_cheb is None else int(n_cheb), G, omega0,
                                   alpha=ALPHA)
    v2 = pilot.v2
    if not (math.isfinite(v2) and v2 > 0):
        raise ModelError(f"the coarse Kramers solve gave <v^2> = {v2}: no stationary "
                         "density (check that the damping confines the motion)")
    sigma, points = stationary_points(split, D, G, half, v2, sigma)
    nc = nc_h if n_cheb is None else int(n_cheb)
    nh = FIRST_HERMITE if n_hermite is None else int(n_hermite)
    if "centres" in points:
        xs0 = cheb_centred(nc, half, ALPHA, points["centres"], points["widths"],
                           points["weight"])[0]
    else:
        xs0 = cheb_mapped(nc, half, ALPHA)[0]
    folds = reflection_symmetric(split, xs0)

    def cost(n, intervals):
        """``n`` times the squared intervals the LU factorises (half of them folded)."""
        return n * (intervals / 2 if folds and intervals % 2 == 0 else intervals) ** 2

    if cost(nh, nc) > max_cost:
        raise ModelError(f"the Kramers solve needs {nh} Hermite functions x {nc + 1} Chebyshev "
                         f"points (cost {cost(nh, nc):.3g} > {max_cost:.3g}): not affordable "
                         "here")
    if n_hermite is None and \
            cost(2 * nh, finer_intervals(nc) if n_cheb is None else nc) <= max_cost:
        nh *= 2  # the same rungs from 64 on (at 32 and 46 the SEDF and vdp cases never stop)

    memo = {}
    later = {}  # the grid steps of P(E) started for a climb's largest grid

    def solve(n, m, well=False, start=False, replace=False):
        """One solve (each once: step 6's check may come inside the grid ladder); with
        ``start`` begun in the second process, for a later call (:mod:`._ahead`), but for
        the well's (a climb's largest grid) with ``refine_ahead``: then its grid step is
        begun there instead, and the grid itself is solved here when asked for."""
        if well and "well" not in memo:
            memo["well"] = stationary_points(split, D, G, half, v2, sigma, well=True)[1]
        well = well and memo["well"] != points  # no saddles: the same points
        at = memo["well"] if well else points
        args = (split, D, float(sigma), half, n, m, G, omega0)
        if start:
            if refine_ahead and well and (n, m, well) not in memo:  # the step, not the grid
                later["P(E)", n, m, well] = step = (*args[:5], finer_intervals(m), *args[6:]), at
                return ahead.start(("P(E)", n, m, well), *step[0], replace=replace,
                                   later=True, **at) and False
            return (n, m, well) not in memo and ahead.start((n, m, well), *args,
                                                            replace=replace, **at)
        if (n, m, well) not in memo:
            memo[n, m, well] = ahead.result((n, m, well), *args, **at)
        return memo[n, m, well]

    def start(n, m, well=False, replace=False):
        return solve(n, m, well, start=True, replace=replace)

    def solve_well(n, m):  # step 7's points
        return solve(n, m, True)

    moved = moments_moved

    sol = solve(nh, nc)
    change = cheb_change = math.nan
    prev = nh
    pairs = []
    if n_hermite is None:
        change = math.inf
        first = nh
        for k in range(1, 13):  # first * 2^(k/2), even (as ._problem.hermite_ladder)
            n = 2 * int(round(first * 2 ** (k / 2) / 2))
            # one finer grid stays affordable; two once the change is within six digits
            # (the budget then goes to the grid: at the top truncations the saddle layers
            # need 1.25^2 times the first intervals; SEDF mu = 0.1, 128 functions: 266 ->
            # 334 moved <x^2> by 1.5e-6, 334 -> 418 by 6e-8)
            grids = 2 if change <= SIX_DIGITS else 1
            room = nc
            if n_cheb is None:
                for _ in range(grids):
                    room = finer_intervals(room)
            if n * room**2 > min(max_cost, HERMITE_COST):  # rungs the first grid resolves
                break
            new = solve(n, nc)
            pairs = [(sol, new)]  # the Hermite step (replaced below when the grid grows)
            change, sol, prev, nh = moved(sol, new), new, nh, n
            if change <= tol:
                break
    if n_cheb is None:
        cheb_change = math.inf
        lower = None  # the previous rung on the last points, once solved
        rungs = {}  # the coarser grids' solutions at the last number of functions
        plan = []
        climbed = None  # step 7's result
        hopeless = None  # step 7's check when it exceeds HOPELESS
        if folds:  # 1.25 steps down from the largest grid within the budget (step 5)
            top = 2 * int(math.sqrt(max_cost / nh))  # cost(nh, top) <= max_cost
            while top >= 1.25 * nc:  # every step a whole one
                plan.insert(0, top)
                top = 2 * int(top / 2.5)
        if folds and n_hermite is None and "centres" in points \
                and EARLY_CHECK < change < math.inf:
            climbed = direct_climb(solve_well, start, moved, cost, nh, nc,
                                   rule_functions(split, D, half, v2),
                                   CLIMB_COST * max_cost, stated_error)
        if folds and n_hermite is None and EARLY_CHECK < change < math.inf \
                and climbed is None:
            # step 6's check first, on the grid where the ladder would make it (step 7)
            up = 2 * int(round(nh * math.sqrt(2) / 2))
            at = [k for k, f in zip([nc] + plan, plan) if cost(up, k) <= max_cost < cost(up, f)]
            if at and at[0] > nc:
                start(up, at[0])  # the pair of the check side by side
                check = (solve(nh, at[0]), solve(up, at[0]))
                hc = moved(*check)
                if SIX_DIGITS < hc <= HOPELESS:
                    climbed = climb_rung(solve, solve_well, moved, cost, [check], up, at[0],
                                         hc, at[0], CLIMB_COST * max_cost, start)
        if folds and n_hermite is None and "centres" in points and plan \
                and change <= EARLY_CHECK and climbed is None:
            # step 5 predicted: straight to the grid of the rule, its check pair beside it
            plan, sol, nc, cheb_change, rungs = direct_grid(
                solve, start, moved, cost, plan, sol, nh, nc,
                GRID_RULE * half / min(points["widths"]), max_cost)
        while climbed is None and cheb_change > tol:
            finer = plan.pop(0) if plan else finer_intervals(nc)
            if cost(nh, finer) > max_cost:
                if n_hermite is None and prev < nh and lower is None and not folds \
                        and cost(prev, finer) <= max_cost:
                    # the grid at the previous rung (step 5)
                    lower = solve(prev, nc)
                    hc = moved(lower, sol)
                    if hc <= min(SIX_DIGITS, GRID_BOUND * cheb_change):
                        change, sol, nh, rungs = hc, lower, prev, {}
                        continue
                break
            up = 2 * int(round(nh * math.sqrt(2) / 2))
            if n_hermite is None and folds and cost(up, nc) <= max_cost < cost(up, finer):
                # step 6's check comes on this grid: climbing now saves the finer grids
                start(nh, finer)  # the next grid beside it (stopped if the check climbs)
                hc = moved(sol, solve(up, nc))
                if hc > HOPELESS:  # no digits of use within the budget: stop here
                    hopeless = hc
                    break
                if hc > SIX_DIGITS:
                    climbed = climb_rung(solve, solve_well, moved, cost,
                                         [(sol, solve(up, nc))], up, nc, hc, nc,
                                         CLIMB_COST * max_cost, start)
                if climbed is not None:
                    break
            fit = [k for k in [*rungs, nc] if cost(up, k) <= max_cost]
            if n_hermite is None and folds and fit and cheb_change <= AHEAD * tol \
                    and not ahead.running((nh, finer, False)):
                start(up, max(fit), replace=True)  # step 6's check if the ladder stops at
                # ``finer`` (an earlier one of a coarser grid stopped)
            new = solve(nh, finer)
            rungs[nc] = sol
            cheb_change, sol, nc = moved(sol, new), new, finer
        pairs = [(rungs[max(rungs)], sol)] if rungs else []  # the last grid step
        up = 2 * int(round(nh * math.sqrt(2) / 2))
        fits = [k for k in rungs if cost(up, k) <= max_cost]
        if hopeless is not None:
            change = hopeless
            pairs.append((sol, solve(up, nc)))
            cheb_change = cheb_change if math.isfinite(cheb_change) else math.nan
        elif climbed is not None:
            sol, change, cheb_change, pairs = climbed
        elif n_hermite is None and folds and fits:
            # the next rung up on the finest grid of the ladder that affords it (step 6)
            k = max(fits)
            pairs.append((rungs[k], solve(up, k)))
            change = moved(*pairs[-1])
            if SIX_DIGITS < change <= HOPELESS:
                climbed = climb_rung(solve, solve_well, moved, cost, pairs, up, k, change,
                                     nc, CLIMB_COST * max_cost, start)
            if climbed is None and cheb_change > SIX_DIGITS and rungs and change <= HOPELESS:
                climbed = climb_grid(solve_well, moved, cost, pairs, nh, nc, change,
                                      CLIMB_COST * max_cost)
            if climbed is not None:
                sol, change, cheb_change, pairs = climbed
        elif n_hermite is None and prev < nh:  # the Hermite change again on the last points
            same = lower is not None and lower.x.size == nc + 1
            pairs.append((lower if same else solve(prev, nc), sol))
            change = moved(*pairs[-1])
    parts = [c for c in (change, cheb_change) if not math.isnan(c)]
    stated = max(ROUNDING, sum(parts)) if n_hermite is None else math.nan  # both errors
    refine = None
    if n_hermite is None and pairs and pairs[0][1] is sol and stated <= HOPELESS \
            and pairs[0][0].coef.shape[0] == sol.coef.shape[0] \
            and pairs[0][0].x.size < sol.x.size:
        # the grid step beyond the last, for P(E) (._energy_density.energy_density_report)
        refine = functools.partial(
            orthonormal_stationary, split, D, float(sol.sigma), half, sol.coef.shape[0],
            finer_intervals(sol.x.size - 1), G, omega0, alpha=sol.alpha, centres=sol.centres,
            widths=sol.widths, weight=sol.weight)
        same = [k for k, (a, at) in later.items() if a == refine.args and at == {
            f: refine.keywords[f] for f in at}]  # the same call started ahead
        refine = Later(refine, ahead.hand_on(same[0]) if same else None)
    return dataclasses.replace(sol, hermite_change=stated, chebyshev_change=cheb_change,
                               refinements=tuple(pairs) if n_hermite is None else (),
                               refine=refine)
