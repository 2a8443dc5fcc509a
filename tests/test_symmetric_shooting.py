"""Half-period shooting of the symmetric cycles of an odd field (numerics.shooting.planar).

For ``f(-y) = -f(y)`` a cycle with ``y(t + T/2) = -y(t)`` solves ``y(T/2) = -y(0)``; the
monodromy matrix of the whole period is ``Phi(T/2)^2`` (the Jacobian is even in ``y``).
References, none from the half-period code: the whole period integrated (the same
compiled flow, twice as long), Liouville's formula ``det Phi(T) = exp(int_0^T div f)``, and
the branch continued with the whole period.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import numerics.shooting.planar as arc
from numerics import limit_cycles
from numerics.cycles.continuation import continue_cycles
from numerics.flow import Method, extended_state, flow

pytest.importorskip("numba")

SEDF = {"mu": 0.1, "beta": 1, "lam": 1}


def _point(params, vary, at, x0, T):
    prob = arc.PlanarProblem("sedf", params, vary, "auto", 1e-10, at)
    u = np.array([x0, T, at])
    prob.choose(u)
    pt = prob.correct(u, np.array([0.0, 0.0, 1.0]), at, max_iter=25)
    return prob, pt


def test_the_half_period_monodromy_squared_is_the_whole_periods():
    """At Delta = 1.5 (paper eq. 3): Phi(T/2)^2 and twice the half divergence integral
    against the whole period integrated; Liouville's formula for the determinant."""
    c = max(limit_cycles("sedf", {**SEDF, "Delta": 1.5}), key=lambda c: c.amplitude_max)
    prob, pt = _point({**SEDF, "Delta": 1.5}, "Delta", 1.5, c.amplitude_max, c.period)
    assert prob.odd
    prob.use_symmetry(pt)
    assert prob.half
    R, A, b, yT, ys = prob.eval(pt.u, 32, with_p=True)
    whole = flow(prob.line(1.5), extended_state(pt.u[0]), pt.u[1], 1, Method.COMPILED, 1e-12,
                 1e-12)[-1]
    assert np.allclose(yT[2:6], whole[2:6], rtol=1e-7, atol=1e-9)
    assert yT[6] == pytest.approx(whole[6], rel=1e-9)
    det = yT[2] * yT[5] - yT[4] * yT[3]
    assert det == pytest.approx(math.exp(yT[6]), rel=1e-7)
    # the whole orbit's samples: the second half is minus the first
    assert len(ys) == 33 and np.allclose(ys[16:, :2], -ys[:17, :2], atol=1e-6)


def test_asymmetric_cycles_and_even_terms_shoot_the_whole_period():
    """A side-well cycle of the odd SEDF (beta = 1.3, Delta = 1.5; x_max = -0.648) is not
    symmetric; a field with an even term is not odd: both keep the whole period."""
    side = min(limit_cycles("sedf", {**SEDF, "beta": 1.3, "Delta": 1.5}),
               key=lambda c: c.amplitude_max)
    assert side.amplitude_max < 0
    prob, pt = _point({**SEDF, "Delta": 1.5}, "beta", 1.3, side.amplitude_max, side.period)
    assert prob.odd
    prob.use_symmetry(pt)
    assert not prob.half

    from kbm import custom_model

    even = custom_model("(1 - x**2)*xdot + c*x**2", name="vdp-even-c")
    prob = arc.PlanarProblem(even, {"mu": 0.1, "c": 0.2}, "c", "auto", 1e-10, 0.2)
    assert not prob.odd


def test_branch_with_half_periods_equals_the_branch_with_whole_periods(monkeypatch):
    """The SEDF branch in Delta (0 to 3): the same points, periods and multipliers (to the
    integration tolerance) with half periods as with whole periods, and fewer integrations
    of half the length."""
    params = {**SEDF, "Delta": 0.0}
    half = continue_cycles("sedf", params, "Delta", (0.0, 3.0), ds_max=0.1)
    monkeypatch.setattr(arc, "_odd_field", lambda line: False)
    whole = continue_cycles("sedf", params, "Delta", (0.0, 3.0), ds_max=0.1)
    assert len(half.points) == len(whole.points) > 20
    for a, b in zip(half.points, whole.points):
        assert a.parameter == pytest.approx(b.parameter, abs=1e-8)
        assert a.period == pytest.approx(b.period, rel=1e-10)
        assert a.amplitude_max == pytest.approx(b.amplitude_max, rel=1e-8)
        assert abs(a.multipliers[1] - b.multipliers[1]) < 1e-8
        assert abs(a.multipliers[0] - 1) < 1e-5
