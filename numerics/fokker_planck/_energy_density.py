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
#: the oversampling of the even orders' values in the angle of the Chebyshev variable, and
#: the points of the Lagrange stencil that interpolates them (:func:`even_order_values`)
OVERSAMPLE = 8
STENCIL = 12
#: the nodes of :func:`energy_density` evaluated together (the velocity functions'
#: recurrence and the values' product; 16384 x 182 orders: 24 MB a temporary)
BATCH = 16384
#: ``prod_{r != q} (q - r)`` of the equispaced stencil
_LAGRANGE_DENOMINATORS = np.array([(-1.0) ** (STENCIL - 1 - q) * math.factorial(q)
                                   * math.factorial(STENCIL - 1 - q) for q in range(STENCIL)])


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


def _oversampled(sol) -> tuple[np.ndarray, int]:
    """``(V, M)``: the even orders' ``c_n`` at the ``M + 1`` angles ``theta_j = j pi/M`` of
    the Chebyshev variable ``t = cos theta`` (``M`` = :data:`OVERSAMPLE` times the solution's
    degree ``m``), from its Chebyshev series zero-padded, by one type-I discrete cosine
    transform (``c(cos theta) = sum_k a_k cos(k theta)`` sampled exactly, up to rounding;
    computed once per solution)."""
    if "oversampled" not in sol._cache:
        from scipy.fft import dct

        a = sol._series()[:, ::2]
        m = a.shape[0] - 1
        M = OVERSAMPLE * max(m, 1)
        padded = np.zeros((M + 1, a.shape[1]))
        padded[:m + 1] = 0.5 * a
        padded[0] = a[0]
        sol._cache["oversampled"] = (dct(padded, type=1, axis=0), M)
    return sol._cache["oversampled"]


def even_order_values(sol, xs: np.ndarray) -> np.ndarray:
    """``c_n(x)`` of the even orders ``n`` (columns) at the positions ``xs`` (rows): the
    Lagrange interpolant of :data:`STENCIL` neighbouring samples of :func:`_oversampled` in
    the angle ``theta`` (reflected at ``theta = 0, pi``, where ``c`` is even in ``theta``),
    one sparse product.  It replaces summing the ``m + 1`` Chebyshev polynomials at each
    node (``O(m)`` a value against ``O(STENCIL)``): a trigonometric polynomial of degree
    ``m`` sampled ``OVERSAMPLE`` times finer than its Nyquist rate is interpolated by
    degree ``STENCIL - 1`` to rounding (measured, SEDF mu = 0.01, 258 x 1041, 4000 nodes
    against the Chebyshev sum: 7e-15 of the largest value with 8 and 12; 1.8e-13 with 8
    and 10, 3e-13 with 4 and 16, 4e-8 with 2 and 12; the sum took 10 times as long)."""
    import scipy.sparse as sps

    V, M = _oversampled(sol)
    p = STENCIL
    s = np.arccos(np.clip(sol._t(np.asarray(xs, float)), -1.0, 1.0)) * (M / np.pi)
    j = np.floor(s).astype(np.int64) - (p // 2 - 1)
    d = (s - j)[:, None] - np.arange(p)  # the node's offsets from the stencil's samples
    before, after = np.ones_like(d), np.ones_like(d)  # prod_{r < q}, prod_{r > q} of d_r
    for q in range(1, p):
        before[:, q] = before[:, q - 1] * d[:, q - 1]
        after[:, p - 1 - q] = after[:, p - q] * d[:, p - q]
    idx = np.abs(j[:, None] + np.arange(p))
    idx = np.where(idx > M, 2 * M - idx, idx)
    S = sps.csr_matrix(((before * after / _LAGRANGE_DENOMINATORS).ravel(), idx.ravel(),
                        np.arange(0, d.size + 1, p)), shape=(d.shape[0], M + 1))
    return S @ V


def _rules(sol, tasks: list, n: int, shared: dict | None) -> list:
    """For each stretch ``(E, a, b)`` of ``tasks``, the ``n``-point rule's ``(w jac/U,
    edge)``: its weights times the Jacobian over ``U`` and the velocity functions' values
    (even orders, columns; :func:`_velocity_edges`), which depend on the solution only
    through its basis, scale and number of functions (the first ``k`` rows of the
    recurrence are the same for any number): ``shared`` keeps them, and the solutions of
    one :func:`energy_density_report` compute them once.  The stretches without them are
    computed together, in batches of about :data:`BATCH` nodes (one recurrence each, not
    one per stretch)."""
    rows = _oversampled(sol)[0].shape[1]
    out, todo = {}, []
    for task in tasks:
        key = (sol.basis, sol.sigma, *task, n)
        if shared is not None and key in shared and shared[key][1].shape[1] >= rows:
            out[task] = shared[key]
        else:
            todo.append(task)
    t, w = _gauss_legendre(n)
    step = max(1, BATCH // n)
    for i in range(0, len(todo), step):
        batch = todo[i:i + step]
        E = np.repeat([e for e, _, _ in batch], n)
        a = np.repeat([a for _, a, _ in batch], n)
        b = np.repeat([b for _, _, b in batch], n)
        tt, ww = np.tile(t, len(batch)), np.tile(w, len(batch))
        xs = 0.5 * (a + b) + 0.5 * (b - a) * np.sin(0.5 * np.pi * tt)
        jac = 0.25 * np.pi * (b - a) * np.cos(0.5 * np.pi * tt)
        U = np.sqrt(np.maximum(2 * (E - np.asarray(sol.G(xs), float)), 1e-300)) / sol.sigma
        weight = ww * jac / U
        edge = _velocity_edges(sol, 2 * rows, U).T
        for k, task in enumerate(batch):
            rule = (weight[k * n:(k + 1) * n], edge[k * n:(k + 1) * n])
            out[task] = rule
            if shared is not None:
                shared[(sol.basis, sol.sigma, *task, n)] = rule
    return [out[task] for task in tasks]


def _stretch_densities(sol, tasks: list, n: int, shared: dict | None) -> np.ndarray:
    """Each stretch's share of ``P(E)`` by the ``n``-point rule (:func:`_rules`; the even
    orders' values at the nodes by :func:`even_order_values`, all stretches at once)."""
    if not tasks:
        return np.empty(0)
    rules = _rules(sol, tasks, n, shared)
    rows = _oversampled(sol)[0].shape[1]
    t = _gauss_legendre(n)[0]
    xs = np.concatenate([0.5 * (a + b) + 0.5 * (b - a) * np.sin(0.5 * np.pi * t)
                         for _, a, b in tasks])
    weight = np.concatenate([r[0] for r in rules])
    out = np.empty(len(tasks))
    step = max(1, BATCH // n)
    for i in range(0, len(tasks), step):
        c = even_order_values(sol, xs[i * n:(i + step) * n])  # nodes, even orders
        edge = np.concatenate([r[1][:, :rows] for r in rules[i:i + step]])
        f = weight[i * n:(i + step) * n] * np.einsum("ij,ij->i", c, edge)
        out[i:i + step] = f.reshape(-1, n).sum(axis=1)
    return out / sol.sigma**2


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

    energies = np.atleast_1d(np.asarray(energies, float))
    owner, tasks = [], []  # each stretch (E, a, b) and the index of its energy
    for i, E in enumerate(energies):
        for a, b in _stretches(sol, float(E), shared):
            owner.append(i)
            tasks.append((float(E), a, b))
    last, done = [None] * len(tasks), [None] * len(tasks)
    # each stretch's first rule: at least as many nodes as the solution has points in the
    # stretch (the integrand is of the solution's degree in its map's variable; fewer nodes
    # cannot resolve it, and two such rules may agree by chance: SEDF mu = 0.02, 182 x 927,
    # E = 1.59, the rules of 64 and 128 nodes agreed to 1e-9 and were both 1.2e-7 off)
    inside = [int(np.count_nonzero((sol.x > a) & (sol.x < b))) for _, a, b in tasks]
    start = [max(nodes, 1 << max(0, c - 1).bit_length()) for c in inside]
    n, active = nodes, list(range(len(tasks)))
    with one_blas_thread():
        while active:  # every stretch's rule doubled until two agree (all stretches at once)
            now = [k for k in active if start[k] <= n]
            vals = _stretch_densities(sol, [tasks[k] for k in now], n, shared)
            for k, v in zip(now, vals):
                if last[k] is not None and (abs(v - last[k]) <= rtol * abs(v) or n >= most):
                    done[k] = (v, abs(v - last[k]))
                last[k] = v
            active = [k for k in active if done[k] is None]
            n *= 2
    out, err = np.zeros(len(energies)), np.zeros(len(energies))
    for i, (v, miss) in zip(owner, done):  # summed in the stretches' order, as before
        out[i] += v
        err[i] += miss
    sol._cache[key] = (out, err)
    return (out.copy(), err.copy()) if quadrature else out.copy()


def _stretches(sol, E: float, shared: dict | None) -> list:
    """``sol.stretches(E)``, kept in ``shared`` for the other solutions of the same
    potential and range (the same roots)."""
    if shared is None:
        return sol.stretches(E)
    key = ("stretches", sol.G, float(sol.x[0]), E)
    if key not in shared:
        shared[key] = sol.stretches(E)
    return shared[key]


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
