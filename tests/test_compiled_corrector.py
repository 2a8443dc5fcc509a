"""The compiled Newton corrector of a branch of cycles (numerics/flow/_shooting_corrector.py).

References, none from the compiled corrector: numpy's LAPACK solve and eigenvalues for its
3x3 solve and trivial multiplier; the Python corrector of numerics.shooting.planar (the
same algorithm on numpy, with the parameter values computed exactly per value) for whole
branches; limit cycles shot from scratch at rtol 1e-12; the exact values of
kbm.parameters.bound.ParameterLine for the affine parameter vector it assumes.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import numerics.shooting.planar as arc
from kbm import custom_model
from kbm.parameters.bound import ParameterLine
from numerics import limit_cycle
from numerics.cycles.continuation import continue_cycles
from numerics.errors import ConvergenceError
from numerics.flow import CompiledLine
from numerics.flow.sensitivity import sensitivity_flow, shooting_corrector
from numerics.shooting import acceptance

pytest.importorskip("numba")

SEDF = {"mu": 0.1, "beta": 1, "lam": 1}
FOLD = custom_model("(-nu + x**2 - x**4)*xdot")


@pytest.fixture(scope="module")
def module():
    line = CompiledLine("sedf", SEDF, "Delta", 1.0)
    return sensitivity_flow(line.template).module


finite = st.floats(-10, 10, allow_nan=False, allow_infinity=False)


@settings(max_examples=60, deadline=None)
@given(st.lists(finite, min_size=12, max_size=12))
def test_the_3x3_solve_equals_lapacks(module, entries):
    """Gaussian elimination with partial pivoting against numpy.linalg.solve (LAPACK gesv)."""
    J = np.array(entries[:9]).reshape(3, 3)
    r = np.array(entries[9:])
    cond = np.linalg.cond(J)
    out = np.zeros(3)
    ok = module._solve3(J, r, out)
    if not np.isfinite(cond) or cond > 1e10:
        return  # near singular: no comparison of two solvers is meaningful
    assert ok
    ref = np.linalg.solve(J, r)
    assert np.allclose(out, ref, rtol=1e-12 * cond, atol=1e-12 * cond * np.abs(ref).max())


def test_a_singular_jacobian_is_reported(module):
    out = np.zeros(3)
    J = np.array([[1.0, 2.0, 3.0], [2.0, 4.0, 6.0], [0.0, 0.0, 1.0]])
    assert not module._solve3(J, np.ones(3), out)


@settings(max_examples=80, deadline=None)
@given(st.lists(finite, min_size=4, max_size=4))
def test_the_trivial_multiplier_distance_equals_numpys_eigenvalues(module, m):
    """|m - 1| for the eigenvalue closest to 1, as numerics.shooting.floquet picks it."""
    eig = np.linalg.eigvals(np.array([[m[0], m[1]], [m[2], m[3]]]))
    ref = float(np.min(np.abs(eig - 1.0)))
    got = module._trivial_distance(m[0], m[1], m[2], m[3])
    scale = max(1.0, max(abs(v) for v in m))
    assert got == pytest.approx(ref, abs=1e-7 * scale)


@settings(max_examples=25, deadline=None)
@given(st.floats(0.0, 3.2), st.floats(0.0, 3.2))
def test_the_sedf_values_are_affine_in_Delta(p_ref, p):
    """The corrector's parameter vector pvec(p_ref) + (p - p_ref) rates against the exact
    values at p (delta = Delta/mu, paper eq. 3, in Delta): equal to rounding."""
    line = CompiledLine("sedf", SEDF, "Delta", 1.0)
    assert line.line.affine
    pv = np.asarray(line(p_ref).pvec) + (p - p_ref) * line.rates(p_ref)
    exact = np.asarray(line(p).pvec)
    assert np.allclose(pv, exact, rtol=1e-14, atol=1e-14)


def test_lines_that_are_not_affine_use_the_python_corrector():
    """delta = Delta/mu is not affine in mu; 2 pi/lam not in lam: no compiled corrector."""
    assert not ParameterLine("sedf", {"Delta": 1, "beta": 1, "lam": 1}, "mu", 0.1).affine
    assert not ParameterLine("sedf", {"Delta": 1, "beta": 1, "mu": 0.1}, "lam", 1.0).affine
    prob = arc.PlanarProblem("sedf", {"Delta": 1, "beta": 1, "lam": 1}, "mu", "auto", 1e-10, 0.1)
    prob.choose(np.array([2.0, 6.3, 0.1]))
    assert prob.sensitive and prob.kernel is None
    prob = arc.PlanarProblem("sedf", SEDF, "Delta", "auto", 1e-10, 1.0)
    prob.choose(np.array([2.0, 6.3, 1.0]))
    assert prob.kernel is shooting_corrector(prob.line.template)


def _python_corrector(monkeypatch):
    choose = arc.PlanarProblem.choose

    def python_only(self, u):
        choose(self, u)
        self.kernel = None
    monkeypatch.setattr(arc.PlanarProblem, "choose", python_only)


@pytest.mark.parametrize("case", ["sedf", "fold"])
def test_branches_equal_the_python_correctors(monkeypatch, case):
    """The SEDF branch in Delta (paper eq. 3; half periods) and the fold of cycles of
    F = (-nu + x^2 - x^4) x' in nu (whole periods, through the fold): the same points as
    the Python corrector's, periods to 1e-10, multipliers to 1e-8."""
    if case == "sedf":
        args = ("sedf", SEDF, "Delta", (0.0, 3.2))
        kw = {"ds_max": 0.1}
    else:
        args = (FOLD, {"mu": 0.1, "nu": 0.05}, "nu", (0.0, 0.2))
        kw = {"ds_max": 0.008}
    fast = continue_cycles(*args, **kw)
    with monkeypatch.context() as m:
        _python_corrector(m)
        slow = continue_cycles(*args, **kw)
    assert len(fast.points) == len(slow.points) > 20
    assert abs(fast.evaluations - slow.evaluations) <= 2
    for a, b in zip(fast.points, slow.points):
        assert a.parameter == pytest.approx(b.parameter, abs=1e-10)
        assert a.period == pytest.approx(b.period, rel=1e-10)
        assert a.amplitude_max == pytest.approx(b.amplitude_max, abs=1e-9)
        assert abs(a.multipliers[1] - b.multipliers[1]) < 1e-8
    assert [s.kind for s in fast.special] == [s.kind for s in slow.special]


def test_branch_points_are_the_cycles_shot_from_scratch():
    """Points of the compiled corrector against limit_cycle at rtol 1e-12 (paper eq. 3)."""
    br = continue_cycles("sedf", SEDF, "Delta", (0.0, 3.0), ds_max=0.1)
    for pt in br.points[::7]:
        c = limit_cycle("sedf", {**SEDF, "Delta": pt.parameter}, rtol=1e-12, atol=1e-12,
                        guess=(pt.x0, pt.period))
        assert pt.period == pytest.approx(c.period, rel=1e-10)
        assert abs(pt.multipliers[1] - c.floquet_multipliers[1]) < 1e-7


def test_failures_raise_the_python_correctors_errors():
    """No convergence within max_iter, and a predicted point outside the domain (T < 0)."""
    prob = arc.PlanarProblem("sedf", SEDF, "Delta", "auto", 1e-10, 1.0)
    prob.choose(np.array([2.0, 6.7, 1.0]))
    assert prob.kernel is not None
    row = np.array([0.0, 0.0, 1.0])
    with pytest.raises(ConvergenceError, match="did not converge in 0 iterations"):
        prob.correct(np.array([2.05, 6.7, 1.0]), row, 1.0, max_iter=0)
    with pytest.raises(ConvergenceError, match="left the domain"):
        prob.correct(np.array([2.0, -1.0, 1.0]), row, 1.0)
    with pytest.raises(ConvergenceError, match="step too large"):
        prob.correct(np.array([0.01, 6.7, 1.0]), row, 1.0)
    pt = prob.correct(np.array([2.03, 6.7, 1.0]), row, 1.0, max_iter=25)
    assert math.isclose(pt.u[2], 1.0) and abs(pt.mults[0] - 1) < acceptance.TRIVIAL_TOL


def test_points_near_the_homoclinic_end_have_the_period_of_their_own_parameter():
    """Near the end the period changes 700 times faster than Delta: a point within 1e-9 of
    the branch in (x0, T, Delta) but not corrected once more had a period 1.4e-7 (relative)
    off the cycle shot at its own Delta (rtol 1e-12); the returned points carry the last
    Newton correction and stay within 2e-8."""
    br = continue_cycles("sedf", SEDF, "Delta", (0.0, 4.0), ds_max=0.05)
    late = [p for p in br.points if p.period > 10.0]
    assert len(late) > 10
    checked = 0
    for pt in late[::3]:
        try:
            c = limit_cycle("sedf", {**SEDF, "Delta": pt.parameter}, rtol=1e-12, atol=1e-12,
                            guess=(pt.x0, pt.period))
        except Exception:  # noqa: BLE001 - shooting from scratch fails by the separatrix
            continue
        checked += 1
        assert pt.period == pytest.approx(c.period, rel=2e-8)
    assert checked >= 3


@pytest.mark.parametrize("factor", ["RESIDUAL_FACTOR", "CORRECTION_FACTOR"])
@pytest.mark.parametrize("compiled", [True, False])
def test_both_correctors_take_the_one_acceptance_standard(monkeypatch, factor, compiled):
    """The numbers of numerics.shooting.acceptance (issue 35: one standard, a residual
    relative to the orbit's scale and the Newton correction, tests 1 and 2) decide for the
    compiled corrector as for the Python one: the SEDF cycle at Delta = 1 (paper eq. 3) is
    accepted with them, and with a bound of zero no iterate passes and both report no
    convergence."""

    prob = arc.PlanarProblem("sedf", SEDF, "Delta", "auto", 1e-10, 1.0)
    prob.choose(np.array([2.0, 6.7, 1.0]))
    assert prob.kernel is not None
    if not compiled:
        prob.kernel = None
    row, start = np.array([0.0, 0.0, 1.0]), np.array([2.03, 6.7, 1.0])
    pt = prob.correct(start, row, 1.0, max_iter=25)
    assert abs(pt.mults[0] - 1) < acceptance.TRIVIAL_TOL
    monkeypatch.setattr(acceptance, factor, 0.0)
    with pytest.raises(ConvergenceError, match="did not converge in 6 iterations"):
        prob.correct(start, row, 1.0, max_iter=6)
