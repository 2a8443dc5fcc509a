"""The linear-damping escape rate in orthonormal Hermite functions folded by parity
(:mod:`numerics.fokker_planck._folded`, issue 36).

References, none produced by the folded solver:

* the same operator on the whole grid (:func:`numerics.fokker_planck._orthonormal.orthonormal_slowest`:
  the blocks assembled without the fold, eliminated from the top down by
  :class:`numerics.fokker_planck._blocks.BlockTridiagonalLU`) and a dense solve;
* the parity of the slowest mode, ``c_n(-x) = (-1)^n c_n(x)`` (``h_n(-xi) = (-1)^n h_n(xi)``
  and the Kramers operator with linear damping, an even potential and an even sink commute
  with ``(x, v) -> (-x, -v)``): the fold is the restriction of the whole operator;
* Risken's pair of Hermite functions at ``sigma = sqrt(kT)`` (matrix continued fraction,
  :mod:`numerics.fokker_planck._fraction`; ``kramers_escape(basis="pair")``), another basis
  and another elimination, and a solve at 1.5 times both sizes (the stated errors).

The CDC at rest, Delta = 3 (E_b/kT = 3.1 at kT = 0.35).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from kbm.model.conservative import split_conservative
from numerics.fokker_planck import kramers_escape
from numerics.fokker_planck._bases import cheb_centred
from numerics.fokker_planck._folded import FoldedLU, FoldedRungs, FoldedTermBlocks
from numerics.fokker_planck._folded_orders import FoldedOrderLU, dominant_ritz
from numerics.fokker_planck._orthonormal import (orthonormal_slowest, orthonormal_terms,
                                                 velocity_scale)
from numerics.fokker_planck.escape import ALPHA, SADDLES, WELLS
from numerics.fokker_planck._problem import escape_problem
from numerics.fokker_planck._sink_pairs import tanh_sink

KT = 0.35
SADDLE = 0.5281669331486846  # the CDC's at Delta = 3, lam = 1 (|g| < 1e-15 there)


def _problem(mu, crowd=SADDLES):
    split = split_conservative("cdc", {"mu": mu, "Delta": 3, "Omega": 1, "lam": 1})
    D = KT * mu
    sigma, wells, half, kappa0, width = escape_problem(split, D, (-SADDLE, SADDLE))

    def points(nc):
        return cheb_centred(nc, half, ALPHA, (-SADDLE, SADDLE) + tuple(wells),
                            (SADDLE / 2, SADDLE / 2, 2.5 * width, 2.5 * width),
                            (crowd, crowd, WELLS, WELLS))

    s = velocity_scale(split, D, (-SADDLE, SADDLE))[0]
    return split, D, s, points, lambda xs: tanh_sink(xs, wells, kappa0, width)


def test_cdc_saddle():
    g = split_conservative("cdc", {"mu": 1, "Delta": 3, "Omega": 1, "lam": 1}).numpy_functions()[0]
    assert abs(float(g(np.array(SADDLE)))) < 1e-13


@settings(max_examples=12, deadline=None)
@given(nh=st.integers(2, 9), nc=st.integers(8, 21), seed=st.integers(0, 2**16))
def test_fold_is_the_restriction(nh, nc, seed):
    """For every vector with the slowest mode's parity, ``c_n(-x) = (-1)^n c_n(x)``, the
    folded operator applied to its kept points equals the whole operator's result on
    those points (even and odd numbers of intervals, every truncation)."""
    split, D, s, points, sink = _problem(0.2)
    xs, Dx = points(nc)
    m = xs.size
    terms = orthonormal_terms(split, D, s, xs, Dx, nh)
    A = FoldedTermBlocks(terms, m, sink(xs))
    rng = np.random.default_rng(seed)
    full = np.zeros((nh, m))
    for n in range(nh):
        half = rng.standard_normal(m)
        full[n] = half + (-1) ** n * half[::-1]
    Afull = sum(np.kron(H.toarray(), X if X.ndim == 2 else np.diag(X)) for H, X in terms)
    Afull -= np.kron(np.eye(nh), np.diag(sink(xs)))
    ref = (Afull @ full.reshape(-1)).reshape(nh, m)
    folded = np.zeros((nh, A.mm))
    for n in range(nh):
        idx = A.maps[n % 2][0]
        folded[n, :idx.size] = full[n, idx]
    got = (A.block(0, nh, 0, nh) @ folded.reshape(-1)).reshape(nh, A.mm)
    scale = np.max(np.abs(ref))
    for n in range(nh):
        idx = A.maps[n % 2][0]
        # row 0 (x = L) is pinned: c_n(L) itself
        assert got[n, 0] == folded[n, 0]
        assert np.max(np.abs(got[n, 1:idx.size] - ref[n, idx[1:]])) <= 1e-12 * scale
        if idx.size < A.mm:  # the padding: decoupled
            assert got[n, A.mm - 1] == folded[n, A.mm - 1]


def test_upward_lu_extends_and_solves():
    """The upward block LU factorised to 8 orders and extended to 16 solves the folded
    matrix as a dense solve does (1e-12), ``apply`` is the product with the block, and a
    truncation at 8 orders uses the leading factors (the Galerkin blocks of the first
    orders do not depend on the truncation)."""
    split, D, s, points, sink = _problem(0.2)
    xs, Dx = points(24)
    A = FoldedTermBlocks(orthonormal_terms(split, D, s, xs, Dx, 16), xs.size, sink(xs))
    lu = FoldedLU(A, 8, 2)
    lu.extend(16)
    rng = np.random.default_rng(4)
    for n in (8, 16):
        rhs = rng.standard_normal(n * A.mm)
        dense = np.linalg.solve(A.block(0, n, 0, n), rhs)
        got = lu.solve(rhs, n)
        assert np.max(np.abs(got - dense)) <= 1e-12 * np.max(np.abs(dense))
    y = rng.standard_normal(2 * A.mm)
    for n0, k0 in ((4, 2), (4, 6)):
        assert np.allclose(A.apply(n0, n0 + 2, k0, k0 + 2, y), A.block(n0, n0 + 2, k0, k0 + 2) @ y,
                           rtol=0, atol=1e-12 * np.max(np.abs(A.block(n0, n0 + 2, k0, k0 + 2))))


@pytest.mark.parametrize("sharp", [1, 8])
def test_order_by_order_lu_extends_and_solves(sharp):
    """The order-by-order LU (:mod:`numerics.fokker_planck._folded_orders`) factorised to 7
    orders and extended to 16 solves the folded matrix as a dense solve does (1e-12) at
    every truncation, with the first sink and a sink ``sharp`` times narrower and
    ``sharp^2`` times stronger (a sink rung's); the Hermite bandwidth at this scale is 2
    (linear damping at ``s != sqrt(kT)``: the couplings two orders apart are diagonal)."""
    split, D, s, points, _ = _problem(0.2)
    sigma, wells, half, kappa0, width = escape_problem(split, D, (-SADDLE, SADDLE))
    xs, Dx = points(24)
    kappa = tanh_sink(xs, wells, kappa0 * sharp ** 2, width / sharp)
    A = FoldedTermBlocks(orthonormal_terms(split, D, s, xs, Dx, 16), xs.size, kappa)
    assert A.bandwidth() == 2
    lu = FoldedOrderLU(A, 7)
    lu.extend(16)
    rng = np.random.default_rng(5)
    for n in (3, 8, 15, 16):
        rhs = rng.standard_normal(n * A.mm)
        dense = np.linalg.solve(A.block(0, n, 0, n), rhs)
        got = lu.solve(rhs, n)
        assert np.max(np.abs(got - dense)) <= 1e-12 * np.max(np.abs(dense))


def test_dominant_ritz_is_arpacks_and_starts_warm():
    """The Arnoldi of ``dominant_ritz`` gives ARPACK's slowest rate
    (``scipy.sparse.linalg.eigs``, k = 1) to 1e-12 from the same cold start; started
    from the slowest mode of the truncation at 48 orders it gives the rate at 12 orders
    (the same factors) as a cold start does, in at most four products."""
    import scipy.sparse.linalg as spla

    split, D, s, points, sink = _problem(5.0)
    xs, Dx = points(48)
    A = FoldedTermBlocks(orthonormal_terms(split, D, s, xs, Dx, 48), xs.size, sink(xs))
    lu = FoldedOrderLU(A, 48)
    calls = []

    def op(n):
        keep = A.keep()[:n * A.mm]

        def apply(v):
            calls.append(n)
            return lu.solve(keep * v, n)
        return keep, apply

    keep, apply48 = op(48)
    arpack = spla.eigs(spla.LinearOperator((keep.size,) * 2, matvec=apply48), k=1, ncv=6,
                       which="LM", return_eigenvectors=False, tol=1e-12, v0=keep.copy())[0]
    theta, vec = dominant_ritz(apply48, keep.copy())
    assert theta.real == pytest.approx(arpack.real, rel=1e-12)
    keep12, apply12 = op(12)
    cold = dominant_ritz(apply12, keep12.copy())[0]
    calls.clear()
    warm = dominant_ritz(apply12, vec[:keep12.size].copy())[0]
    assert len(calls) <= 4
    assert warm.real == pytest.approx(cold.real, rel=1e-12)
    assert abs(warm.real - theta.real) > 1e-9 * abs(theta.real)  # another truncation


def test_a_carried_start_gives_the_cold_rate_in_fewer_products(monkeypatch):
    """A rung started from another grid's slowest mode (``FoldedRungs(start=mode)``,
    :func:`numerics.fokker_planck._folded.carried_mode`: interpolated to its points, as the
    sink ladders start each new rung) gives the rate of a cold start on the same factors
    to 1e-12 (the same stopping test) in fewer products."""
    split, D, s, points, sink = _problem(5.0)
    calls = []
    solve = FoldedOrderLU.solve
    monkeypatch.setattr(FoldedOrderLU, "solve",
                        lambda self, rhs, n: calls.append(n) or solve(self, rhs, n))
    coarse = FoldedRungs(48, by_order=True)
    coarse(split, D, s, points, 48, 64, sink)
    calls.clear()
    cold = FoldedRungs(48, by_order=True)(split, D, s, points, 48, 80, sink)
    n_cold = len(calls)
    calls.clear()
    carried = FoldedRungs(48, by_order=True, start=coarse.mode)
    warm = carried(split, D, s, points, 48, 80, sink)
    assert len(calls) < n_cold
    assert warm == pytest.approx(cold, rel=1e-12)


@pytest.mark.parametrize("mu,nh,nc", [(0.2, 32, 64), (5.0, 48, 80)])
def test_order_by_order_rate_is_the_pairs(mu, nh, nc):
    """The rate of :class:`FoldedRungs` factorised order by order (``by_order``) equals
    the same discretisation's rate eliminated in pairs of orders (:class:`FoldedLU`, the
    other elimination) to 1e-12, for a truncation factorised fresh and one extended up
    the ladder."""
    split, D, s, points, sink = _problem(mu)
    pairs = FoldedRungs(nh)(split, D, s, points, nh, nc, sink)
    rungs = FoldedRungs(nh, by_order=True)
    small = rungs(split, D, s, points, nh // 2, nc, sink)
    assert rungs(split, D, s, points, nh, nc, sink) == pytest.approx(pairs, rel=1e-12)
    assert small == pytest.approx(FoldedRungs(nh)(split, D, s, points, nh // 2, nc, sink),
                                  rel=1e-12)


@pytest.mark.parametrize("mu,nh,nc", [(0.2, 32, 64), (0.02, 64, 96)])
def test_folded_rate_is_the_whole_grids(mu, nh, nc):
    """The folded rate equals the rate of the same discretisation on the whole grid
    (unfolded, eliminated from the top down) to 1e-11, at the turnover and at low
    friction; one factorisation extended up the ladder gives a smaller rung's rate as a
    fresh one does."""
    split, D, s, points, sink = _problem(mu)
    whole = orthonormal_slowest(split, D, s, points, nh, nc, sink)
    rungs = FoldedRungs(nh)
    small = rungs(split, D, s, points, nh // 2, nc, sink)
    folded = rungs(split, D, s, points, nh, nc, sink)
    assert folded == pytest.approx(whole, rel=1e-11)
    assert small == pytest.approx(FoldedRungs(nh // 2)(split, D, s, points, nh // 2, nc, sink),
                                  rel=1e-12)


def test_turnover_agrees_with_the_pair_basis():
    """mu = 0.2: the orthonormal basis's rate equals Risken's pair basis (another basis,
    scale and elimination) within the two solves' stated errors and to 1e-8; the stated
    truncation, Chebyshev and sink errors are below 1e-6 of the rate."""
    fp = kramers_escape("cdc", {"mu": 0.2, "Delta": 3, "Omega": 1, "lam": 1}, KT * 0.2,
                        (-SADDLE, SADDLE), basis="orthonormal")
    pair = kramers_escape("cdc", {"mu": 0.2, "Delta": 3, "Omega": 1, "lam": 1}, KT * 0.2,
                          (-SADDLE, SADDLE), basis="pair")
    stated = (fp.truncation_error + fp.chebyshev_error + pair.truncation_error
              + pair.chebyshev_error)
    assert abs(fp.rate - pair.rate) <= stated
    assert fp.rate == pytest.approx(pair.rate, rel=1e-8)
    assert max(fp.truncation_error, fp.chebyshev_error, fp.sink_error) < 1e-6 * fp.rate
    assert fp.hermite < pair.hermite and math.isfinite(fp.scale_error)


def test_basis_is_checked():
    """An unknown basis, and the pair basis for a nonlinear damping, are refused; ``auto``
    takes the pair at mu = 1 (``8 omega_b/gamma = 34``: the same rate as ``pair``) and the
    folded orthonormal functions at mu = 0.02 (the slow test below); the first sink's
    rates (``sink_tol=inf``: the sink ladder's tests are in test_fokker_planck_sink.py)."""
    p = {"mu": 1, "Delta": 3, "Omega": 1, "lam": 1}
    auto = kramers_escape("cdc", p, KT, (-SADDLE, SADDLE), sink_tol=math.inf)
    pair = kramers_escape("cdc", p, KT, (-SADDLE, SADDLE), basis="pair", sink_tol=math.inf)
    assert (auto.rate, auto.ladder, auto.sink_error) == (pair.rate, pair.ladder, pair.sink_error)
    assert math.isnan(auto.scale_error)
    from kbm.errors import ParameterError

    with pytest.raises(ParameterError, match="basis"):
        kramers_escape("cdc", {"mu": 1, "Delta": 3, "Omega": 1, "lam": 1}, KT, (-SADDLE, SADDLE),
                       basis="chebyshev")
    with pytest.raises(ParameterError, match="linear damping"):
        kramers_escape("sedf", {"mu": 0.1, "Delta": 3, "beta": 1, "lam": 1}, 0.05,
                       (-0.5, 0.5), basis="pair")


@pytest.mark.slow
def test_low_friction_stated_errors_are_honest():
    """mu = 0.02 (omega_b/gamma = 209): the default rate against an independent solve at
    1.5 times both sizes (192 functions on 394 intervals) lies within the stated
    truncation + Chebyshev error, and agrees with Risken's pair basis at 3444 functions
    on the default grid (the last change there 9e-13) to 1e-9."""
    p = {"mu": 0.02, "Delta": 3, "Omega": 1, "lam": 1}
    fp = kramers_escape("cdc", p, KT * 0.02, (-SADDLE, SADDLE))
    assert math.isfinite(fp.scale_error) and fp.scale_error <= fp.truncation_error
    assert fp.hermite <= 181 and fp.chebyshev <= 315
    stated = fp.truncation_error + fp.chebyshev_error
    assert stated < 1e-6 * fp.rate and fp.sink_error < 1e-6 * fp.rate
    split, D, s, points, sink = _problem(0.02)
    nh, nc = 3 * fp.hermite // 2, 3 * (fp.chebyshev - 1) // 2
    fine = FoldedRungs(nh)(split, D, s, points, nh, nc, sink)
    assert abs(fp.rate - fine) <= stated
    from numerics.fokker_planck._rungs import FractionRungs

    sigma, wells, half, kappa0, width = escape_problem(split, D, (-SADDLE, SADDLE))
    pair = FractionRungs(split, sigma, D / KT, wells, lambda xs, sharp: sink(xs), points)
    assert pair.rate(3444, fp.chebyshev - 1) == pytest.approx(fp.rate, rel=1e-9)
