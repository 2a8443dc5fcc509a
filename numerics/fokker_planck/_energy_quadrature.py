"""The quadrature of ``P(E)`` of a stationary Kramers solution (:func:`energy_density`, what
:mod:`._energy_density` reports): on each stretch ``a < x < b`` where ``G < E``, with
``U = (2 (E - G(x)))^(1/2)/s``,

``int_a^b dx sum_n c_n(x) b_n(U)/(s^2 U)``, ``b_n = f_n(U) + f_n(-U)``

(``2 f_n(U)`` for even ``n``, 0 for odd; :func:`_velocity_edges`).  The substitution
``x = (a + b)/2 + (b - a)/2 sin(pi t/2)`` makes the ends' ``1/U ~ (b - x)^(-1/2)`` smooth,
and Gauss-Legendre rules in ``t`` are doubled until two agree, from a rule of at least as
many nodes as the solution has points in the stretch.

The work is the values ``c_n`` of the even orders at the nodes: summing the ``m + 1``
Chebyshev polynomials costs ``O(m)`` a value (SEDF mu = 0.01, 258 x 1041: 70 Gflop over
the solutions of one report, 8 s CPU); :func:`even_order_values` interpolates them from
samples eight times finer than the degree in the angle of the Chebyshev variable, ``O(12)``
a value, to rounding.  The stretches of every energy are evaluated together, a batch of
nodes at a time (one velocity recurrence and one sparse product each).

On a spectral-element solution (:mod:`._elements_solve`) the stretches are cut at the
elements' ends (its ``pieces``: the values are piecewise polynomials, continuous but not
smooth across an end), the first rule of each piece has its ``quadrature_nodes`` (16), and
the values come from its own ``even_order_values`` (each element's Lagrange polynomial,
one sparse product): SEDF at rest, mu = 0.01, 362 functions on 124 elements, 0.7 s CPU,
2342 pieces, 474 of them doubled past 32 nodes.
"""

from __future__ import annotations

import functools
import math

import numpy as np

__all__ = ["energy_density", "even_order_values", "stretches_shared", "OVERSAMPLE",
           "STENCIL", "BATCH"]

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
    kept in the solution's cache until :func:`energy_density` ends)."""
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


def _even_orders(sol) -> int:
    """The number of even orders ``0, 2, ...`` of the solution's Hermite functions."""
    return (sol.coef.shape[0] + 1) // 2


def _even_values(sol, xs: np.ndarray) -> np.ndarray:
    """:func:`even_order_values`, or the solution's own (``sol.even_order_values``: the
    elements' Lagrange polynomials, :mod:`._elements_solve`)."""
    own = getattr(sol, "even_order_values", None)
    return own(xs) if own is not None else even_order_values(sol, xs)


def _rules(sol, tasks: list, n: int, shared: dict | None) -> list:
    """For each stretch ``(E, a, b)`` of ``tasks``, the ``n``-point rule's ``(w jac/U,
    edge)``: its weights times the Jacobian over ``U`` and the velocity functions' values
    (even orders, columns; :func:`_velocity_edges`), which depend on the solution only
    through its basis, scale and number of functions (the first ``k`` rows of the
    recurrence are the same for any number): ``shared`` keeps them, and the solutions of
    one :func:`energy_density_report` compute them once.  The stretches without them are
    computed together, in batches of about :data:`BATCH` nodes (one recurrence each, not
    one per stretch)."""
    rows = _even_orders(sol)
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
    rows = _even_orders(sol)
    t = _gauss_legendre(n)[0]
    xs = np.concatenate([0.5 * (a + b) + 0.5 * (b - a) * np.sin(0.5 * np.pi * t)
                         for _, a, b in tasks])
    weight = np.concatenate([r[0] for r in rules])
    out = np.empty(len(tasks))
    step = max(1, BATCH // n)
    for i in range(0, len(tasks), step):
        c = _even_values(sol, xs[i * n:(i + step) * n])  # nodes, even orders
        edge = np.concatenate([r[1][:, :rows] for r in rules[i:i + step]])
        f = weight[i * n:(i + step) * n] * np.einsum("ij,ij->i", c, edge)
        out[i:i + step] = f.reshape(-1, n).sum(axis=1)
    return out / sol.sigma**2


def energy_density(sol, energies, rtol: float = 1e-8, nodes: int | None = None,
                   most: int = 2048,
                   quadrature: bool = False, shared: dict | None = None):
    """``P(E)`` of the stationary solution ``sol`` at each of ``energies`` (module
    docstring): Gauss-Legendre rules of ``nodes`` (default the solution's
    ``quadrature_nodes``, else 64), or of the power of two at or above the
    solution's points in the stretch if more, doubled on each stretch until two agree to
    ``rtol`` (relative) or ``most`` nodes (near a separatrix energy, whose logarithmic
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
        (:func:`_rules`; the same numbers).

    Returns
    -------
    numpy.ndarray, or (numpy.ndarray, numpy.ndarray) with ``quadrature``
    """
    if nodes is None:  # 64; 16 on each element of an element solution (._elements_solve)
        nodes = getattr(sol, "quadrature_nodes", 64)
    key = ("energy_density", np.asarray(energies, float).tobytes(), rtol, nodes, most)
    if key in sol._cache:  # a coarse solution shared by two refinements is evaluated once
        P, miss = sol._cache[key]
        return (P.copy(), miss.copy()) if quadrature else P.copy()
    from ._blocks import one_blas_thread

    energies = np.atleast_1d(np.asarray(energies, float))
    owner, tasks = [], []  # each stretch (E, a, b) and the index of its energy
    for i, E in enumerate(energies):
        for a, b in stretches_shared(sol, float(E), shared):
            owner.append(i)
            tasks.append((float(E), a, b))
    last, done = [None] * len(tasks), [None] * len(tasks)
    # each stretch's first rule: at least as many nodes as the solution has points in the
    # stretch (the integrand is of the solution's degree in its map's variable; fewer nodes
    # cannot resolve it, and two such rules may agree by chance: SEDF mu = 0.02, 182 x 927,
    # E = 1.59, the rules of 64 and 128 nodes agreed to 1e-9 and were both 1.2e-7 off)
    inside = [int(np.count_nonzero((sol.x > a) & (sol.x < b))) for _, a, b in tasks]
    # (at most half ``most``, so that no rule exceeds it: the ends' rounding of ``E - G``
    # grows with the square of the nodes; SEDF mu = 0.01, 258 x 1301, 975 points at most)
    start = [min(max(nodes, 1 << max(0, c - 1).bit_length()), max(nodes, most // 2))
             for c in inside]
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
    sol._cache.pop("oversampled", None)  # 19 MB at 364 functions x 1601 points, not kept
    return (out.copy(), err.copy()) if quadrature else out.copy()


def stretches_shared(sol, E: float, shared: dict | None) -> list:
    """``sol.stretches(E)`` (an element solution's ``pieces``), kept in ``shared`` for the
    other solutions of the same potential and range (the same roots; the same elements)."""
    ranges = getattr(sol, "pieces", sol.stretches)  # an element solution's: cut at its ends
    if shared is None:
        return ranges(E)
    key = ("stretches", sol.G, float(sol.x[0]), E, getattr(sol, "edges", ()))
    if key not in shared:
        shared[key] = ranges(E)
    return shared[key]
