"""Numerical evaluation of the infinite Bessel sums: the stated tolerance is met, and a sum
that cannot meet it within its term budget says so (kbm.output.evaluate)."""

from __future__ import annotations

import mpmath
import numpy as np
import pytest
import scipy.special as sps
import sympy as sp
from hypothesis import given, strategies as st

from kbm import SeriesTruncationError, derive, mpmath_function, numpy_function

n, z = sp.Symbol("n", integer=True), sp.Symbol("z")


@given(st.floats(min_value=0.01, max_value=40.0))
def test_jacobi_anger_identity_to_tolerance(zv):
    """Jacobi-Anger / Neumann: J_0(z) + 2 sum_{n>=1} J_{2n}(z) = 1 (A&S 9.1.46), to ~1e-15."""
    f = numpy_function(sp.besselj(0, z) + 2 * sp.Sum(sp.besselj(2 * n, z), (n, 1, sp.oo)), [z])
    assert abs(float(f(zv)) - 1.0) < 5e-14


def test_sum_of_squares_identity_vectorised():
    """J_0(z)^2 + 2 sum_{n>=1} J_n(z)^2 = 1 (A&S 9.1.76), vectorised over z."""
    f = numpy_function(sp.besselj(0, z)**2 + 2 * sp.Sum(sp.besselj(n, z)**2, (n, 1, sp.oo)), [z])
    zs = np.linspace(0.0, 30.0, 61)
    assert np.max(np.abs(f(zs) - 1.0)) < 1e-14


def test_numpy_truncation_meets_tolerance_against_mpmath():
    """sedf B_2 and u_2 (double sums) in double precision agree with 30-digit mpmath
    evaluation to ~1e-13 relative: the truncation error is below the stated tolerance."""
    res = derive("sedf", 2, params={"beta": 1, "delta": "3/2", "k": 2, "Omega": 1})
    a, psi = sp.symbols("a psi")
    fB = numpy_function(res.B[2], [a])
    fu = numpy_function(res.u[2], [a, psi])
    with mpmath.workdps(30):
        gB = mpmath_function(res.B[2], [a])
        gu = mpmath_function(res.u[2], [a, psi])
        for av in ("0.3", "1.7", "3.1"):
            ref = gB(mpmath.mpf(av))
            assert abs(float(fB(float(av))) - float(ref)) <= 1e-13 * max(1.0, abs(float(ref)))
            ref_u = gu(mpmath.mpf(av), mpmath.mpf("0.4"))
            assert abs(float(fu(float(av), 0.4)) - float(ref_u)) <= 1e-13 * max(1.0, abs(float(ref_u)))


def test_truncation_failure_is_reported():
    """A sum whose terms have not decayed within the term budget raises, with the size of
    the last terms, instead of returning an unconverged number."""
    f = numpy_function(sp.Sum(sp.besselj(2 * n + 1, z), (n, 0, sp.oo)), [z], max_terms=50)
    with pytest.raises(SeriesTruncationError, match="did not converge"):
        f(1000.0)
    g = numpy_function(sp.Sum(sp.besselj(2 * n + 1, z), (n, 0, sp.oo)), [z])
    # int_0^z J_0(t) dt = 2 sum_{n>=0} J_{2n+1}(z) (A&S 11.1.2): check against quadrature
    from scipy.integrate import quad
    ref = 0.5 * quad(lambda s: sps.j0(s), 0, 7.5, epsabs=1e-13, epsrel=1e-13, limit=200)[0]
    assert abs(float(g(7.5)) - ref) < 1e-12
