"""The stationary Kramers solve on spectral elements with its sizes chosen and measured
(:func:`element_ladder`, what :func:`.kramers.stationary_kramers` runs for a nonlinear
damping whose potential has saddles on the range, the multi-well SEDF): a ladder of
elements at a predicted Hermite truncation, then a ladder of Hermite truncations on the
last elements, over the single solves of :func:`._elements_solve.element_stationary`
(the discretisation in :mod:`._elements`).

Why elements there.  The Chebyshev ladder of :mod:`._stationary_orthonormal` needs one
global grid fine enough for the saddles' layers, whose width is ``(D/omega_b)^(1/2)``: at
low friction its sizes and LU grow as ``N m^2`` (SEDF at rest, Delta = 3, D = mu/2,
``kbm noise --method fokker-planck``: 41 s CPU at mu = 0.01, 146-173 s and 3.1 GB at
mu = 0.005).  Elements put the points where the layers are and factorise by static
condensation, ``~ N^3`` per interface node: the same six digits in seconds (the tables of
docs/noise.rst).

The ladder (measured, SEDF at rest, Delta = 3, D = mu/2; the changes are relative, the
larger of ``<x^2>`` and ``<v^2>``; ``P`` is of its peak):

1. The range, the velocity scale and the centres of the element ends as the Chebyshev
   ladder's steps 1 to 3 (:func:`._stationary_points.stationary_points` with the deepest
   well, a pilot of 32 functions measuring ``<v^2>``).
2. The elements: ``E`` = :data:`ELEMENT_RULE` times ``L/l``, ``l`` the narrowest
   layer's width (without saddles a tenth of the Chebyshev ladder's first intervals), at
   least :data:`FEWEST`, degree :data:`DEGREE`, the ladder starting one element step
   below it; when ``P(E)`` is wanted (``refine_ahead``) :data:`ENERGY_RULE` times ``L/l``
   as far as the budget affords the last solve.  ``L/l`` is 21.5, 48, 68, 96 at
   mu = 0.1, 0.02, 0.01, 0.005.
3. The first rung of the functions: the first ``64 * 2^(k/2)`` (even) at least
   :data:`FUNCTION_SHARE` of the rule's ``N = pi V/delta``
   (:func:`._stationary_points.rule_functions` at the pilot's ``<v^2>``: 187, 480, 723,
   1029 at mu = 0.1, 0.02, 0.01, 0.005), lowered while the rung above it on the element
   step would exceed the budget.  The rungs whose change to the next was within six
   digits were 90, 182, 256, 362 there (0.48, 0.38, 0.35, 0.35 of the rule; changes
   7e-9, 4.5e-8, 4.3e-8, 3.2e-7), the rungs below them moved the moments by 1.5e-4,
   5.8e-5, 1.1e-5, 1.2e-6: 0.33 starts at 64, 182, 256, 362.  (Before, the functions climbed every rung from 64 on the first elements:
   at mu = 0.005 seven solves, 64 to 512, where three suffice.)
4. The element ladder at that rung, ``E`` times :data:`ELEMENT_STEP` (even), until the
   moments' change is within ``tol`` (default :data:`TOL`, a tenth of six digits: the
   stated error is the sum of two changes) and, when ``P(E)`` is wanted, ``P``'s change
   within :data:`ENERGY_TOL`, or the rung above on the next step would exceed the budget.
5. The Hermite ladder on those elements, ``2^(1/2)`` times the functions, until the
   change is within ``tol``, or the stated sum (step 6) within :data:`ENOUGH` times
   ``tol`` (six digits, with room for the rest: mu = 0.005, 362 -> 512 moved the moments
   by 3.3e-7, and 512 -> 724, 27 s more CPU, would buy digits nobody asked for), or the
   budget ends; when it climbed more than one rung, the
   last element step is solved again at the coarser rung of the last Hermite pair.
6. The stated error (``hermite_change``) is the sum of the last element change (step 4,
   ``chebyshev_change``) and the last Hermite change (step 5), at least
   :data:`ROUNDING` (``inf`` when either was not measured): two measured changes between
   two solves, the solution the finest of both pairs.  The two pairs are its
   ``refinements``: the sum of their changes of ``P(E)`` is ``P``'s stated error
   (:func:`._energy_density.energy_density_change`), with no further solve (``refine``
   is ``None``).

Why the elements are refined at the lower rung.  Once the functions resolve the
velocity, the element step moves the solution the same at either rung: mu = 0.01,
98 -> 118 elements moved ``P`` by 2.65e-6 at 256 and at 362 functions (the same to three
digits), the moments by 7.9e-9 and 1.5e-9, below ``tol`` at both; a solve at the lower
rung costs half.  And the Hermite pair is measured on the solution's own elements.

Why ``P(E)`` needs more elements than the moments.  ``P`` samples the density along one
orbit, the moments average it over the plane: mu = 0.01, 362 functions on 82, 98, 118,
142, 170 elements, against 512 on 200, ``P`` was 8.2e-6, 2.9e-6, 9.9e-7, 2.4e-7, 3.6e-8
off (at energies 4.4 to 6.1, above the saddles), the moments 2.3e-8, 1.4e-9, 1.4e-10 and
below; weighting the map's centres less (0.6, 0.35 of their weights) did not help
(256 functions on 142: 2.6e-7, 3.3e-7).  ``ENERGY_RULE`` 2.5 starts the ladder of
``P`` at its pair 142 -> 172 at mu = 0.01 (moved ``P`` by 2.6e-7) and 200 -> 240 at
mu = 0.005 (5.0e-9 of the moments; with the ``N^2 E`` of the band LU before, the budget
stopped it at 158 -> 190, ``P`` 3.7e-6).

Before, ``P(E)`` took the max of the two pairs' changes (the moments' error is their
sum) and, beyond six digits, came from one element step more with the step's change
times ``r/(1 - r)``, an extrapolation of the geometric tail.

The solve of the answer, ``n 2^(1/2)`` functions on the element step, starts in a second
process (:mod:`._ahead`) beside the element pair at ``n``, and each element step's rung
above beside it (stopped when the ladder goes on): the same solves and bits, less wall
time.  With ``P(E)`` wanted that process evaluates the answer's ``P(E)`` on its own grid
after the solve and sends it back with it (:func:`_solve`; the returned solution shares the
cache of the Hermite pair's, where :func:`._energy_density.energy_density_report` finds it):
at mu = 0.005 the first process evaluates the element pair's ``P`` (4.8 s CPU) while the
second evaluates the answer's (3.5 s), and the report after the ladder, which took 4.5 s
CPU (the answer's ``P`` twice: the returned solution's and the pair's), takes 0.01 s.  The
solves of each process take their large arrays from one buffer (:mod:`._workspace`,
:data:`WORKSPACE`): 6.1, 7.7 and 16.5 s CPU (user and system) for the three solves at
mu = 0.005, the first two in one process, against 8.9, 9.3 and 19.2 s with fresh arrays
(interleaved, load 2.5).

The budget: :data:`COST_SHARE` times ``N^2 E`` (``E/2`` when folded, :mod:`._parity`) at
most ``max_cost``, so that ``max_cost`` 2.5e7 (``kbm noise``'s) is about 2.5 GB, as it was
when the interface LU kept a band of ``6 N^2`` numbers per node; it keeps ``4 N^2`` now and
the interiors are factorised in place (:mod:`._elements_lu`): one solve of 512 functions on
176 elements, folded, peaked at 1.39 GB (``N^2 E/2`` = 2.3e7), on 240 at 1.88 GB (3.1e7).

Measured (SEDF at rest, Delta = 3, D = mu/2, ``max_cost`` 2.5e7, ``P(E)`` wanted; one
process, CPU of the ladder and ``P(E)``, load 3-5 on two cores; "off" against a finer
element solve, 256 x 100, 362 x 170, 512 x 220, 512 x 256 at mu = 0.1, 0.02, 0.01, 0.005,
the moments the larger of ``<x^2>``, ``<v^2>``, ``P`` of its peak):

=====  ==============================  ===============================  ==================
mu     now: sizes, stated, P stated,   before: sizes, stated, P stated  CPU now, before
       off (moments; P)                (P from), off (moments; P)
=====  ==============================  ===============================  ==================
0.1    128 x 58, 5.7e-8, 5.0e-7;       128 x 58, 9.1e-9, 5.0e-7;        2.8 s, 2.9 s
       2.2e-9; 1.7e-8                  2.2e-9; 1.7e-8
0.02   256 x 120, 5.7e-8, 7.7e-8;      256 x 90, 4.5e-8, 1.6e-7;        7.5 s, 13.2 s
       2.2e-10; 3.2e-8                 2.5e-10; 1.4e-7
0.01   362 x 172, 5.5e-8, 2.6e-7;      362 x 124, 4.4e-8, 5.4e-7        21 s, 29-32 s
       9.3e-11; 5.5e-8                 (x 150); 1.2e-10; 2.1e-7
0.005  512 x 190, 3.4e-7, 3.7e-6;      512 x 176, 3.2e-7, 9.7e-7        45 s, 83-86 s
       4.6e-10; 9.7e-7                 (x 212); 7.6e-10; 3.7e-7
0.005  512 x 240, 3.0e-7, 5.0e-7;      (:data:`COST_SHARE` and the      42 s (load 1-2.5)
       3.7e-10; 2.1e-7 (off 512 x 300) one-node LU, below)
=====  ==============================  ===============================  ==================

The solves now (``N x E``): mu = 0.01, 256 x 142 and 256 x 172 (the element pair, ``P``
moved by 2.6e-7), 362 x 172 (the Hermite pair, 5.7e-8); before, 64 to 362 on 102, 362 x
124 and ``P``'s 362 x 150.  At mu = 0.005 the budget stops the elements at 362 x 158 ->
190 (``P`` moved by 3.7e-6; the pair 202 -> 240, which moved it by 5.5e-7 at 362
functions, would cost 3.1e7 at 512), the stated ``P`` is beyond six digits; before, ``P`` came from
512 x 212 beyond the budget with ``r/(1 - r)`` times the step.  Its moments are 8.0e-8
and 3.9e-8 from the Chebyshev route's at ``--fp-budget 8.6e7`` (stated 5.6e-7).

Since the interface LU of one node at a time (:mod:`._elements_lu`, 1.39 against 1.96 GB
at 512 x 176) the cost counts :data:`COST_SHARE` of ``N^2 E``, so that the budget stays
about 2.5 GB, and at mu = 0.005 the elements of ``P`` reach 200 -> 240 at 362 functions,
then 512 on 240: stated 3.0e-7 (the element change 5.0e-9), ``P`` 5.0e-7, 3.7e-10 and
2.1e-7 off 512 x 300, 42 s CPU and 1.88 GB in one process with ``P(E)``.  At mu = 0.002
it reaches 512 x 316, stated 2.8e-5 (the functions': 362 against 512), ``P`` 8.1e-5,
56 s and 2.34 GB: six digits there need 724 functions, beyond the budget.

Since the buffer of :mod:`._workspace` and the answer's ``P(E)`` evaluated once (mu = 0.005):
one process, 39.5 s CPU (the ladder 35.8 s, 3.2 s of it system; ``P(E)`` 3.7 s) against
47.2 s (44.0 s, 9.1 s; 3.1 s), peak 1.91 against 1.88 GB (load 4-5); ``kbm noise`` in two
processes (its command in :mod:`._elements_lu`; two interleaved pairs, load 2-4) 48.5 and
49.9 s wall against 58.1 and 61.3 s, 50.4 and 48.6 s CPU (6.7 and 6.2 s system) against
59.7 and 59.6 s (13.8 and 13.3 s), peak 1.79 against 1.73 GB; at mu = 0.01 (D = 0.005,
load 4-4.5) 23.7 and 27.4 s wall against 27.5 and 25.2 s, 23.1 and 25.8 s CPU against 26.6
and 24.5 s.  The same bytes with one process and two.
"""

from __future__ import annotations

import dataclasses
import math

from ._solution import moments_moved
from . import _workspace
from ._ahead import Ahead, fp_workers
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
#: the first rung of the functions: the first ``64 * 2^(k/2)`` at least this share of
#: :func:`._stationary_points.rule_functions` (``pi V/delta`` at the pilot's ``<v^2>``;
#: module docstring, step 3)
FUNCTION_SHARE = 0.33
#: the elements per ``L/l`` that ``P(E)`` needs (the last of its element pair; step 3)
ENERGY_RULE = 2.5
#: the Hermite ladder also stops when the stated sum is within this many ``tol`` (step 5)
ENOUGH = 5
#: the budget's share of ``N^2 E`` (``E/2`` folded): the peak memory of one solve is
#: about 60 bytes per unit of ``N^2 E`` (512 x 176 folded: 1.39 GB; 512 x 240: 1.88 GB),
#: so that ``max_cost`` counts about 100 bytes (module docstring)
COST_SHARE = 0.6
#: the buffer of the solves of each process (:mod:`._workspace`; reserved, its pages
#: untouched until used): this many bytes per unit of the largest affordable ``N^2 E``
#: (``max_cost/COST_SHARE``); a solve's arrays take about ``32 N^2 E + 7 10^3 N E`` bytes
#: (``E/2`` folded; 512 x 240: 1.5 GB)
WORKSPACE = 64
#: the change of ``P(E)`` (of its peak) at which the element ladder stops when ``P(E)``
#: is wanted (half of six digits: the functions' change and the quadrature's add to it)
ENERGY_TOL = 5e-7


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
        ``P(E)`` will be wanted: the elements start from :data:`ENERGY_RULE` and their
        ladder goes on until ``P`` changes by at most :data:`ENERGY_TOL` of its peak too
        (steps 2 and 4 of the module docstring), so that ``P`` of the solution itself
        has its error measured.

    Returns
    -------
    ElementKramersSolution
        With ``hermite_change`` the stated error, ``chebyshev_change`` the element change,
        ``refinements`` the two pairs (the Hermite pair, then the element pair) and
        ``refine`` ``None``.

    Raises
    ------
    kbm.errors.ModelError
        The first solve exceeds ``max_cost``, or the pilot finds no stationary density.
    """
    with Ahead(_solve, workers=fp_workers(workers), G=G, keep=("energy_density",)) as ahead, \
            _workspace.workspace(WORKSPACE * max_cost / COST_SHARE):
        return _ladder(split, D, G, omega0, ahead, sigma=sigma, L=L,
                       tol=TOL if tol is None else float(tol), max_cost=max_cost,
                       refine_ahead=refine_ahead)


def _solve(*args, density: bool = False, **kwargs) -> ElementKramersSolution:
    """:func:`._elements_solve.element_stationary`; with ``density`` then ``P(E)`` on the
    solution's :func:`._energy_density.energy_grid`, kept in its cache: the answer solved
    ahead comes back with it (``keep`` of :class:`._ahead.Ahead`), computed in the second
    process while this one evaluates the element pair, and
    :func:`._energy_density.energy_density_report` finds it there (the same bits)."""
    with _workspace.solve():
        sol = element_stationary(*args, **kwargs)
    if density:
        from ._energy_density import energy_density, energy_grid

        energy_density(sol, energy_grid(sol))
    return sol


def _sizes(split, D: float, G, omega0: float, sigma, L):
    """``(half, s, points, E, folds, rule, reach)``: steps 1 and 2 of the module docstring
    (``rule`` the functions of :func:`._stationary_points.rule_functions` at the pilot's
    ``<v^2>``, ``nan`` when ``sigma`` is given; ``reach`` ``L/l``, ``nan`` without
    saddles)."""
    from kbm.errors import ModelError

    from ._bases import cheb_mapped
    from ._model import _chebyshev_size, _half_width
    from ._parity import reflection_symmetric
    from ._stationary_orthonormal import FIRST_HERMITE, MIN_INTERVALS
    from ._stationary_points import ALPHA, rule_functions, stationary_points
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
    reach = math.nan
    if "centres" in points:
        reach = half / min(points["widths"])
        E = 2 * math.ceil(ELEMENT_RULE * reach / 2)
    else:
        E = 2 * math.ceil(0.05 * nc)
    folds = reflection_symmetric(split, cheb_mapped(nc, half, ALPHA)[0])
    rule = rule_functions(split, D, half, v2) if sigma is None else math.nan
    return half, s, points, max(FEWEST, E), folds, rule, reach


def _energy_moved(a, b) -> float:
    """The largest change of ``P(E)`` from the solve ``a`` to ``b`` on
    :func:`._energy_density.energy_grid` of ``b``, relative to the peak of ``b``'s."""
    import numpy as np

    from ._energy_density import energy_density, energy_grid

    E = energy_grid(b)
    Pb = energy_density(b, E)
    return float(np.max(np.abs(Pb - energy_density(a, E)))) / float(np.max(np.abs(Pb)))


def _ladder(split, D: float, G, omega0: float, ahead, *, sigma, L, tol: float,
            max_cost: float, refine_ahead: bool = False) -> ElementKramersSolution:
    """The body of :func:`element_ladder` (``ahead``: :class:`._ahead.Ahead` of
    :func:`._elements_solve.element_stationary`)."""
    from kbm.errors import ModelError

    half, s, points, E_rule, folds, rule, reach = _sizes(split, D, G, omega0, sigma, L)
    memo: dict = {}

    def cost(n: int, e: int) -> float:
        return COST_SHARE * n * n * (e / 2 if folds else e)

    def args(n, e):
        return (split, D, s, half, n, e, DEGREE, G, omega0)

    def solve(n: int, e: int) -> ElementKramersSolution:
        if (n, e) not in memo:
            memo[n, e] = ahead.result((n, e), *args(n, e), **points)
        return memo[n, e]

    moved = moments_moved

    def rung(n: int) -> int:  # the next rung of 64 * 2^(k/2)
        k = 0
        while functions(k) <= n:
            k += 1
        return functions(k)

    def functions(k: int) -> int:
        return 2 * int(round(FIRST_FUNCTIONS * 2 ** (k / 2) / 2))

    def finer(e: int) -> int:
        return 2 * math.ceil(ELEMENT_STEP * e / 2)

    # steps 2 and 3: the elements one step below the rule's, the first rung predicted
    E = max(FEWEST, 2 * round(E_rule / ELEMENT_STEP / 2))
    k = 0
    while math.isfinite(rule) and functions(k) < FUNCTION_SHARE * rule:
        k += 1
    while k > 0 and cost(functions(k + 1), finer(E)) > max_cost:
        k -= 1  # the budget: the rung above on the element step affordable
    n = functions(k)
    if refine_ahead and math.isfinite(reach):  # P(E)'s elements, as far as affordable
        want = 2 * round(ENERGY_RULE * reach / ELEMENT_STEP / 2)
        while E < want and cost(rung(n), finer(E + 2)) <= max_cost:
            E += 2
    if cost(n, E) > max_cost:
        raise ModelError(f"the Kramers solve needs {n} Hermite functions x {E} "
                         f"elements (cost {cost(n, E):.3g} > {max_cost:.3g}): "
                         "not affordable here")
    if cost(rung(n), finer(E)) <= max_cost:  # the predicted answer, beside its pairs
        ahead.start((rung(n), finer(E)), *args(rung(n), finer(E)), density=refine_ahead,
                    **points)
    sol = solve(n, E)
    element = energy = math.inf
    element_pair = None
    while (element > tol or (refine_ahead and energy > ENERGY_TOL)) \
            and cost(rung(n), finer(E)) <= max_cost:  # step 4: the elements at n
        ahead.start((rung(n), finer(E)), *args(rung(n), finer(E)), replace=True,
                    density=refine_ahead, **points)
        E = finer(E)
        new = solve(n, E)
        element_pair = (sol, new)
        element, sol = moved(sol, new), new
        if refine_ahead:
            energy = _energy_moved(*element_pair)
    hermite = math.inf
    hermite_pair = None
    while hermite > tol and hermite + element > ENOUGH * tol \
            and cost(rung(n), E) <= max_cost:  # step 5: the functions at E
        up = rung(n)
        if not ahead.running((up, E)):
            ahead.cancel()
        new = solve(up, E)
        hermite_pair = (sol, new)
        hermite, sol, n = moved(sol, new), new, up
    ahead.cancel()
    if hermite_pair is not None and element_pair is not None \
            and element_pair[1].coef.shape[0] != hermite_pair[0].coef.shape[0]:
        # the functions climbed past the first rung: the element step again at the
        # coarser rung of the last pair (step 5)
        m = hermite_pair[0].coef.shape[0]
        element_pair = (solve(m, len(element_pair[0].edges) - 1), hermite_pair[0])
        element = moved(*element_pair)
    stated = max(ROUNDING, hermite + element)
    pairs = tuple(p for p in (hermite_pair, element_pair) if p is not None)
    return dataclasses.replace(sol, hermite_change=stated, chebyshev_change=element,
                               refinements=pairs, refine=None, _cache=sol._cache)
