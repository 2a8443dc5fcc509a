"""The stationary Kramers (Fokker-Planck) equation of a one-degree-of-freedom model at rest,
solved numerically: a route that owes nothing to averaging or to simulation.

For ``x'' = -g(x) + mu h(x, x') + sqrt(2 D) xi(t)`` the density ``P(x, v)`` obeys

``dP/dt = -v dP/dx + d/dv[(g(x) - mu h(x, v)) P] + D d^2P/dv^2``

(Risken, *The Fokker-Planck Equation*, 2nd ed., ch. 10).  The method is a spectral
Galerkin-collocation discretisation: Hermite functions of the velocity (Risken's choice,
sec. 10.3, with the scale ``sigma`` of the velocity set to the measured ``sqrt(<v^2>)``)
times Chebyshev collocation in the position on ``[-L, L]`` (``L`` where ``G/sigma^2``
exceeds 45 above its minimum).  Why this and not Risken's matrix continued fractions:

* the damping of the models is nonlinear in ``x`` and ``v`` (van der Pol, Rayleigh, the
  SEDF), which couples Hermite orders ``n`` to ``n +- 3``: the continued fraction would
  need blocks of three orders, and the potentials (``x^2/2`` plus a cosine) are neither
  periodic nor polynomial, so the position operators are dense in any global basis anyway;
* Chebyshev collocation converges exponentially for the analytic potentials and densities
  here, and the whole operator is a sparse matrix (block-banded in ``n``) that one sparse
  LU factorises in about a second; the same matrix gives the escape rate as its smallest
  nonzero eigenvalue (shift-invert Arnoldi; there the matrix is factorised block by block in
  the Hermite index, :mod:`._blocks`, the continued fraction's elimination in LU form).

The stationary equation's ``n = 0`` block says that the current ``sigma c_1`` is constant;
it is replaced by ``c_1 = 0`` (no current through the far ends, where the density is below
``exp(-45)``) at all points but one, and the normalisation ``int c_0 dx = 1``.

That is Risken's pair on one Chebyshev grid (``basis="risken"``), until the twenty-ninth
session the route of a linear damping; it is now solved on spectral elements with its error
measured (:mod:`._linear_elements`: the pair's grid residual, amplified by ``1/mu``, put
the CDC at mu = 0.001 1.1e-5 off Boltzmann with a stated error of 0; the elements are
1e-15 off at mu = 0.15 to 1e-4).  A nonlinear damping is solved in
orthonormal Hermite functions with Galerkin projection (:mod:`._stationary_orthonormal`):
in Risken's pair every high order grows wherever the local friction is negative
(:mod:`._orthonormal`), and the SEDF at rest (mu = 0.1, Delta = 3, D = 0.05) did not
converge (``<x^2>`` = 2.2164, 2.2770, 2.3148 at 64, 128, 256 functions; 2.32852184 in the
orthonormal functions, stated change 7.4e-8, and 2.32852186 on another grid).

Checks (tests/test_fokker_planck.py): for linear damping the solution is the Boltzmann
density ``exp(-H/kT)`` to 1e-9 (quadrature of ``exp(-G/kT)``); for the van der Pol
oscillator it agrees with first-order stochastic averaging as ``mu -> 0`` and with a
fixed-seed Langevin ensemble within its standard errors.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import operator

import numpy as np
import scipy.sparse as sps
import sympy as sp

from kbm.model.conservative import ConservativeSplit, split_conservative
from kbm.errors import ModelError, ParameterError
from kbm.parameters.names import noise_intensity

from ._bases import cheb, clenshaw_curtis, hermite_matrices
from ._blocks import on_one_blas_thread
from ._model import _chebyshev_size, _half_width, velocity_terms
from ._solution import KramersSolution
from ._stationary_orthonormal import stationary_orthonormal

__all__ = ["kramers_operator", "kramers_terms", "stationary_kramers"]


def kramers_operator(split: ConservativeSplit, D: float, sigma: float, L: float,
                     n_hermite: int, n_cheb: int):
    """The Kramers operator as a sparse matrix on ``c[n, i]`` (row ``n * (n_cheb+1) + i``),
    with the points and weights.

    Returns
    -------
    (scipy.sparse.csr_matrix, numpy.ndarray, numpy.ndarray)
    """
    terms, xs, w = kramers_terms(split, D, sigma, L, n_hermite, n_cheb)
    ops = [sps.kron(H, sps.csr_matrix(X) if X.ndim == 2 else sps.diags(X))
           for H, X in terms]
    return functools.reduce(operator.add, ops).tocsr(), xs, w


def kramers_terms(split: ConservativeSplit, D: float, sigma: float, L: float,
                  n_hermite: int, n_cheb: int):
    """The Kramers operator as ``sum_j kron(H_j, X_j)``: ``H_j`` sparse in the Hermite
    index, ``X_j`` the dense Chebyshev differentiation matrix or (1-D) a diagonal.

    Returns
    -------
    (list of (scipy.sparse.csr_matrix, numpy.ndarray), numpy.ndarray, numpy.ndarray)
        The terms, the points and the Clenshaw-Curtis weights.
    """
    terms = velocity_terms(split)
    kmax = max([k for k, _ in terms], default=1)
    xs, Dx = cheb(n_cheb, L)
    g = split.numpy_functions()[0]
    U, Du = hermite_matrices(n_hermite, kmax + 2)
    N = n_hermite

    def cut(M):
        return sps.csr_matrix(M[:N, :N])

    out = [(cut(-sigma * U), Dx), (cut(Du / sigma), np.asarray(g(xs), float)),
           (cut(Du @ Du * (D / sigma**2)), np.ones(xs.size))]
    for k, a in terms:
        Uk = sps.identity(N + kmax + 2, format="csr")
        for _ in range(k):
            Uk = U @ Uk
        out.append((cut(-(sigma ** (k - 1)) * (Du @ Uk)), np.asarray(a(xs), float)))
    return out, xs, clenshaw_curtis(n_cheb, L)


@on_one_blas_thread
def stationary_kramers(model, params: dict, D: float, *, n_hermite: int | None = None,
                       n_cheb: int | None = None, sigma: float | None = None,
                       L: float | None = None, omega0: float | None = None,
                       tol: float | None = None, max_cost: float = 2e7,
                       basis: str | None = None, workers: int | None = None,
                       refine_ahead: bool = False,
                       elements: tuple[int, int] | None = None) -> KramersSolution:
    """The stationary solution of the Kramers equation.

    Parameters
    ----------
    model : str or kbm.model.builtins.Oscillator
        An autonomous model (a slider at ``v = 0``) whose damping is polynomial in ``x'``.
    params : dict
        Its parameters with ``mu`` (``D`` apart).
    D : float
        Noise intensity, ``> 0``.
    n_hermite, n_cheb : int, optional
        Hermite functions of the velocity and Chebyshev intervals in the position.
        Default for linear damping: :func:`._linear_elements.linear_stationary` (12
        functions on the elements that resolve ``exp(-G/kT)``, the error the change on
        1.25 times the elements); given either, Risken's pair with 12 functions and
        ``n_cheb`` that resolves ``exp(-G/kT)`` to 1e-9.  For a nonlinear damping the ladders of
        :func:`._stationary_orthonormal.stationary_orthonormal` (Hermite functions
        ``32 * 2^(k/2)``, then the intervals by 1.25, each until ``<x^2>`` and ``<v^2>``
        change by less than ``tol`` or the budget ends); the larger last change is the
        solution's ``hermite_change``, its stated truncation error.  For a nonlinear
        damping whose potential has saddles on the range (the multi-well SEDF) with
        neither given, the element ladder (``basis="elements"``).  With
        ``basis="risken"`` the number of functions is doubled from 32 and the last solve
        runs on 1.5 times the intervals (the previous method).
    sigma, L : float, optional
        Velocity scale and half-width of the position range (default: ``sigma^2 = kT`` for
        linear damping; for a nonlinear damping the scale that resolves the density's
        reach and velocity structure, :func:`._stationary_orthonormal.stationary_orthonormal`;
        ``L`` where ``G mu/D`` exceeds 45 above its minimum).
    omega0 : float, optional
        The frequency of ``a^2`` (default the model's ``omega0``, else ``sqrt(g'(0))``).
    tol : float, optional
        Relative change of ``<x^2>`` and ``<v^2>`` at which the Hermite (and, in the
        orthonormal functions, the Chebyshev) ladder stops (default 1e-8; the element
        ladder's :data:`._elements_ladder.TOL`, 1e-7, a tenth of six digits, as its stated
        error is the sum of its two last changes).
        (It tested ``<a^2>`` alone and stopped at 128 functions whatever the change: for the
        SEDF at mu = 0.1, Delta = 3, D = 0.05 ``<a^2>`` moved by 5e-5 from 128 to 256
        functions while ``<x^2>`` moved by 1.7e-2, and 2.2764 was printed to ten digits
        against a simulated 2.321 +- 0.006.)
    max_cost : float
        Largest ``n_hermite * n_cheb^2`` (the nonzeros of the operator, about; the sparse
        LU's work grows with it): beyond it the solve is refused with the sizes.  For a
        model symmetric under ``(x, v) -> (-x, -v)`` in orthonormal functions, solved on
        ``x >= 0`` (:mod:`._parity`), ``n_hermite * (n_cheb/2)^2``; its ladder may climb
        one Hermite rung more on grids of up to
        :data:`._stationary_orthonormal.CLIMB_COST` times it when the functions, not the
        grid, limit six digits (step 7 of
        :func:`._stationary_orthonormal.stationary_orthonormal`); a solve whose factors
        would exceed :data:`._pentadiagonal_disk.FACTOR_MEMORY` bytes in memory keeps them
        on disk (the same solution; the budget then bounds the time, not the memory).
        The element ladder's cost is 0.6 ``n_hermite^2 E`` (``E/2`` folded), about its
        peak memory in units of 100 bytes
        (:data:`._elements_ladder.COST_SHARE`).
    basis : {None, "orthonormal", "risken", "elements"}
        The velocity functions.  Default: for linear damping, where ``sigma^2 = kT``
        makes the Maxwellian one function, the orthonormal functions on spectral elements
        (:mod:`._linear_elements`; Risken's pair, :mod:`._bases`, when sizes are given or
        with ``"risken"``); the orthonormal
        Hermite functions with Galerkin projection (:mod:`._stationary_orthonormal`, its
        own choice of ``sigma``, points and sizes) for a nonlinear damping, where Risken's
        pair grows every high order wherever the local friction is negative
        (:mod:`._orthonormal`; the SEDF at mu = 0.1, Delta = 3, D = 0.05 gave
        ``<x^2>`` = 2.2164, 2.2770, 2.3148 at 64, 128, 256 functions).  ``"risken"``
        forces the old discretisation (a second method for comparisons).  For a
        nonlinear damping whose potential has saddles on the range (the multi-well SEDF)
        and no sizes given, the default is ``"elements"``: the orthonormal functions
        times spectral elements in ``x``, with the ladder of
        :func:`._elements_ladder.element_ladder` (SEDF at rest, Delta = 3, D = mu/2,
        mu = 0.005 at ``max_cost`` 2.5e7, ``kbm noise``'s budget: stated 3.9e-7 on 512
        functions x 148 elements in 25 s user + 6 s system CPU, 1.33 GB, one process
        (3.0e-7 on 512 x 240 with ``refine_ahead``, 42 s CPU with ``P(E)``, 1.88 GB), where the
        Chebyshev ladder states 3.9e-6 at that budget and took 164 s CPU and 3.2 GB at
        8.6e7 for 5.6e-7).  ``"orthonormal"`` keeps the Chebyshev ladder there.
    workers : int, optional
        At most this many processes for the orthonormal and element ladders' independent
        solves
        (:mod:`._ahead`; default :func:`._ahead.fp_workers`, ``KBM_FP_WORKERS`` or 2); the
        solution is the same bits whatever it is.
    refine_ahead : bool
        ``P(E)`` will be wanted (:func:`._energy_density.energy_density_report`): the
        orthonormal ladder may start its grid step early, in its second process (the same
        bits; the solution's ``refine`` hands it on); the element ladder chooses its
        elements for ``P(E)`` too (:func:`._elements_ladder.element_ladder`).
    elements : (int, int), optional
        ``(E, p)``: instead, one solve on ``E`` spectral elements of the odd degree ``p``
        in the position (:mod:`._elements`, :func:`._elements_solve.element_stationary`)
        times ``n_hermite`` orthonormal Hermite functions (required), with the scale,
        range and element centres of the orthonormal ladder's first steps (``sigma^2 =
        kT`` for linear damping); no ladder: its ``hermite_change`` is ``nan`` (no stated
        error).  Default ``None``: the routes above.

    Returns
    -------
    KramersSolution

    Raises
    ------
    kbm.errors.ParameterError
        ``D <= 0`` or ``mu <= 0``; ``elements`` the element solve cannot use (an odd
        number of elements, an even degree) or without ``n_hermite``; ``basis`` not one
        of those named, or ``"elements"`` with ``n_hermite`` or ``n_cheb`` but no
        ``elements``.
    kbm.errors.ModelError
        A driven or non-confining model, or a damping not polynomial in ``x'``.
    """
    D = noise_intensity(D, "the Kramers equation needs noise")
    params = {k: v for k, v in dict(params).items() if k != "D"}
    split = split_conservative(model, params)
    mu = float(split.mu)
    if not mu > 0:
        raise ParameterError(f"mu = {mu:g} must be > 0")
    G = split.numpy_functions()[2]
    if omega0 is None:
        w0 = sp.sympify(split.model.omega0).subs({sp.Symbol(k): v
                                                  for k, v in split.params.items()})
        omega0 = (float(w0) if w0.is_number
                  else math.sqrt(float(split.numpy_functions()[1](np.array(0.0)))))
    terms = velocity_terms(split)
    kT = _linear_temperature(terms, D)
    if basis not in (None, "orthonormal", "risken", "elements"):
        raise ParameterError(f"basis = {basis!r}: use 'orthonormal', 'risken' or 'elements'")
    if basis == "elements" and elements is None and (n_hermite is not None
                                                     or n_cheb is not None):
        raise ParameterError("basis = 'elements' chooses its own sizes: leave out n_hermite "
                             "and n_cheb, or give elements=(E, p) with n_hermite for one "
                             "solve at those sizes")
    if elements is not None:
        from ._elements_solve import element_kramers, element_sizes

        E, p = element_sizes(elements, n_hermite)
        return element_kramers(split, None, D, n_hermite=int(n_hermite), elements=E, degree=p,
                               sigma=math.sqrt(kT) if sigma is None and kT is not None
                               else sigma, L=L, omega0=float(omega0), well=kT is None)
    if basis == "elements" or (basis is None and kT is None and n_hermite is None
                               and n_cheb is None and _has_saddles(split, G, D, L)):
        from ._elements_ladder import element_ladder

        return element_ladder(split, D, G, float(omega0), sigma=sigma, L=L, tol=tol,
                              max_cost=max_cost, workers=workers, refine_ahead=refine_ahead)
    tol = 1e-8 if tol is None else float(tol)
    if basis == "orthonormal" or (basis is None and kT is None):
        return stationary_orthonormal(split, D, G, float(omega0), n_hermite=n_hermite,
                                      n_cheb=n_cheb, sigma=sigma, L=L, tol=tol,
                                      max_cost=max_cost, workers=workers,
                                      refine_ahead=refine_ahead)
    if kT is not None and basis is None and n_hermite is None and n_cheb is None:
        from ._linear_elements import linear_stationary

        return linear_stationary(split, D, kT, G, float(omega0), L=L, sigma=sigma, tol=tol)
    if sigma is not None:
        s2 = float(sigma) ** 2
    elif kT is not None:
        s2 = kT
    else:  # a coarse solve measures <v^2> and the extent of the density
        half = _half_width(G, D / mu) if L is None else float(L)
        pilot = _solve(split, D, math.sqrt(D / mu), half, 32,
                       _chebyshev_size(G, D / mu, half), G, omega0)
        s2 = pilot.v2
        if not (math.isfinite(s2) and s2 > 0):
            raise ModelError(f"the coarse Kramers solve gave <v^2> = {s2}: no stationary "
                             "density (check that the damping confines the motion)")
        if L is None:  # where the marginal falls below 1e-12 of its peak, and 30 % more
            c0 = np.abs(pilot.coef[0])
            held = np.abs(pilot.x[c0 > 1e-12 * float(np.max(c0))])
            L = min(half, 1.3 * float(np.max(held)))
        if kT is None and sigma is None:
            s2 = pilot.v2
    half = _half_width(G, s2) if L is None else float(L)
    scale = s2 if kT is not None else min(s2, D / mu)
    nc = _chebyshev_size(G, scale, half) if n_cheb is None else int(n_cheb)
    nh = (12 if kT is not None else 32) if n_hermite is None else int(n_hermite)
    if nh * nc**2 > max_cost:
        raise ModelError(f"the Kramers solve needs {nh} Hermite functions x {nc + 1} Chebyshev "
                         f"points (cost {nh * nc**2:.3g} > {max_cost:.3g}): not affordable here")
    sol = _solve(split, D, math.sqrt(s2), half, nh, nc, G, omega0)
    if n_hermite is not None:
        return sol
    if kT is not None:
        return dataclasses.replace(sol, hermite_change=0.0)
    change = math.inf  # doubled while both moments move and the budget allows
    while change > tol and 2 * nh * nc**2 <= max_cost:
        nh *= 2
        new = _solve(split, D, math.sqrt(s2), half, nh, nc, G, omega0)
        change = max(abs(new.x2 - sol.x2) / abs(new.x2), abs(new.v2 - sol.v2) / abs(new.v2))
        sol = new
    finer = 2 * math.ceil(0.75 * nc)
    if n_cheb is None and nh * finer**2 <= max_cost:
        # a nonlinear damping's density is not exp(-G/sigma^2), which set nc: 1.5 times
        # the intervals (vdp mu = 0.3, D = 0.15: <x^2> 1.1e-6 low on 88, 6e-10 on 132)
        sol = _solve(split, D, math.sqrt(s2), half, nh, finer, G, omega0)
    return dataclasses.replace(sol, hermite_change=change)


def _has_saddles(split, G, D: float, L: float | None) -> bool:
    """Whether ``G`` has an interior maximum (``g`` turns from positive to negative) on the
    range ``[-L, L]`` (default :func:`._model._half_width` at ``D/mu``): the multi-well
    potentials, whose separatrices' layers the element ladder resolves
    (:mod:`._elements_ladder`)."""
    half = _half_width(G, D / float(split.mu)) if L is None else float(L)
    gz = np.asarray(split.numpy_functions()[0](np.linspace(-half, half, 20001)), float)
    return bool(np.any((gz[:-1] > 0) & (gz[1:] <= 0)))


def _linear_temperature(terms, D: float) -> float | None:
    """``kT = D/c`` when ``mu h = -c v`` with a constant ``c > 0``, else ``None``."""
    if len(terms) != 1 or terms[0][0] != 1:
        return None
    vals = terms[0][1](np.linspace(-3.0, 3.0, 7))
    c = -float(vals[0])
    return D / c if c > 0 and np.allclose(vals, vals[0], rtol=0, atol=1e-15) else None


def _solve(split, D, sigma, half, nh, nc, G, omega0) -> KramersSolution:
    """One stationary solve: the constrained operator factorised block by block in the
    Hermite index (:mod:`._blocks`; 1.1-2.3 times faster than SuperLU on the vdp and CDC
    cases of tests/test_fokker_planck.py, the same moments to 1e-10), SuperLU when a
    Schur complement is singular (the block LU does not pivot across blocks)."""
    import scipy.sparse.linalg as spla

    from ._blocks import BlockTridiagonalLU, one_blas_thread

    A, xs, w = kramers_operator(split, D, sigma, half, nh, nc)
    m = xs.size
    A = _constrained(A, w, nh, m)
    b = np.zeros(A.shape[0])
    b[m - 1] = 1.0
    try:
        with one_blas_thread():
            c = BlockTridiagonalLU(A, m).solve(b)
        if not np.all(np.isfinite(c)):
            raise np.linalg.LinAlgError("a non-finite block solve")
    except np.linalg.LinAlgError:
        c = spla.splu(A).solve(b)
    c = c.reshape(nh, m)
    return KramersSolution(xs, w, c, sigma, G, float(omega0), _residual(c))


def _constrained(A, w: np.ndarray, n: int, m: int):
    """``A`` with its rows replaced: block ``0`` by ``c_1 = 0`` at all points but the last
    and ``int c_0 dx = 1`` (that row's right-hand side is 1); the two end points of every
    block n >= 2 by ``c_n(+-L) = 0`` (the density is below ``exp(-45)`` there)."""
    keep = np.ones(n * m)
    keep[:m] = 0.0
    ends = np.concatenate([[k * m, k * m + m - 1] for k in range(2, n)])
    keep[ends] = 0.0
    rows = list(range(m - 1)) + [m - 1] * m + list(ends)
    cols = list(range(m, 2 * m - 1)) + list(range(m)) + list(ends)
    vals = [1.0] * (m - 1) + list(w) + [1.0] * len(ends)
    C = sps.csr_matrix((vals, (rows, cols)), shape=A.shape)
    return (sps.diags(keep) @ A + C).tocsc()


def _residual(c: np.ndarray) -> float:
    from numpy.polynomial import chebyshev as C

    big = float(np.max(np.abs(c)))
    herm = float(np.max(np.abs(c[-2:])))
    modes = C.chebfit(np.cos(np.pi * np.arange(c.shape[1]) / (c.shape[1] - 1)), c[0],
                      c.shape[1] - 1)
    return max(herm, float(np.max(np.abs(modes[-4:])))) / big
