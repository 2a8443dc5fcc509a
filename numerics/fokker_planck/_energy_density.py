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
or Risken's ``He_n(u) exp(-u^2/2)/(2 pi n!)^(1/2)``).  On each stretch ``a < x < b`` where
``G < E`` the substitution ``x = (a + b)/2 + (b - a)/2 sin(pi t/2)`` makes the ends'
``1/U ~ (b - x)^(-1/2)`` smooth, and Gauss-Legendre rules in ``t`` are doubled until two
agree.  At a separatrix energy ``E_s`` (a saddle's ``G``) ``P`` has a logarithmic
singularity (the period ``T(E)`` does: for linear damping ``P(E) = T(E) exp(-E/kT)/Z``,
the Boltzmann density times the period, ``Z = (2 pi kT)^(1/2) int exp(-G/kT) dx``).
"""

from __future__ import annotations

import functools
import math

import numpy as np

from ._blocks import on_one_blas_thread

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
#: the factor on the measured contraction ``q`` of the grid step in the geometric tail of
#: :func:`energy_density_report`.  Measured, SEDF at rest, Delta = 3, D = mu/2, against
#: solves of 362 functions x 1602 (mu = 0.01) and 1282 intervals (0.02, 0.03) at another
#: velocity scale: the factor at which the tail would equal the finer solve's true error
#: (less the Hermite pair's part) is 0.98, 1.10 and 0.19 at mu = 0.01, 0.02, 0.03 (``q`` =
#: 0.219, 0.154, 0.149; the bare ratio understates at mu = 0.02, where the error's worst
#: energy, 0.955, is not the step's, 4.14).  With 1.2 the stated error is 1.35, 1.22 and
#: 8.9 times the true one (9.9e-7, 3.3e-7, 6.0e-8 of the peak against 7.3e-7, 2.7e-7,
#: 6.8e-9); 1.5 stated 1.3e-6 at mu = 0.01, over six digits where they are met.
TAIL_SAFETY = 1.2


def _velocity_edges(sol, n: int, U: np.ndarray) -> np.ndarray:
    """``b_k(U) = f_k(U) + f_k(-U)`` for the even ``k < n`` (rows, ``k = 0, 2, ...``)."""
    if sol.basis == "orthonormal":
        from ._hermite_functions import hermite_function_values

        f = hermite_function_values(n, U)
    else:
        from ._bases import hermite_functions

        f = hermite_functions(n, U) * (np.exp(-0.5 * U * U) / math.sqrt(2 * math.pi))
    return 2.0 * f[::2]


@functools.lru_cache(maxsize=16)
def _gauss_legendre(n: int) -> tuple[np.ndarray, np.ndarray]:
    """The ``n``-point Gauss-Legendre rule (scipy's, whose large rules cost ``O(n)``, not
    the ``O(n^3)`` eigenvalues of numpy's)."""
    from scipy.special import roots_legendre

    return roots_legendre(n)


def _chebyshev_values(t: np.ndarray, n: int, block: int = 32) -> np.ndarray:
    """``T_k(t)`` for ``k < n`` (columns): ``T_0 .. T_block`` by ``T_{k+1} = 2 t T_k -
    T_{k-1}``, then ``block`` rows at a time by the same recurrence with the step
    ``block``, ``T_{m+b} = 2 T_b T_m - T_{m-b}`` (``T_{-j} = T_j``; from ``cos((m +- b)
    theta)``, ``t = cos theta``): one vector operation per ``block`` degrees, not per
    degree (SEDF mu = 0.01, 1041 and 1301 points: 920 stretches of mostly 64 or 128 nodes
    took 2.5 s of Python loop per degree).  The same values to a few ulps (the step
    recurrence is that of ``T_k(T_b)``, as stable)."""
    out = np.empty((n, t.size))
    out[0] = 1.0
    if n > 1:
        out[1] = t
    two_t = 2 * t
    first = min(n, block + 1)
    for k in range(1, first - 1):
        np.multiply(two_t, out[k], out=out[k + 1])
        out[k + 1] -= out[k - 1]
    if n > first:
        two_tb = 2 * out[block]
        m = block + 1  # T_m = 2 T_b T_{m-b} - T_{2b-m} for b < m < 2b
        top = min(n, 2 * block)
        out[m:top] = two_tb * out[1:top - block] - out[2 * block - m:2 * block - top:-1]
        for m in range(2 * block, n, block):
            top = min(n, m + block)
            np.multiply(two_tb, out[m - block:top - block], out=out[m:top])
            out[m:top] -= out[m - 2 * block:top - 2 * block]
    return out.T


def _stretch_density(sol, coefs, E: float, a: float, b: float, n: int,
                     shared: dict | None = None) -> float:
    """The stretch's share of ``P(E)`` by the ``n``-point rule (``coefs``: the Chebyshev
    series of the even orders, columns; the values of ``T_k`` times them, one matrix
    product).  ``shared`` keeps the nodes and the velocity functions' values, which
    depend on the solution only through its basis, scale and number of functions (the
    first ``k`` rows of the recurrence are the same for any number): the solutions of
    one :func:`energy_density_report` compute them once."""
    key = (sol.basis, sol.sigma, E, a, b, n)
    rows = coefs.shape[1]
    if shared is not None and key in shared and shared[key][3].shape[0] >= rows:
        w, jac, xs, edge, U = shared[key]
        edge = edge[:rows]
    else:
        t, w = _gauss_legendre(n)
        xs = 0.5 * (a + b) + 0.5 * (b - a) * np.sin(0.5 * np.pi * t)
        jac = 0.25 * np.pi * (b - a) * np.cos(0.5 * np.pi * t)
        U = np.sqrt(np.maximum(2 * (E - np.asarray(sol.G(xs), float)), 1e-300)) / sol.sigma
        edge = _velocity_edges(sol, 2 * rows, U)
        if shared is not None:
            shared[key] = (w, jac, xs, edge, U)
    c = (_chebyshev_values(sol._t(xs), coefs.shape[0]) @ coefs).T  # even orders, rows
    return float(np.sum(w * jac * np.sum(c * edge, axis=0) / U)) / sol.sigma**2


def energy_density(sol, energies, rtol: float = 1e-8, nodes: int = 64, most: int = 2048,
                   quadrature: bool = False, shared: dict | None = None):
    """``P(E)`` of the stationary solution ``sol`` at each of ``energies`` (module
    docstring): Gauss-Legendre rules of ``nodes``, doubled on each stretch until two agree
    to ``rtol`` (relative) or ``most`` nodes (near a separatrix energy, whose logarithmic
    singularity converges slowly).

    Parameters
    ----------
    sol : KramersSolution
    energies : array_like
    quadrature : bool
        Also return the quadrature's error estimate (the last two rules' difference, summed
        over the stretches).
    shared : dict, optional
        The nodes and velocity functions computed for other solutions of the same scale
        (:func:`_stretch_density`; the same numbers).

    Returns
    -------
    numpy.ndarray, or (numpy.ndarray, numpy.ndarray) with ``quadrature``
    """
    key = ("energy_density", np.asarray(energies, float).tobytes(), rtol, nodes, most)
    if key in sol._cache:  # a coarse solution shared by two refinements is evaluated once
        P, miss = sol._cache[key]
        return (P.copy(), miss.copy()) if quadrature else P.copy()
    from ._blocks import one_blas_thread

    # the odd orders have b_n = 0; contiguous, and one BLAS thread: the products are small
    # (SEDF mu = 0.01, 1041 points, 129 even orders: 64 nodes took 20 ms a stretch, 4x the
    # product's work with a strided array on two threads under load)
    coefs = np.ascontiguousarray(sol._series()[:, ::2])
    out, err = [], []
    with one_blas_thread():
        for E in np.atleast_1d(np.asarray(energies, float)):
            total = miss = 0.0
            for a, b in sol.stretches(float(E)):
                n, last = nodes, None
                while True:
                    val = _stretch_density(sol, coefs, float(E), a, b, n, shared)
                    if last is not None and (abs(val - last) <= rtol * abs(val)
                                             or n >= most):
                        break
                    last, n = val, 2 * n
                total += val
                miss += abs(val - last)
            out.append(total)
            err.append(miss)
    sol._cache[key] = (np.array(out), np.array(err))
    return (np.array(out), np.array(err)) if quadrature else np.array(out)


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
    """``|P_fine(E) - P_coarse(E)|/|P(E)|`` at each energy, the largest over the pairs of
    solutions whose change of the moments states ``sol``'s error (``sol.refinements``:
    the Hermite and the Chebyshev step of :func:`._stationary_orthonormal.stationary_orthonormal`,
    or a finer grid for linear damping); ``None`` when none was kept."""
    pairs = getattr(sol, "refinements", ())
    if not pairs:
        return None
    P = (energy_density(sol, energies, shared=shared) if values is None
         else np.asarray(values, float))
    worst = np.zeros(len(P))
    for coarse, fine in pairs:
        d = np.abs(energy_density(fine, energies, shared=shared)
                   - energy_density(coarse, energies, shared=shared))
        worst = np.maximum(worst, d / np.abs(P))
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
    and a grid pair in ``sol.refinements``, the nonlinear dampings' ladders), ``P`` is
    that of the solve one grid step finer, 1.25 times ``sol``'s intervals: the grid's
    error sits in the separatrices' layers (:mod:`._stationary_points`), which ``P(E)``
    samples along one orbit where the moments average it over the plane (SEDF mu = 0.01:
    the last grid step moved ``P`` by 1.2e-5 of its peak, the moments by 2.9e-7).  Then
    ``change`` is that step's change (``sol``'s error, more than the finer solve's) or
    the Hermite pair's of ``sol.refinements``, whichever is larger, plus the quadrature's;
    ``change_peak`` states the finer solve's error as the geometric tail of the grid
    ladder, the step's largest change times ``r/(1 - r)`` with ``r`` :data:`TAIL_SAFETY`
    times the ratio ``q`` of that change to the ladder's last (times 1 when ``r > 1/2``),
    plus the Hermite pair's and the quadrature's largest.  (SEDF at rest, Delta = 3,
    D = mu/2: ``q`` = 0.22 at mu = 0.01, where the changes of the grids 666 -> 833 ->
    1041 -> 1302 at 258 functions fall by 0.23 and 0.22 per step and the solves are
    5.0e-5, 1.3e-5, 2.5e-6, 7.3e-7 of the peak from 362 x 1602; ``q`` = 0.15 at
    mu = 0.02, where the finer solve's error is 0.2 of the step, hence the safety,
    measured at mu = 0.01 to 0.03 as its comment says.)

    The grid step may start in a second process (:mod:`._ahead`; at most ``workers``
    processes, :func:`._ahead.fp_workers`), the same bits.
    """
    from ._ahead import Ahead, fp_workers

    pairs = getattr(sol, "refinements", ())
    grid = [p for p in pairs if p[1].coef is sol.coef
            and p[0].coef.shape[0] == sol.coef.shape[0] and p[0].x.size < sol.x.size]
    with Ahead(lambda: sol.refine(), workers=fp_workers(workers), G=sol.G) as ahead:
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
        # same numbers; SEDF mu = 0.01, 258 and 364 functions: 195 evaluations, not 376;
        # with _chebyshev_values' step, P of the solution and its refinements 4.5 s CPU,
        # not 6.2)
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
        before = float(np.max(np.abs(here - energy_density(grid[0][0], E, shared=shared))))
        hermite = np.zeros(len(P))
        for coarse, fine in pairs:
            if fine.coef.shape[0] != coarse.coef.shape[0]:
                hermite = np.maximum(hermite, np.abs(energy_density(fine, E, shared=shared)
                                                     - energy_density(coarse, E,
                                                                      shared=shared)))
        r = TAIL_SAFETY * float(np.max(step)) / before if before > 0 else 1.0
        tail = r / (1 - r) if r <= 0.5 else 1.0
        change = (np.maximum(step, hermite) + quad) / np.abs(P)
        absolute = tail * float(np.max(step)) + float(np.max(hermite)) + float(np.max(quad))
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
