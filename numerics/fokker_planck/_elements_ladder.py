"""The stationary Kramers solve on spectral elements with its sizes chosen and measured
(:func:`element_ladder`, what :func:`.kramers.stationary_kramers` runs for a nonlinear
damping whose potential has saddles on the range, the multi-well SEDF): a ladder of
Hermite truncations on a generous number of elements, then a ladder of elements at the
last truncation, over the single solves of :func:`._elements_solve.element_stationary`
(the discretisation in :mod:`._elements`).

Why elements there.  The Chebyshev ladder of :mod:`._stationary_orthonormal` needs one
global grid fine enough for the saddles' layers, whose width is ``(D/omega_b)^(1/2)``: at
low friction its sizes and LU grow as ``N m^2`` (SEDF at rest, Delta = 3, D = mu/2,
``kbm noise --method fokker-planck``: 41 s CPU at mu = 0.01, 146-173 s and 3.1 GB at
mu = 0.005).  Elements put the points where the layers are and factorise by static
condensation, ``~ N^3`` per interface node: the same six digits in seconds (the tables of
docs/noise.rst).

The ladder (measured, SEDF at rest, Delta = 3, D = mu/2; the changes are relative, the
larger of ``<x^2>`` and ``<v^2>``):

1. The range, the velocity scale and the centres of the element ends as the Chebyshev
   ladder's steps 1 to 3 (:func:`._stationary_points.stationary_points` with the deepest
   well, a pilot of 32 functions measuring ``<v^2>``).
2. ``E`` = :data:`ELEMENT_RULE` times ``L/l``, ``l`` the narrowest layer's width (even;
   without saddles a tenth of the Chebyshev ladder's first intervals), at least
   :data:`FEWEST`, degree :data:`DEGREE`.  ``L/l`` is 21.5, 68, 96 at mu = 0.1, 0.01, 0.005, where the moments
   were within 1e-7 of the converged ones on about 34, 84 and 140 elements.
3. The Hermite ladder ``64 * 2^(k/2)`` on those elements until two rungs' moments agree
   to ``tol`` (default :data:`TOL`, a tenth of six digits: the stated error is the sum of
   two changes) or the next rung with the element step of 4. would exceed the budget.
4. The element ladder at that truncation, ``E`` times :data:`ELEMENT_STEP` (even), until
   the change is within ``tol`` or the budget ends.
5. The stated error (``hermite_change``) is the sum of the last Hermite change (step 3,
   on the first elements) and the last element change (step 4, ``chebyshev_change``), at
   least :data:`ROUNDING`; the two pairs are the solution's ``refinements`` (their change
   of ``P(E)`` is its stated error, :mod:`._energy_density`), and the solve one element
   step finer its ``refine``: ``P(E)`` samples the separatrices' layers along one orbit
   and moves more than the moments under the element step (mu = 0.1: 128 functions on
   34 -> 42 elements moved ``P`` by 3.3e-6 of its peak near the separatrix energy, the
   moments by 6.4e-8), and :func:`._energy_density.energy_density_report` takes ``P``
   from that solve when its stated change exceeds six digits, as for the Chebyshev
   ladder's grid step.

The element step of the last rung is started beside that rung in a second process
(:mod:`._ahead`) when the last two Hermite changes extrapolate geometrically to within
``tol`` (the rung is then likely the last; the step is stopped when it is not), with
``refine_ahead`` followed there by the step after it (``refine``, handed on to
:func:`._energy_density.energy_density_report`): the same solves and bits, less wall
time.  The budget: ``N^2 E`` (the interface LU keeps about
``13 N^2`` numbers per element, :mod:`._elements_lu`; ``E/2`` when folded, :mod:`._parity`)
at most ``max_cost`` (512 functions on 72 folded elements: 1.9e7, about 1.9 GB); the
``refine`` of ``P(E)``, one element step beyond the last, may exceed it by that step, as
the Chebyshev ladder's grid step does (mu = 0.005: 512 x 210, 2.75e7; ``kbm noise`` peaked
at 2.3 GB).

Measured (SEDF at rest, Delta = 3, D = mu/2, against the Chebyshev ladder at the same
budget 2.5e7, both within the sum of the stated errors; CPU of the ladder and ``P(E)``
with the second process, load 4-6): mu = 0.1, 128 x 58 stated 9.1e-9 (Chebyshev 128 x 448,
1.8e-8), 3 s each; mu = 0.02, 256 x 90, 4.5e-8, 12 s (182 x 740, 5.5e-7, 15 s);
mu = 0.01, 362 x 124, 4.4e-8, 32 s (258 x 1040, 3.0e-7, 31 s); mu = 0.005, 512 x 176,
3.2e-7 and ``P(E)`` 9.7e-7 of its peak, 90 s (364 x 876, 3.9e-6 and 5.9e-5, 90 s; six
digits took it ``--fp-budget 8.6e7``, 146-173 s and 3.1 GB).
"""

from __future__ import annotations

import dataclasses
import functools
import math

from ._solution import moments_moved
from ._ahead import Ahead, Later, fp_workers
from ._elements_solve import ElementKramersSolution, element_stationary

__all__ = ["element_ladder", "ELEMENT_RULE", "ELEMENT_STEP", "DEGREE", "TOL"]

#: the first truncation of the Hermite ladder (then ``* 2^(1/2)``, even)
FIRST_FUNCTIONS = 64
#: the elements per ``L/l`` (step 2 of the module docstring)
ELEMENT_RULE = 1.5
#: the growth of the element ladder (step 4)
ELEMENT_STEP = 1.2
#: the degree of the elements (odd: :mod:`._elements`; 13 converged as 11 on fewer nodes)
DEGREE = 13
#: the default change at which each ladder stops (a tenth of six digits)
TOL = 1e-7
#: the floor of the stated change (the rounding of one solve's moments)
ROUNDING = 1e-10
#: the fewest elements: ``P(E)`` samples the separatrices' layers along one orbit and
#: needs more than the moments (SEDF mu = 0.1, D = 0.05, 128 functions: 34 -> 42 elements
#: moved ``P`` by 3.3e-6 of its peak near the separatrix energy, the moments by 6.4e-8, and
#: the report stated 1.6e-6 from 50; 48 -> 58 moved ``P`` by 5.0e-7, stated 5.0e-7)
FEWEST = 48


def element_ladder(split, D: float, G, omega0: float, *, sigma: float | None = None,
                   L: float | None = None, tol: float | None = None, max_cost: float = 2e7,
                   workers: int | None = None,
                   refine_ahead: bool = False) -> ElementKramersSolution:
    """The stationary Kramers solve on elements with its sizes chosen and measured (module
    docstring).

    Parameters
    ----------
    split : kbm.model.conservative.ConservativeSplit
        The model at rest.
    D : float
        Noise intensity.
    G : callable
        The potential.
    omega0 : float
        The frequency of ``<a^2>``.
    sigma, L : float, optional
        Velocity scale and half-width (default: the Chebyshev ladder's choice).
    tol : float, optional
        The change at which each ladder stops (default :data:`TOL`).
    max_cost : float
        The largest ``N^2 E`` (``E/2`` folded) of a solve.
    workers : int, optional
        At most this many processes (:func:`._ahead.fp_workers`; the same bits).
    refine_ahead : bool
        ``P(E)`` will be wanted: the process of the element step started ahead goes on
        with the step after it (``refine``, handed on; the same bits).

    Returns
    -------
    ElementKramersSolution
        With ``hermite_change`` the stated error, ``chebyshev_change`` the element change
        and ``refinements`` the two pairs.

    Raises
    ------
    kbm.errors.ModelError
        The first solve exceeds ``max_cost``, or the pilot finds no stationary density.
    """
    with Ahead(element_stationary, workers=fp_workers(workers), G=G) as ahead:
        return _ladder(split, D, G, omega0, ahead, sigma=sigma, L=L,
                       tol=TOL if tol is None else float(tol), max_cost=max_cost,
                       refine_ahead=refine_ahead)


def _sizes(split, D: float, G, omega0: float, sigma, L):
    """``(half, s, points, E, folds)``: steps 1 and 2 of the module docstring."""
    from kbm.errors import ModelError

    from ._bases import cheb_mapped
    from ._model import _chebyshev_size, _half_width
    from ._parity import reflection_symmetric
    from ._stationary_orthonormal import FIRST_HERMITE, MIN_INTERVALS
    from ._stationary_points import ALPHA, stationary_points
    from ._stationary_solve import orthonormal_stationary

    mu = float(split.mu)
    half = _half_width(G, D / mu) if L is None else float(L)
    nc = max(MIN_INTERVALS, 2 * math.ceil(_chebyshev_size(G, D / mu, half) / 4))
    v2 = math.nan
    if sigma is None:
        v2 = orthonormal_stationary(split, D, math.sqrt(D / mu), half, FIRST_HERMITE, nc, G,
                                    omega0, alpha=ALPHA).v2
        if not (math.isfinite(v2) and v2 > 0):
            raise ModelError(f"the coarse Kramers solve gave <v^2> = {v2}: no stationary "
                             "density (check that the damping confines the motion)")
    s, points = stationary_points(split, D, G, half, v2, sigma, well=True)
    if "centres" in points:
        E = 2 * math.ceil(ELEMENT_RULE * half / min(points["widths"]) / 2)
    else:
        E = 2 * math.ceil(0.05 * nc)
    folds = reflection_symmetric(split, cheb_mapped(nc, half, ALPHA)[0])
    return half, s, points, max(FEWEST, E), folds


def _ladder(split, D: float, G, omega0: float, ahead, *, sigma, L, tol: float,
            max_cost: float, refine_ahead: bool = False) -> ElementKramersSolution:
    """The body of :func:`element_ladder` (``ahead``: :class:`._ahead.Ahead` of
    :func:`._elements_solve.element_stationary`)."""
    from kbm.errors import ModelError

    half, s, points, E, folds = _sizes(split, D, G, omega0, sigma, L)
    memo: dict = {}

    def cost(n: int, e: int) -> float:
        return n * n * (e / 2 if folds else e)

    def args(n, e):
        return (split, D, s, half, n, e, DEGREE, G, omega0)

    def solve(n: int, e: int) -> ElementKramersSolution:
        if (n, e) not in memo:
            memo[n, e] = ahead.result((n, e), *args(n, e), **points)
        return memo[n, e]

    moved = moments_moved

    def functions(k: int) -> int:
        return 2 * int(round(FIRST_FUNCTIONS * 2 ** (k / 2) / 2))

    def finer(e: int) -> int:
        return 2 * math.ceil(ELEMENT_STEP * e / 2)

    k = 0
    if cost(functions(0), E) > max_cost:
        raise ModelError(f"the Kramers solve needs {functions(0)} Hermite functions x {E} "
                         f"elements (cost {cost(functions(0), E):.3g} > {max_cost:.3g}): "
                         "not affordable here")
    sol = solve(functions(0), E)
    hermite = math.inf
    before = math.inf  # the Hermite change before the last
    hermite_pair = ahead_key = None
    while hermite > tol:  # step 3
        up = functions(k + 1)
        if cost(up, finer(E)) > max_cost:
            break
        if math.isfinite(before) and hermite * hermite / before <= tol:
            ahead_key = (up, finer(E))  # likely the last rung: its element step beside it
            then = (up, finer(finer(E)))  # and the step after it, for P(E)
            ahead.start(ahead_key, *args(*ahead_key), replace=True, **points,
                        then=[(then, args(*then), points)] if refine_ahead else ())
        new = solve(up, E)
        hermite_pair = (sol, new)
        before, hermite, sol, k = hermite, moved(sol, new), new, k + 1
    n = sol.coef.shape[0]
    if ahead_key is not None and ahead_key != (n, finer(E)):
        ahead.cancel()  # started for a rung that was not the last
    element = math.nan
    element_pair = None
    while not element <= tol and cost(n, finer(E)) <= max_cost:  # step 4
        E = finer(E)
        new = solve(n, E)
        element_pair = (sol, new)
        element, sol = moved(sol, new), new
    refine = None
    if element_pair is not None:  # the element step beyond the last, for P(E)
        refine = Later(functools.partial(element_stationary, *args(n, finer(E)), **points),
                       ahead.hand_on((n, finer(E))))
    ahead.cancel()
    parts = [c for c in (hermite, element) if not math.isnan(c)]  # inf: not measured
    stated = max(ROUNDING, sum(parts))
    pairs = tuple(p for p in (hermite_pair, element_pair) if p is not None)
    return dataclasses.replace(sol, hermite_change=stated, chebyshev_change=element,
                               refinements=pairs, refine=refine)
