"""The density of the energy ``P(E)`` of a stationary Kramers solution
(:func:`energy_density`), its grid (:func:`energy_grid`) and its stated error
(:func:`energy_density_change`, the change under the refinements that state the moments'
error; at low friction :func:`energy_density_report` takes ``P`` from one grid step more,
since the grid's error moves ``P(E)`` more than the moments).

``P(E)`` is the derivative of the mass below ``E`` (:meth:`._solution.KramersSolution.mass_below`,
over the same stretches, :meth:`._solution.KramersSolution.stretches`):
with ``P(x, v) = sum_n c_n(x) f_n(v/s)/s`` and ``U(x) = (2 (E - G(x)))^(1/2)/s``,

``P(E) = int_{G < E} dx sum_n c_n(x) b_n(U)/(s^2 U)``, ``b_n(U) = f_n(U) + f_n(-U)``,

i.e. ``int dx (P(x, v) + P(x, -v))/|v|`` at ``|v| = (2 (E - G))^(1/2)``: ``b_n = 2 f_n(U)``
for even ``n`` and ``0`` for odd ``n`` (``f_n`` the orthonormal Hermite functions ``h_n``,
or Risken's ``He_n(u) exp(-u^2/2)/(2 pi n!)^(1/2)``), by the quadrature of
:mod:`._energy_quadrature`.  At a separatrix energy ``E_s`` (a saddle's ``G``) ``P`` has a logarithmic
singularity (the period ``T(E)`` does: for linear damping ``P(E) = T(E) exp(-E/kT)/Z``,
the Boltzmann density times the period, ``Z = (2 pi kT)^(1/2) int exp(-G/kT) dx``).
"""

from __future__ import annotations

import numpy as np

from ._blocks import on_one_blas_thread
from ._energy_quadrature import energy_density

__all__ = ["energy_density", "energy_grid", "energy_density_change", "energy_density_report",
           "separatrix_energies", "negative_part",
           "ENERGY_POINTS"]

#: the number of energies of :func:`energy_grid`
ENERGY_POINTS = 32
#: the stated change of ``P(E)`` (of its peak) above which :func:`energy_density_report`
#: takes ``P`` from a solve one grid step finer
SIX_DIGITS = 1e-6
#: the moments' stated change from which :func:`energy_density_report` starts the grid step
#: of ``P(E)`` (``sol.refine``) beside the evaluation that decides it (:mod:`._ahead`;
#: stopped when not needed): ``P``'s grid change ran 20 to 40 times the moments' (SEDF at
#: rest, Delta = 3, D = mu/2: stated 2.9e-7 and 5.4e-7 at mu = 0.01 and 0.02, where the
#: step is taken; 1.1e-8 and 2.5e-8 at mu = 0.1 and 0.05, where it is not)
REFINE_AHEAD = 1e-7


def separatrix_energies(sol) -> list:
    """``G`` at the saddles (interior maxima of ``G``) on the solution's range, increasing."""
    grid = np.linspace(-float(sol.x[0]), float(sol.x[0]), 20001)
    Gg = np.asarray(sol.G(grid), float)
    k = np.flatnonzero((Gg[1:-1] > Gg[:-2]) & (Gg[1:-1] >= Gg[2:])) + 1
    from scipy.optimize import minimize_scalar

    out = set()
    for i in k:
        r = minimize_scalar(lambda z: -float(sol.G(np.array(z))), bracket=(grid[i - 1],
                            grid[i], grid[i + 1]), tol=1e-12)
        out.add(round(-float(r.fun), 12))
    return sorted(out)


def energy_grid(sol, points: int = ENERGY_POINTS, floor: float = 1e-5) -> np.ndarray:
    """``points`` energies, the midpoints of equal bins from the bottom of ``G`` to the
    largest ``G`` where the marginal of ``x`` exceeds ``floor`` of its peak (above it the
    orbits' turning points carry little mass: SEDF mu = 0.1, D = 0.05, ``P`` falls to
    ``2e-7`` of its peak at 9 for a top of 6.6; with ``floor = 1e-8`` the top was 22.8,
    where the solution's ``P`` is ``1e-10`` and of either sign)."""
    marg = sol.marginal()
    Gx = np.asarray(sol.G(sol.x), float)
    held = marg > floor * float(np.max(marg))
    lo = float(np.min(np.asarray(sol.G(np.linspace(-sol.x[0], sol.x[0], 20001)), float)))
    hi = float(np.max(Gx[held]))
    edges = np.linspace(lo, hi, points + 1)
    return 0.5 * (edges[:-1] + edges[1:])


def energy_density_change(sol, energies, values=None,
                          shared: dict | None = None) -> np.ndarray | None:
    """``|P_fine(E) - P_coarse(E)|/|P(E)|`` at each energy, summed over the pairs of
    solutions whose change of the moments states ``sol``'s error (``sol.refinements``: the
    Hermite and the Chebyshev step of :func:`._stationary_orthonormal.stationary_orthonormal`,
    the Hermite and the element step of :func:`._elements_ladder.element_ladder`, or a finer
    grid for linear damping), as the moments' changes are summed: either step alone leaves
    the other's error in ``P``; ``None`` when none was kept."""
    pairs = getattr(sol, "refinements", ())
    if not pairs:
        return None
    P = (energy_density(sol, energies, shared=shared) if values is None
         else np.asarray(values, float))
    worst = np.zeros(len(P))
    for coarse, fine in pairs:
        worst = worst + np.abs(energy_density(fine, energies, shared=shared)
                               - energy_density(coarse, energies, shared=shared)) / np.abs(P)
    return worst


@on_one_blas_thread
def energy_density_report(sol, finer=None, points: int = ENERGY_POINTS,
                          workers: int | None = None) -> dict:
    """``P(E)`` on :func:`energy_grid` of ``sol`` with its stated error, for JSON: ``E``,
    ``P``, ``change`` (per energy, relative; the largest of each energy's and its two
    neighbours'), ``change_peak`` (relative to the peak of ``P``) and ``separatrices``
    (where ``P`` is logarithmically singular).

    The change is that under ``sol.refinements`` (:func:`energy_density_change`; for a
    solution without them, linear damping, the change to ``finer``, a solve on a finer
    grid; ``None`` without either), plus the quadrature's estimate, and ``change_peak``
    the largest, before the neighbours', relative to the peak.

    When that exceeds :data:`SIX_DIGITS` and ``sol`` keeps its grid step (``sol.refine``
    and a grid pair in ``sol.refinements``, the Chebyshev ladder; the element ladder keeps
    none, its ``P`` is the solution's own with the sum of the two pairs' changes, and its
    elements are chosen for ``P`` when ``P`` is wanted, :mod:`._elements_ladder`), ``P`` is
    that of the solve one grid step finer, 1.25 times ``sol``'s intervals: the grid's
    error sits in the separatrices' layers (:mod:`._stationary_points`), which ``P(E)``
    samples along one orbit where the moments average it over the plane (SEDF mu = 0.01:
    the last grid step moved ``P`` by 1.2e-5 of its peak, the moments by 2.9e-7).  Then
    ``change`` is the sum of that step's change, the Hermite pair's of ``sol.refinements``
    and the quadrature's, and ``change_peak`` its largest: measured changes between solves,
    the step's that of ``sol``, an upper estimate of the finer solve's error (SEDF at rest,
    Delta = 3, D = mu/2, ``basis="orthonormal"``: stated 2.7e-6, 1.3e-6, 2.4e-7 of the peak
    at mu = 0.01, 0.02, 0.03, 3.7, 4.9 and 36 times the distance to solves of 362
    functions x 1602 and 1282 intervals; docs/noise.rst).  (Before, ``change_peak`` was the step's
    change times ``r/(1 - r)``, ``r`` 1.2 times its ratio to the ladder's last step: an
    extrapolation of the geometric tail, 1.35 times the true error at mu = 0.01; and the
    pairs' changes were combined by their largest, where the moments' stated error is their
    sum.)

    The grid step may start in a second process (:mod:`._ahead`; at most ``workers``
    processes, :func:`._ahead.fp_workers`), the same bits, or come from the ladder's,
    which started it with the climb's solves (``sol.refine.handed``); stopped when not
    needed.
    """
    from ._ahead import Ahead, fp_workers

    pairs = getattr(sol, "refinements", ())
    grid = [p for p in pairs if p[1].coef is sol.coef
            and p[0].coef.shape[0] == sol.coef.shape[0] and p[0].x.size < sol.x.size]
    with Ahead(lambda: sol.refine(), workers=fp_workers(workers), G=sol.G) as ahead:
        # the ladder's second process may be solving it already (._ahead.Later)
        ahead.adopt("refine", getattr(sol.refine, "handed", None))
        if grid and getattr(sol, "refine", None) is not None \
                and sol.hermite_change >= REFINE_AHEAD:
            ahead.start("refine")  # the grid step beside the evaluations below (._ahead)
        return _report(sol, finer, points, pairs, grid, ahead)


def _report(sol, finer, points: int, pairs, grid, ahead) -> dict:
    """The body of :func:`energy_density_report` (``grid``: the grid pairs of
    ``sol.refinements``; ``ahead``: :class:`._ahead.Ahead` of ``sol.refine``)."""
    E = energy_grid(sol, points)
    shared: dict = {}  # the nodes and velocity functions, for every solution of the report
    widest = max([sol] + [s for pair in pairs for s in pair], key=lambda s: s.coef.shape[0])
    if widest is not sol:  # first: its velocity functions' rows serve the others' (the
        # same numbers; SEDF mu = 0.01, 258 and 364 functions: each rule's recurrence once)
        energy_density(widest, E, shared=shared)
    P, quad = energy_density(sol, E, quadrature=True, shared=shared)
    if not pairs and finer is not None:
        change = np.abs(energy_density(finer, E, shared=shared) - P) / np.abs(P)
    else:
        change = energy_density_change(sol, E, P, shared)
    if change is not None:
        change = change + quad / np.abs(P)
        absolute = float(np.max(change * np.abs(P)))
    if change is not None and absolute > SIX_DIGITS * float(np.max(np.abs(P))) and grid \
            and getattr(sol, "refine", None) is not None:
        here = P
        P, quad = energy_density(ahead.result("refine"), E, quadrature=True, shared=shared)
        step = np.abs(P - here)
        hermite = np.zeros(len(P))
        for coarse, fine in pairs:
            if fine.coef.shape[0] != coarse.coef.shape[0]:
                hermite = hermite + np.abs(energy_density(fine, E, shared=shared)
                                           - energy_density(coarse, E, shared=shared))
        change = (step + hermite + quad) / np.abs(P)
        absolute = float(np.max(change * np.abs(P)))
    if change is not None:  # the largest of each energy's and its neighbours' (a change
        # that crosses zero between two rungs says nothing there: SEDF mu = 0.1 at E = 2.16,
        # 1.3e-9 stated and 3.5e-8 from a 256 x 1026 solve, 1.6e-7 and 1.9e-6 beside it)
        change = np.maximum.reduce([change, np.r_[change[1:], 0.0], np.r_[0.0, change[:-1]]])
    peak = float(np.max(np.abs(P)))
    out = {"E": [float(e) for e in E], "P": [float(p) for p in P],
           "change": None if change is None else [float(c) for c in change],
           "change_peak": None if change is None else absolute / peak,
           "separatrices": [float(e) for e in separatrix_energies(sol)]}
    if np.any(P < 0):
        out["negative"] = negative_part(E, P, change)
    return out


def negative_part(E: np.ndarray, P: np.ndarray, change: np.ndarray | None) -> dict:
    """Where the solved ``P(E)`` is negative, reported, not clipped: ``E`` and ``P`` there,
    ``mass`` (``int max(-P, 0) dE`` by the grid's equal bins, of the density's 1) and
    ``within_change`` (whether each negative value lies within its stated change, a
    relative ``change >= 1``, so that zero is within the stated error there; ``None``
    without a stated change).

    The spectral solution is not positive by construction: in the tail, where ``P`` is a
    few 1e-6 of its peak, its error is of either sign (SEDF at rest, Delta = 3, mu = 0.002,
    D = 0.001: eleven negative values, the largest -2.9e-6 of a peak of 0.41, each within
    its change; ``mass`` 4.1e-6).  ``P`` keeps its
    values, so that ``change`` stays relative to them (clipped to zero, the relative
    change there would be infinite)."""
    neg = P < 0
    width = float(E[1] - E[0]) if len(E) > 1 else 0.0
    return {"E": [float(e) for e in E[neg]], "P": [float(p) for p in P[neg]],
            "mass": float(-np.sum(P[neg]) * width),
            "within_change": None if change is None else bool(np.all(change[neg] >= 1))}
