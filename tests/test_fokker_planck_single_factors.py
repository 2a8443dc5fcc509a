"""The single-precision factors of the order-by-order LU, in memory and on disk
(numerics/fokker_planck/_pentadiagonal.py and _pentadiagonal_disk.py, ``single``), their
double-precision product (numerics/fokker_planck/_single_products.py), and the stationary
solve by GMRES on them (numerics/fokker_planck/_bordered.py).

References: the row sums of the product by :func:`math.fsum` (exactly rounded); a dense
LU (:func:`scipy.linalg.lu_factor`) of the assembled collocation matrix; for linear damping the
Boltzmann density ``exp(-H/kT)`` (Gibbs; Risken, *The Fokker-Planck Equation*, sec. 10.1):
``<x^2>`` the quadrature of ``x^2 exp(-G/kT)`` (:func:`numerics.escape.boltzmann_moment`)
and ``<x'^2> = kT``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.linalg import lu_factor, lu_solve

import numerics.fokker_planck._pentadiagonal_disk as disk
from kbm.model.conservative import split_conservative
from numerics.escape import boltzmann_moment
from numerics.fokker_planck._bases import cheb_mapped
from numerics.fokker_planck._blocks import TermBlocks
from numerics.fokker_planck._bordered import bordered_inverse_iteration
from numerics.fokker_planck._orthonormal import orthonormal_terms
from numerics.fokker_planck._pentadiagonal import HermitePentadiagonalLU
from numerics.fokker_planck._single_products import single_matvec
from numerics.fokker_planck._stationary_solve import orthonormal_stationary

SEDF = {"mu": 0.1, "Delta": 3, "beta": 1, "lam": 1}
CDC = {"mu": 0.15, "Delta": 2, "lam": 1.3, "Omega": 1}


def _terms(nh: int, nc: int):
    split = split_conservative("sedf", SEDF)
    xs, Dx = cheb_mapped(nc, 6.0, 0.95)  # lambda_0 1.3e-3, the next 6.5e-2 (24 x 61)
    return orthonormal_terms(split, 0.05, 0.5, xs, Dx, nh), xs.size


@pytest.mark.parametrize("rows, cols", [(1, 1), (7, 5), (67, 129)])
def test_single_matvec_sums_in_double(rows, cols):
    """Each entry of the product of a single-precision matrix and a double vector is the
    exactly rounded sum (:func:`math.fsum` of the products, each exact in double) to the
    rounding bound of a double sum, ``cols eps sum |a_ij x_j|``, far below single
    precision's; a double matrix gives numpy's product."""
    rng = np.random.default_rng(rows)
    a = rng.standard_normal((rows, cols)).astype(np.float32)
    x = rng.standard_normal(cols)
    got = single_matvec(a, x)
    assert got.dtype == np.float64
    for i in range(rows):
        terms = [float(a[i, j]) * float(x[j]) for j in range(cols)]
        bound = cols * np.finfo(float).eps * math.fsum(abs(t) for t in terms)
        assert abs(got[i] - math.fsum(terms)) <= bound
    ad = a.astype(float)
    assert np.array_equal(single_matvec(ad, x), ad @ x)


@pytest.mark.parametrize("on_disk", [False, True])
def test_single_factors_precondition_gmres_to_the_dense_solve(on_disk, tmp_path):
    """SEDF, 24 functions x 61 points, the end rows pinned: the factors are kept in single
    precision (in memory, or on disk in records of ``2 m^2`` single-precision numbers per
    order), and the inverse iteration by flexible GMRES preconditioned by them (the
    bordered steps of :func:`bordered_inverse_iteration`) gives the eigenvector of the
    inverse iteration with a dense LU (:func:`scipy.linalg.lu_factor` of the assembled
    matrix) within 1e-10."""
    terms, m = _terms(24, 60)
    pins = (0, m - 1)
    if on_disk:
        lu = disk.DiskPentadiagonalLU(terms, m, pins, directory=str(tmp_path), single=True)
        lu._file.seek(0, 2)
        assert lu._file.tell() == 23 * 2 * m * m * 4
    else:
        lu = HermitePentadiagonalLU(terms, m, pins, single=True)
        assert all(lu._inv[k].dtype == np.float32 and lu._x1[k].dtype == np.float32
                   for k in range(1, 24))
    A = np.asarray(TermBlocks(terms, m, None, pins, 0).block(0, 24, 0, 24))
    keep = np.ones(24 * m)
    keep[[k * m + p for k in range(24) for p in pins]] = 0.0

    def mass(v):  # the sum of c_0 over the points: a functional not orthogonal to it
        return float(np.sum(v[:m]))

    c0 = np.zeros(24 * m)
    c0[1:m - 1] = 1.0
    ref = c0 / mass(c0)
    dense = lu_factor(A)
    for _ in range(8):
        ref = lu_solve(dense, keep * ref)
        ref /= mass(ref)
    got = bordered_inverse_iteration(lambda r: lu.solve(r, refine=False), lambda v: A @ v,
                                     c0 / mass(c0), keep, mass, 8, 1e-13)
    assert got is not None
    assert np.max(np.abs(got[0] - ref)) <= 1e-10 * np.max(np.abs(ref))


def test_single_factors_on_disk_sweep_as_in_memory(tmp_path):
    """The single-precision factors on disk give the sweeps of those in memory bit for bit
    (the forward sweep recomputes ``A(k-1, k)`` by the elimination's own single-precision
    operations)."""
    terms, m = _terms(20, 40)
    pins = (0, m - 1)
    ram = HermitePentadiagonalLU(terms, m, pins, single=True)
    lu = disk.DiskPentadiagonalLU(terms, m, pins, directory=str(tmp_path), single=True)
    rng = np.random.default_rng(11)
    for _ in range(2):
        b = rng.standard_normal(20 * m)
        assert np.array_equal(lu.solve(b, refine=False), ram.solve(b, refine=False))


def test_single_factors_stay_in_memory_below_the_cap():
    """The route by :data:`FACTOR_MEMORY`: ``12 N m^2`` bytes in single precision against
    ``24 N m^2`` in double, so a cap between the two keeps the single-precision factors in
    memory and sends the double ones to disk."""
    terms, m = _terms(12, 20)
    assert disk.factor_bytes(12, m, single=True) * 2 == disk.factor_bytes(12, m)
    cap = 1.5 * disk.factor_bytes(12, m, single=True)
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(disk, "FACTOR_MEMORY", cap)
        single = disk.pentadiagonal_lu(terms, m, (0, m - 1), single=True)
        double = disk.pentadiagonal_lu(terms, m, (0, m - 1))
    assert type(single) is HermitePentadiagonalLU and single._inv[3].dtype == np.float32
    assert isinstance(double, disk.DiskPentadiagonalLU)


def test_mixed_solve_on_disk_is_boltzmann_for_linear_damping(monkeypatch):
    """CDC at rest (linear damping, kT = D/mu = 0.6), at a velocity scale not the
    Maxwellian's (0.8 kT^(1/2)), by GMRES on single-precision factors kept on disk
    (:data:`FACTOR_MEMORY` 0): <x^2> the quadrature of x^2 exp(-G/kT) to 1e-8 and
    <x'^2> = kT to 1e-8, the solve of the factors in memory to 1e-12."""
    split = split_conservative("cdc", CDC)
    G = split.numpy_functions()[2]

    def solve():
        return orthonormal_stationary(split, 0.09, 0.8 * math.sqrt(0.6), 5.0, 40, 160, G,
                                      1.0, mixed=True)

    ram = solve()
    made = []
    real = disk.DiskPentadiagonalLU

    def counted(*args, **kwargs):
        made.append(kwargs.get("single"))
        return real(*args, **kwargs)

    monkeypatch.setattr(disk, "FACTOR_MEMORY", 0)
    monkeypatch.setattr(disk, "DiskPentadiagonalLU", counted)
    sol = solve()
    assert made == [True]  # the single-precision factors, no fallback to the direct solve
    assert sol.x2 == pytest.approx(boltzmann_moment(split, 0.6), rel=1e-8)
    assert sol.v2 == pytest.approx(0.6, rel=1e-8)
    assert sol.x2 == pytest.approx(ram.x2, rel=1e-12)
    assert sol.v2 == pytest.approx(ram.v2, rel=1e-12)
