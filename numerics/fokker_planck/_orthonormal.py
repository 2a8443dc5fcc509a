"""The escape rate of a nonlinearly damped model in orthonormal Hermite functions of the
velocity (:func:`nonlinear_escape`, what :func:`.escape.kramers_escape` runs when the
damping is not ``-gamma x'``).

Why not the Hermite functions of :mod:`._bases` (Risken's ``He_n(u) exp(-u^2/2)``, tested
against ``He_n``): in that pair of bases the friction and diffusion of the Kramers operator
act on the order ``n`` as ``-n gamma(x)`` plus a coupling to ``n + 2`` (Risken, *The
Fokker-Planck Equation*, 2nd ed., eq. 10.51 with ``gamma`` the local friction), whatever
the scale.  A self-exciting damping ``mu (beta x^2 - 1) x'`` has ``gamma(x) < 0`` for
``beta x^2 < 1`` (the whole well of the SEDF at rest and the sink at the next wells'
bottoms), so every high order *grows* there at ``n |gamma|``: the truncated matrix has
spurious growing orders, the slowest mode's coefficients rise toward the top order
(SEDF, mu = 0.1, Delta = 3, D = 0.05, 256 orders: the last order 90 times the largest
``c_0``) and the rate wanders by 1e-4 with the truncation and with the Chebyshev points
(1448 orders: still 3e-5 apart).

Here the density is expanded in the orthonormal functions
``h_n(xi) = H_n(xi) exp(-xi^2/2)/(2^n n! sqrt(pi))^(1/2)``, ``xi = v/s``, and each
equation projected on the same functions (Galerkin in ``L^2(dv)``).  In that inner
product ``-v d/dx`` and ``g(x) d/dv`` are skew, the diffusion ``D d^2/dv^2`` is negative
and the friction term ``-d/dv(a(x) v P)`` adds only ``-a(x)/2``: the truncated velocity
operator is bounded above by half the largest friction whatever ``n``, so no order grows
spuriously, and the coefficients decay spectrally (the SEDF case: 12 digits with 64
functions).  The multiplications by ``xi`` and ``d/dxi`` are tridiagonal,
``xi h_n = sqrt((n+1)/2) h_{n+1} + sqrt(n/2) h_{n-1}`` and
``h_n' = sqrt(n/2) h_{n-1} - sqrt((n+1)/2) h_{n+1}``.

The scale ``s`` of the velocity: the functions up to ``N`` resolve ``pi s/sqrt(2 N)`` and
reach ``s sqrt(2 N)``.  The density has a layer of width ``delta = (D/omega_b)^(1/2)`` in
the velocity along the separatrix (:mod:`.escape`) and reaches ``V``, the speed at the
well's bottom for an energy a few ``D/mu`` above the barrier; both are resolved with
``N = pi V/delta`` functions at ``s = (delta V/(2 pi))^(1/2)`` (:func:`velocity_scale`).
The ladder keeps ``s`` and grows ``N`` by ``sqrt 2`` (reach and resolution both grow);
its last rung is recomputed at the scale ``1.3 s`` (another basis), and that change is
``scale_error``.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sps

from ._blocks import BlockTridiagonalLU, TermBlocks, one_blas_thread
from ._ladder import hermite_chebyshev_ladder
from ._model import velocity_terms

__all__ = ["orthonormal_matrices", "orthonormal_terms", "velocity_scale",
           "orthonormal_slowest", "nonlinear_escape", "OTHER_SCALE"]

#: the second velocity scale, in units of the first (the independent check)
OTHER_SCALE = 1.3


def orthonormal_matrices(n: int):
    """``(X, Dxi)``: multiplication by ``xi`` and ``d/dxi`` on the coefficients of
    ``h_0 .. h_{n-1}`` (sparse; ``X`` symmetric, ``Dxi`` skew)."""
    k = np.arange(n - 1)
    up = np.sqrt((k + 1.0) / 2)
    X = sps.diags([up, up], [-1, 1], shape=(n, n), format="csr")
    Dxi = sps.diags([-up, up], [-1, 1], shape=(n, n), format="csr")
    return X, Dxi


def orthonormal_terms(split, D: float, s: float, xs: np.ndarray, Dx: np.ndarray,
                      n_hermite: int) -> list:
    """The Kramers operator ``-v dP/dx + g dP/dv - d/dv(mu h P) + D d^2P/dv^2`` as
    ``sum_j kron(H_j, X_j)`` in the orthonormal functions of ``v/s`` times the points
    ``xs`` (``X_j`` the differentiation matrix ``Dx`` or, 1-D, a diagonal).  The products
    of ``xi`` and ``d/dxi`` are formed on ``k_max + 2`` extra orders and cut: the Galerkin
    projection of each product exactly."""
    terms = velocity_terms(split)
    kmax = max([k for k, _ in terms], default=1)
    big = n_hermite + kmax + 2
    X, Dq = orthonormal_matrices(big)
    g = split.numpy_functions()[0]

    def cut(M):
        return sps.csr_matrix(M[:n_hermite, :n_hermite])

    out = [(cut(-s * X), Dx), (cut(Dq / s), np.asarray(g(xs), float)),
           (cut(Dq @ Dq * (D / s**2)), np.ones(xs.size))]
    for k, a in terms:
        Xk = sps.identity(big, format="csr")
        for _ in range(k):
            Xk = X @ Xk
        out.append((cut(-(s ** (k - 1)) * (Dq @ Xk)), np.asarray(a(xs), float)))
    return out


def velocity_scale(split, D: float, saddles) -> tuple:
    """``(s, n)``: the scale of the orthonormal Hermite functions and the number that
    resolves the separatrix layer (module docstring): ``delta = (D/omega_b)^(1/2)``
    (``omega_b`` the larger barrier frequency), ``V = 2 (2 (E_b - G(0)) + 2 D/mu)^(1/2)``
    (``E_b`` the higher saddle), ``s = (delta V/(2 pi))^(1/2)``, ``n = pi V/delta``."""
    gp, G = split.numpy_functions()[1:3]
    wb = max(math.sqrt(abs(float(gp(np.array(z))))) for z in saddles)
    Eb = max(float(G(np.array(z))) for z in saddles) - float(G(np.array(0.0)))
    delta = math.sqrt(D / wb)
    V = 2 * math.sqrt(2 * Eb + 2 * D / float(split.mu))
    return math.sqrt(delta * V / (2 * math.pi)), int(math.ceil(math.pi * V / delta))


def orthonormal_slowest(split, D: float, s: float, points, nh: int, nc: int, sink) -> float:
    """The smallest decay rate of the Kramers operator minus the sink ``sink(xs)`` (the
    rate of :mod:`.escape`) in ``nh`` orthonormal Hermite functions of ``v/s`` times the
    ``nc + 1`` points and differentiation matrix ``points(nc)``; every order vanishes at
    the ends ``x = +-L`` (the sink has emptied them).  Block LU in the Hermite index
    (:mod:`._blocks`), shift-invert Arnoldi from a fixed start (the same bytes each run)."""
    import scipy.sparse.linalg as spla

    xs, Dx = points(nc)
    m = xs.size
    terms = orthonormal_terms(split, D, s, xs, Dx, nh)
    keep = np.ones(nh * m)
    ends = np.concatenate([[k * m, k * m + m - 1] for k in range(nh)])
    keep[ends] = 0.0
    with one_blas_thread():
        lu = BlockTridiagonalLU(TermBlocks(terms, m, sink(xs), (0, m - 1), 0), m)
        op = spla.LinearOperator((nh * m, nh * m), matvec=lambda v: lu.solve(keep * v),
                                 dtype=float)
        theta = spla.eigs(op, k=3, which="LM", return_eigenvectors=False, tol=1e-12,
                          v0=np.ones(nh * m) * keep)
    lam = 1.0 / theta
    lam = lam[np.argsort(np.abs(lam))]
    return float(-lam[0].real)


def nonlinear_escape(split, D: float, saddles, half: float, sink, points, ladder, *,
                     n_hermite: int, n_cheb: int, tol: float, max_hermite: int,
                     max_cheb: int, max_cost: float, layer_intervals: float,
                     slowest=None) -> dict:
    """The Hermite and Chebyshev ladders of :func:`.escape.kramers_escape` for a nonlinear
    damping, in orthonormal Hermite functions (module docstring).

    ``sink(xs, sharp)`` is the sink at the points (``sharp = 2``: the sharper one of
    ``sink_error``), ``points(nc)`` the points and differentiation matrix on ``nc``
    intervals of ``[-half, half]``, ``ladder(start, stop)`` the Hermite truncations
    (:func:`._problem.hermite_ladder`).  The Hermite truncation grows by ``sqrt 2`` from ``n_hermite`` at the
    scale of :func:`velocity_scale` until two successive rates and the rate at the scale
    :data:`OTHER_SCALE` times larger (the last truncation) agree to ``tol``; the position
    intervals start at ``n_cheb`` or ``layer_intervals L/l`` (``l = delta/omega_b``, the layer's width
    in ``x``) and grow by 1.2 while the rate moves by more than ``tol`` on the finer grid.
    The block LU keeps ``3 n_hermite n_cheb^2`` numbers (``slowest.numbers(n, nc)`` where
    ``slowest`` has it) at most ``3 max_cost``.
    ``slowest``: the solve of one rung, called as :func:`orthonormal_slowest` (its default;
    for linear damping in an even potential :class:`._folded.FoldedRungs`, the same rate
    on half the points, one factorisation extended up the ladder).

    Returns
    -------
    dict
        The fields of :class:`.escape.KramersEscape` but ``saddles`` and ``wells``.
    """
    s, _ = velocity_scale(split, D, saddles)
    gp = split.numpy_functions()[1]
    wb = max(math.sqrt(abs(float(gp(np.array(z))))) for z in saddles)
    layer = math.sqrt(D / wb) / wb
    nc = max(int(n_cheb), 2 * math.ceil(layer_intervals / 2 * half / layer))
    memo: dict = {}
    slowest = orthonormal_slowest if slowest is None else slowest
    # the numbers the factorisation keeps (its blocks: lower, upper and LU of b m rows)
    numbers = getattr(slowest, "numbers", lambda n, nc: 3 * n * nc * nc)

    def cost(n, nc):  # in the budget's units: a third of the numbers kept
        return numbers(n, nc) / 3

    def fits(n, nc):
        return numbers(n, nc) <= 3 * max_cost

    def solve(n, nc, scale=1.0, sharp=1):
        if (n, nc, scale, sharp) not in memo:
            memo[n, nc, scale, sharp] = slowest(
                split, D, s * scale, points, n, nc, lambda xs: sink(xs, sharp))
        return memo[n, nc, scale, sharp]

    def other_scale(n, nc, rate):  # the basis's check: the rate at another scale
        return abs(solve(n, nc, OTHER_SCALE) - rate)

    out = hermite_chebyshev_ladder(solve, ladder, fits, start=int(n_hermite), n_cheb=nc,
                                   tol=tol, max_hermite=max_hermite, max_cheb=max_cheb,
                                   check=other_scale, cost=cost, budget=max_cost)
    scale_err = out.pop("check_error")
    return dict(out, truncation_error=max(out["truncation_error"], scale_err),
                scale_error=scale_err, velocity_scale=s)
