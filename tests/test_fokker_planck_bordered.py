"""The stationary solve by GMRES on the single-precision order-by-order LU
(numerics/fokker_planck/_bordered.py) and the single-precision factorisation
(numerics/fokker_planck/_pentadiagonal.py, ``single``).

References: a dense LU (:func:`numpy.linalg.solve`) for flexible GMRES; the direct solve
of the same discretisation (the double-precision order-by-order LU and its inverse
iteration, a second method); for linear damping the Boltzmann density ``exp(-H/kT)``
(Gibbs; Risken, *The Fokker-Planck Equation*, sec. 10.1): ``<x^2>`` the quadrature of
``x^2 exp(-G/kT)`` (:func:`numerics.escape.boltzmann_moment`), ``<x'^2> = kT``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from kbm.model.conservative import split_conservative
from numerics.escape import boltzmann_moment
from numerics.fokker_planck import _bordered
from numerics.fokker_planck._bases import cheb_mapped
from numerics.fokker_planck._bordered import RESIDUAL, fgmres
from numerics.fokker_planck._orthonormal import orthonormal_terms
from numerics.fokker_planck._pentadiagonal import HermitePentadiagonalLU
from numerics.fokker_planck._stationary_solve import orthonormal_stationary

SEDF = {"mu": 0.1, "Delta": 3, "beta": 1, "lam": 1}
CDC = {"mu": 0.15, "Delta": 2, "lam": 1.3, "Omega": 1}


def _sedf(nh=46, nc=120, **kw):
    split = split_conservative("sedf", SEDF)
    G = split.numpy_functions()[2]
    return orthonormal_stationary(split, 0.05, 0.5, 6.0, nh, nc, G, 1.0, **kw)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_fgmres_against_a_dense_solve(seed):
    """Flexible GMRES with an inexact preconditioner (the inverse of a perturbed matrix)
    reaches a true residual below its tolerance and the dense LU's solution to the
    condition number times it; with too few iterations it returns ``None``."""
    rng = np.random.default_rng(seed)
    n = 60
    A = np.eye(n) * 4 + rng.standard_normal((n, n)) / math.sqrt(n)
    P = np.linalg.inv(A + 0.05 * rng.standard_normal((n, n)) / math.sqrt(n))
    b = rng.standard_normal(n)
    x = fgmres(lambda v: A @ v, lambda v: P @ v, b, np.zeros(n), 1e-12, 40)
    assert np.linalg.norm(b - A @ x) <= 1e-12
    ref = np.linalg.solve(A, b)
    assert np.max(np.abs(x - ref)) <= 1e-12 * np.linalg.cond(A) * np.max(np.abs(ref))
    assert fgmres(lambda v: A @ v, lambda v: v, b, np.zeros(n), 1e-12, 2) is None


def test_single_precision_factorisation_is_an_approximate_inverse():
    """The single-precision order-by-order LU (SEDF, 24 functions x 61 points) solves a
    system within 1e-3 of the double-precision LU's solution, and not to 1e-9 (its
    rounding is single precision's), the factors kept in single precision."""
    split = split_conservative("sedf", SEDF)
    xs, Dx = cheb_mapped(60, 5.0, 0.95)
    terms = orthonormal_terms(split, 0.05, 0.5, xs, Dx, 24)
    m = xs.size
    b = np.random.default_rng(3).standard_normal(24 * m)
    ref = HermitePentadiagonalLU(terms, m, (0, m - 1)).solve(b)
    single = HermitePentadiagonalLU(terms, m, (0, m - 1), single=True)
    assert single._inv[5].dtype == np.float32
    err = np.max(np.abs(single.solve(b) - ref)) / np.max(np.abs(ref))
    assert 1e-12 < err <= 1e-3


def test_mixed_solve_equals_the_direct_solve():
    """The SEDF at rest (mu = 0.1, D = 0.05) on 46 functions x 121 points, folded: the
    moments and coefficients by GMRES on the single-precision LU within 1e-10 of the
    direct solve's (the same discretisation; measured 1e-13 and below), converged."""
    direct, mixed = _sedf(mixed=False), _sedf(mixed=True)
    assert mixed.x2 == pytest.approx(direct.x2, rel=1e-10)
    assert mixed.v2 == pytest.approx(direct.v2, rel=1e-10)
    scale = np.max(np.abs(direct.coef))
    assert np.max(np.abs(mixed.coef - direct.coef)) <= 1e-10 * scale
    assert mixed.iteration_change <= 1e-14
    assert mixed.residual == pytest.approx(direct.residual, rel=1e-2, abs=1e-12)


def test_mixed_solve_of_linear_damping_is_boltzmann():
    """CDC at rest (linear damping, kT = D/mu = 0.6) at a velocity scale not the
    Maxwellian's (0.8 kT^(1/2), so every function is used), by GMRES on the
    single-precision LU: <x^2> the quadrature of x^2 exp(-G/kT) to 1e-8 and
    <x'^2> = kT to 1e-8."""
    split = split_conservative("cdc", CDC)
    G = split.numpy_functions()[2]
    sol = orthonormal_stationary(split, 0.09, 0.8 * math.sqrt(0.6), 5.0, 40, 160, G, 1.0,
                                 mixed=True)
    assert sol.x2 == pytest.approx(boltzmann_moment(split, 0.6), rel=1e-8)
    assert sol.v2 == pytest.approx(0.6, rel=1e-8)


def test_unconverged_gmres_falls_back_to_the_direct_solve(monkeypatch):
    """When GMRES cannot reach the residual tolerance (one iteration allowed), the solve
    is the direct one, bit for bit."""
    monkeypatch.setattr(_bordered, "MAX_ITERATIONS", 1)
    a, b = _sedf(mixed=True), _sedf(mixed=False)
    assert np.array_equal(a.coef, b.coef) and a.residual == b.residual


def test_residual_tolerance_is_met(monkeypatch):
    """Every bordered solve returned meets the stated tolerance on the true residual
    (the product of the bordered matrix recomputed)."""
    seen = []
    inner = _bordered.fgmres

    def spy(matvec, precond, rhs, x0, tol, max_iterations):
        x = inner(matvec, precond, rhs, x0, tol, max_iterations)
        seen.append((tol, float(np.linalg.norm(rhs - matvec(x)))))
        return x

    monkeypatch.setattr(_bordered, "fgmres", spy)
    _sedf(mixed=True)
    assert seen and all(tol == RESIDUAL and r <= tol for tol, r in seen)
