"""The block-tridiagonal LU of the Kramers matrix (numerics.fokker_planck._blocks), checked
against a second method: dense LU (numpy.linalg.solve) on random block-banded matrices, and
SuperLU (scipy.sparse.linalg.splu) on the escape problem's matrix, whose slowest decay
rate must not depend on the factorisation."""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.sparse as sps
from hypothesis import given, settings, strategies as st

from kbm.model.conservative import split_conservative
from numerics.fokker_planck import kramers_operator
from numerics.fokker_planck._blocks import (BlockTridiagonalLU, TermBlocks,
                                            hermite_bandwidth, one_blas_thread)
from numerics.fokker_planck.kramers import kramers_terms
from numerics.fokker_planck._model import next_wells
from numerics.fokker_planck._problem import kT_gamma
from numerics.fokker_planck._sink_pairs import tanh_sink

PARAMS = {"Delta": 2, "lam": 1.3, "Omega": 1}


def escape_matrix_rate(split, D, sigma, wells, half, nh, nc, kappa0, width, solver="block",
                       alpha: float = 0.0):
    """The smallest decay rate of the Kramers operator with the sink ``tanh_sink`` centred on
    the next wells' bottoms ``wells`` (Hanggi, Talkner and Borkovec 1990, sec. II.C: the
    rate as the lowest nonvanishing eigenvalue): the second method of these tests (the
    code's ladders use ``numerics.fokker_planck._orthonormal``, ``._folded`` and
    ``._rungs``).

    ``solver``: ``"fraction"`` (linear damping only: the closed-form blocks of
    ``._fraction``, folded by parity when the potential and the wells are symmetric, on
    the points of ``._bases.cheb_mapped`` with ``alpha``), ``"block"`` (the blocks
    assembled from ``kramers_terms``, ``._blocks``) or ``"splu"`` (SuperLU of the global
    sparse matrix); the last two on Chebyshev points."""
    import scipy.sparse.linalg as spla

    from numerics.fokker_planck._bases import cheb_mapped
    from numerics.fokker_planck._fraction import EscapeFraction
    from numerics.fokker_planck._parity import symmetric

    if solver == "fraction":
        gamma = kT_gamma(split, D)[1]
        xs, Dx = cheb_mapped(nc, half, alpha)
        g = np.asarray(split.numpy_functions()[0](xs), float)
        with one_blas_thread():
            return EscapeFraction(Dx, g, tanh_sink(xs, wells, kappa0, width), sigma, gamma, nh,
                                  symmetric(g, wells)).slowest()
    terms, xs, _ = kramers_terms(split, D, sigma, half, nh, nc)
    m = xs.size
    kappa = tanh_sink(xs, wells, kappa0, width)
    keep = np.ones(nh * m)
    ends = np.concatenate([[k * m, k * m + m - 1] for k in range(2, nh)])
    keep[ends] = 0.0
    with one_blas_thread():
        if solver == "block":  # block tridiagonal in the Hermite index (._blocks)
            lu = BlockTridiagonalLU(TermBlocks(terms, m, kappa, (0, m - 1)), m)
        else:
            A = kramers_operator(split, D, sigma, half, nh, nc)[0]
            A = A - sps.kron(sps.identity(nh), sps.diags(kappa))
            C = sps.csr_matrix((np.ones(ends.size), (ends, ends)), shape=A.shape)
            lu = spla.splu((sps.diags(keep) @ A + C).tocsc())
        op = spla.LinearOperator((nh * m, nh * m), matvec=lambda v: lu.solve(keep * v),
                                 dtype=float)
        theta = spla.eigs(op, k=3, which="LM", return_eigenvectors=False, tol=1e-12,
                          v0=keep.copy())
    lam = 1.0 / theta
    lam = lam[np.argsort(np.abs(lam))]
    return float(-lam[0].real)


def _cdc_wells(mu):
    """``(split, g, xs, wells)`` of the CDC at ``PARAMS``: the saddle ``xs`` by Brent on
    ``g`` (independent of the code under test) and the next wells' bottoms."""
    from scipy.optimize import brentq

    split = split_conservative("cdc", dict(PARAMS, mu=mu))
    g = split.numpy_functions()[0]
    xs = brentq(lambda z: float(g(np.array(z))), 0.3, 1.0, xtol=1e-15)
    return split, g, xs, next_wells(g, (-xs, xs))


def _banded(rng, n_orders, m, b):
    """A random matrix coupling Hermite orders ``n`` to ``n +- b`` only; the diagonal
    blocks grow with ``n`` like the damping ``-n gamma`` and the ``n = 0`` block is
    singular on its own (as the Kramers matrix's is without a sink)."""
    size = n_orders * m
    A = np.zeros((size, size))
    for n in range(n_orders):
        for k in range(max(0, n - b), min(n_orders, n + b + 1)):
            A[n * m:(n + 1) * m, k * m:(k + 1) * m] = rng.standard_normal((m, m))
        A[n * m:(n + 1) * m, n * m:(n + 1) * m] += (3.0 * n * m) * np.eye(m)
    A[:m, :m] = 0.0
    A[:m, :m][0, 0] = 1.0  # rank one: the block is singular for m > 1
    return A


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), n_orders=st.integers(2, 9), m=st.integers(2, 7),
       b=st.integers(1, 3))
def test_block_lu_solves_like_dense_lu(seed, n_orders, m, b):
    """For any matrix of Hermite bandwidth ``b`` the block sweeps give ``A^{-1} r`` of
    dense LU (relative difference below 1e-9 times the condition number's size), though
    the ``n = 0`` block alone is singular: the elimination runs from the top orders."""
    rng = np.random.default_rng(seed)
    A = _banded(rng, n_orders, m, b)
    cond = np.linalg.cond(A)
    if not np.isfinite(cond) or cond > 1e8:
        return
    r = rng.standard_normal(A.shape[0])
    lu = BlockTridiagonalLU(sps.csr_matrix(A), m)
    assert hermite_bandwidth(sps.csr_matrix(A), m) <= b
    x = lu.solve(r)
    ref = np.linalg.solve(A, r)
    assert np.linalg.norm(x - ref) <= 1e-12 * cond * np.linalg.norm(ref)


def test_hermite_bandwidth_of_the_kramers_operator():
    """Linear damping with ``sigma^2 = kT``: friction and diffusion are diagonal in the
    Hermite functions (Risken eq. 10.51), so the operator couples ``n`` to ``n +- 1`` only
    (their ``n + 2`` parts cancel to round-off); at another ``sigma`` they couple ``n + 2``."""
    mu, D = 1.0, 0.15
    split = split_conservative("cdc", dict(PARAMS, mu=mu))
    A, xs, _ = kramers_operator(split, D, math.sqrt(D / mu), 3.0, 12, 24)
    assert hermite_bandwidth(A, xs.size) == 1
    A2, _, _ = kramers_operator(split, D, 1.3 * math.sqrt(D / mu), 3.0, 12, 24)
    assert hermite_bandwidth(A2, xs.size) == 2
    for s, b in ((math.sqrt(D / mu), 1), (1.3 * math.sqrt(D / mu), 2)):
        terms, _, _ = kramers_terms(split, D, s, 3.0, 12, 24)
        assert TermBlocks(terms, xs.size).bandwidth() == b


def test_term_blocks_assemble_the_sparse_matrix():
    """The blocks assembled from the terms are the sparse operator's, with the sink on the
    diagonal and the pinned rows identity rows (the escape matrix of :func:`escape_matrix_rate`)."""
    split = split_conservative("cdc", dict(PARAMS, mu=0.3))
    A, xs, _ = kramers_operator(split, 0.045, 0.4, 3.0, 7, 10)
    m, n = xs.size, 7
    kappa = np.linspace(0.0, 2.0, m)
    ends = np.concatenate([[k * m, k * m + m - 1] for k in range(2, n)])
    keep = np.ones(n * m)
    keep[ends] = 0.0
    ref = (sps.diags(keep) @ (A - sps.kron(sps.identity(n), sps.diags(kappa)))
           + sps.csr_matrix((np.ones(ends.size), (ends, ends)), shape=A.shape)).toarray()
    terms, _, _ = kramers_terms(split, 0.045, 0.4, 3.0, 7, 10)
    blocks = TermBlocks(terms, m, kappa, (0, m - 1))
    for n0, n1, k0, k1 in ((0, 7, 0, 7), (2, 4, 0, 3), (5, 7, 1, 6)):
        got = blocks.block(n0, n1, k0, k1)
        np.testing.assert_allclose(got, ref[n0 * m:n1 * m, k0 * m:k1 * m], rtol=0,
                                   atol=1e-13 * np.max(np.abs(ref)))


def test_escape_rate_independent_of_the_factorisation():
    """The slowest decay rate with the sink (mu = 1, 32 Hermite x 96 Chebyshev) is the same
    from the block LU and from SuperLU to 1e-10."""
    mu, kT = 1.0, 0.15
    split, g, xs, wells = _cdc_wells(mu)
    args = (split, kT * mu, math.sqrt(kT), wells, 1.2 * wells[1], 32, 96, 5.0,
            0.1 * (wells[1] - xs))
    block = escape_matrix_rate(*args, solver="block")
    sparse = escape_matrix_rate(*args, solver="splu")
    assert block > 0
    assert block == pytest.approx(sparse, rel=1e-10)


def test_one_blas_thread_restores_the_count():
    """Inside, every BLAS found runs one thread; after, the counts are as before."""
    from threadpoolctl import threadpool_info

    def counts():
        return [i["num_threads"] for i in threadpool_info() if i["user_api"] == "blas"]

    before = counts()
    assert before, "numpy's BLAS is loaded"
    with one_blas_thread():
        assert all(n == 1 for n in counts())
    assert counts() == before


def test_closed_form_blocks_equal_the_assembled_escape_matrix():
    """The escape matrix of linear damping from its closed-form blocks (Risken eqs.
    10.51-10.53; numerics.fokker_planck._fraction), whole and folded by parity, has the
    slowest decay rate of the block LU of the matrix assembled from kramers_terms
    (mu = 0.3, 40 Hermite x 48 Chebyshev, plain Chebyshev points): 1e-9."""
    from numerics.fokker_planck._bases import cheb
    from numerics.fokker_planck._fraction import EscapeFraction

    mu, kT = 0.3, 0.15
    split, g, xs, wells = _cdc_wells(mu)
    half, width = 1.25 * wells[1], 0.1 * (wells[1] - xs)
    ref = escape_matrix_rate(split, kT * mu, math.sqrt(kT), wells, half, 40, 48, 5.0, width,
                             solver="block")
    x, Dx = cheb(48, half)
    kappa = tanh_sink(x, wells, 5.0, width)
    with one_blas_thread():
        for fold in (False, True):
            rate = EscapeFraction(Dx, np.asarray(g(x), float), kappa, math.sqrt(kT), mu, 40,
                                  fold).slowest()
            assert rate == pytest.approx(ref, rel=1e-9)


def test_upward_elimination_solves_and_extends():
    """The escape matrix eliminated from the lowest Hermite orders up
    (numerics.fokker_planck._fraction, the compiled sweeps of ._sweeps) solves like dense LU
    (numpy.linalg.solve) of the matrix assembled independently from kramers_terms with the
    sink and the pinned rows (TermBlocks), to 1e-10; and the rate of a truncation from
    factors extended to twice as many orders equals that of a fresh factorisation to 1e-12
    (the first N factors of the upward elimination are those of every larger truncation)."""
    from numerics.fokker_planck._bases import cheb
    from numerics.fokker_planck._fraction import EscapeFraction

    mu, kT, nh, nc = 0.3, 0.15, 12, 24
    split, g, xs, wells = _cdc_wells(mu)
    half, width = 1.25 * wells[1], 0.1 * (wells[1] - xs)
    terms, x, _ = kramers_terms(split, kT * mu, math.sqrt(kT), half, nh, nc)
    kappa = tanh_sink(x, wells, 5.0, width)
    m = x.size
    A = TermBlocks(terms, m, kappa, (0, m - 1)).block(0, nh, 0, nh)
    rhs = np.random.default_rng(7).standard_normal(nh * m)
    x2, Dx = cheb(nc, half)
    assert np.allclose(x2, x, rtol=0, atol=1e-14)
    with one_blas_thread():
        frac = EscapeFraction(Dx, np.asarray(g(x), float), kappa, math.sqrt(kT), mu, nh,
                              False)
        out = np.concatenate(frac.solve([rhs[k * m:(k + 1) * m] for k in range(nh)]))
        ref = np.linalg.solve(A, rhs)
        assert np.max(np.abs(out - ref)) <= 1e-10 * np.max(np.abs(ref))
        for fold in (False, True):
            args = (Dx, np.asarray(g(x), float), kappa, math.sqrt(kT), mu)
            fresh = EscapeFraction(*args, nh, fold).slowest()
            longer = EscapeFraction(*args, nh, fold, capacity=nh + 1)
            longer.extend(2 * nh)  # beyond the capacity: the factors are copied once
            assert longer.slowest(n=nh) == pytest.approx(fresh, rel=1e-12)


@settings(max_examples=20, deadline=None)
@given(n_from=st.integers(2, 40), n_to=st.integers(2, 60), seed=st.integers(0, 2**31 - 1))
def test_chebyshev_interpolation_is_exact_for_polynomials(n_from, n_to, seed):
    """The barycentric interpolation between Chebyshev-Lobatto grids (Berrut and Trefethen
    2004) reproduces every polynomial of degree <= n_from (the mode's move between the
    escape ladder's grids, numerics.fokker_planck._rungs)."""
    from numpy.polynomial import chebyshev as C

    from numerics.fokker_planck._rungs import chebyshev_interpolation

    coef = np.random.default_rng(seed).standard_normal(n_from + 1)
    t0 = np.cos(np.pi * np.arange(n_from + 1) / n_from)
    t1 = np.cos(np.pi * np.arange(n_to + 1) / n_to)
    P = chebyshev_interpolation(n_from, n_to)
    assert np.allclose(P @ C.chebval(t0, coef), C.chebval(t1, coef), rtol=0,
                       atol=1e-11 * np.sum(np.abs(coef)))


def test_centred_points_differentiate_spectrally():
    """The points crowded at given centres (numerics.fokker_planck._bases.cheb_centred, an
    arctangent map after Kosloff-Tal-Ezer's) are the Kosloff-Tal-Ezer points at weight 0,
    symmetric for symmetric centres, and their differentiation matrix converges
    spectrally: sin(3x) exp(-x^2) differentiated to 2e-3, 1e-7 with 48, 128 intervals
    (8.3e-4, 2.0e-8 measured: most points sit near the centres, few elsewhere)."""
    from numerics.fokker_planck._bases import cheb_centred, cheb_mapped

    L, centres, widths = 1.2, (-0.5, 0.5, -1.0, 1.0), (0.25, 0.25, 0.1, 0.1)
    x0, D0 = cheb_centred(40, L, 0.9, centres, widths, 0.0)
    x1, D1 = cheb_mapped(40, L, 0.9)
    assert np.allclose(x0, x1, rtol=0, atol=1e-15) and np.allclose(D0, D1, rtol=0, atol=1e-12)
    for n, tol in ((48, 2e-3), (128, 1e-7)):
        x, D = cheb_centred(n, L, 0.9, centres, widths, (1.0, 1.0, 0.05, 0.05))
        assert np.all(np.diff(x) < 0) and x[0] == L and x[-1] == -L
        assert np.allclose(x, -x[::-1], rtol=0, atol=1e-15)
        f = np.sin(3 * x) * np.exp(-x * x)
        df = (3 * np.cos(3 * x) - 2 * x * np.sin(3 * x)) * np.exp(-x * x)
        assert np.max(np.abs(D @ f - df)) < tol


def _substitution(lu, piv, b):
    """The textbook LU solve (Golub and Van Loan, Matrix Computations, 4th ed., algs.
    3.1.3-3.1.4, column-oriented): interchanges, unit lower then upper substitution, one
    column at a time (plain Python floats)."""
    b = [float(v) for v in b]
    s = len(b)
    for i in range(s):
        b[i], b[piv[i]] = b[piv[i]], b[i]
    for j in range(s):
        for i in range(j + 1, s):
            b[i] -= float(lu[i, j]) * b[j]
    for j in range(s - 1, -1, -1):
        b[j] /= float(lu[j, j])
        for i in range(j):
            b[i] -= float(lu[i, j]) * b[j]
    return np.array(b)


@settings(max_examples=40, deadline=None)
@given(m=st.integers(1, 23), cut=st.integers(0, 22), seed=st.integers(0, 2**31 - 1))
def test_compiled_sweep_kernels_are_the_textbook_substitution(m, cut, seed):
    """The compiled LU solve and product of the sweeps (numerics.fokker_planck._sweeps, four
    columns per pass) give the column-oriented substitution and product bit for bit (each
    entry loses the columns' terms in the same order), and LAPACK's getrs to 1e-12, for
    any size, leading block and row interchanges."""
    from scipy.linalg import lapack

    from numerics.fokker_planck._sweeps import _lu_solve, _matvec

    rng = np.random.default_rng(seed)
    s = max(1, m - cut % m)
    A = rng.standard_normal((s, s)) + 4 * np.eye(s)
    lu, piv, info = lapack.dgetrf(A)
    assert info == 0
    lut = np.zeros((m, m))
    lut[:s, :s] = lu.T  # the sweeps' layout: transposed, leading block
    pv = np.concatenate([piv, np.arange(s, m)]).astype(np.int64)
    b = rng.standard_normal(m)
    out = b.copy()
    _lu_solve(lut, pv, s, out)
    assert np.array_equal(out[:s], _substitution(lu, piv, b[:s]))
    assert np.array_equal(out[s:], b[s:])
    assert np.allclose(out[:s], lapack.dgetrs(lu, piv, b[:s])[0], rtol=0,
                       atol=1e-12 * np.max(np.abs(out[:s])))
    rows, cols = s, m
    prod = np.full(m, np.nan)
    _matvec(lut, rows, cols, b, prod)
    ref = [0.0] * rows
    for j in range(cols):
        for i in range(rows):
            ref[i] += float(lut[j, i]) * float(b[j])
    assert np.array_equal(prod[:rows], np.array(ref))


def test_factors_in_a_used_buffer_are_those_of_a_fresh_one():
    """The escape ladder's factorisations share one storage (numerics.fokker_planck._rungs:
    the last factors' pages): factors written over a buffer full of NaN (any stale value
    read would spread) give the fresh factorisation's rate and solves bit for bit, folded
    and not, and the ladder's rates (two truncations, a finer grid, the sharper sink) equal
    those of fresh factorisations of each."""
    from numerics.fokker_planck._bases import cheb
    from numerics.fokker_planck._fraction import EscapeFraction
    from numerics.fokker_planck._rungs import FractionRungs

    mu, kT, nh, nc = 0.3, 0.15, 12, 24
    split, g, xs, wells = _cdc_wells(mu)
    half, width = 1.25 * wells[1], 0.1 * (wells[1] - xs)
    x, Dx = cheb(nc, half)
    args = (Dx, np.asarray(g(x), float), tanh_sink(x, wells, 5.0, width), math.sqrt(kT), mu)
    rhs = [np.random.default_rng(3).standard_normal(s) for s in
           EscapeFraction(*args, nh, False).sizes]
    with one_blas_thread():
        for fold in (False, True):
            fresh = EscapeFraction(*args, nh, fold)
            used = EscapeFraction(*args, nh, fold, buffer=np.full(2 * nh * (nc + 1) ** 2,
                                                                   np.nan))
            assert used.slowest() == fresh.slowest()
            sizes = fresh.sizes
            assert all(np.array_equal(a, b) for a, b in
                       zip(used.solve([r[:s] for r, s in zip(rhs, sizes)]),
                           fresh.solve([r[:s] for r, s in zip(rhs, sizes)])))

        def sink(pts, sharp):
            return tanh_sink(pts, wells, 5.0 * (3 if sharp > 1 else 1), width / sharp)

        rungs = FractionRungs(split, math.sqrt(kT), mu, wells, sink, lambda n: cheb(n, half))
        for n, m, sharp in ((nh, nc, 1), (2 * nh, nc, 1), (nh, 30, 1), (nh, nc, 2)):
            pts, Dm = cheb(m, half)
            ref = EscapeFraction(Dm, np.asarray(g(pts), float), sink(pts, sharp),
                                 math.sqrt(kT), mu, n, True).slowest()
            assert rungs.rate(n, m, sharp, capacity=2 * nh) == pytest.approx(ref, rel=1e-11)
