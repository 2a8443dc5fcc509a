"""The one locator of special points (numerics.shooting.locate) and the forced response
continued by the one driver under the one acceptance standard (numerics.shooting.forced_branch).

Independent references: the exact roots of scalar test functions (bisection and the
Illinois method, Dahlquist and Bjorck, *Numerical Methods*, sec. 6.2); a hand-written
scipy DOP853 shooting of the forced Duffing oscillator, whose non-trivial multiplier near a
saddle-node of responses obeys ``1 - lambda ~ c sqrt(sigma_f - sigma)`` (Kuznetsov,
*Elements of Applied Bifurcation Theory*, sec. 3.3), so that ``(1 - lambda)^2`` is linear
in sigma and extrapolates to zero at the fold.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

from numerics.errors import ConvergenceError
from numerics.flow.forced_system import ForcedSystem
from numerics.shooting.forced_branch import continue_response
from numerics.shooting.forced_orbit import periodic_response
from numerics.shooting.locate import locate_zero


@settings(max_examples=40, deadline=None)
@given(root=st.floats(0.01, 0.99), power=st.sampled_from([1, 3, 5]), secant=st.booleans())
def test_the_zero_stays_bracketed(root, power, secant):
    """f(w) = (w - r)^k on [0, 1]: the final bracket holds r and is below tol, or the last
    trial point has |f| <= f_tol."""
    f = lambda w: (w - root) ** power  # noqa: E731
    got = locate_zero(lambda w: w, f, 0.0, 1.0, f(0.0), f(1.0), tol=1e-12, f_tol=1e-30,
                      secant=secant, max_iter=200)
    assert got.failure is None
    assert got.lo <= root <= got.hi or abs(f(got.point)) <= 1e-30
    assert got.hi - got.lo < 1e-12 or abs(f(got.point)) <= 1e-30
    assert got.at_lo is None or got.at_lo == got.lo


def test_a_failed_trial_ends_the_location_with_the_bracket_so_far():
    """Past w = 0.7 no orbit: the bracket so far and the error are returned."""
    def trial(w):
        if w > 0.7:
            raise ConvergenceError("no periodic orbit here")
        return w

    got = locate_zero(trial, lambda w: w - 0.6, 0.0, 1.0, -0.6, 0.4, tol=1e-9)
    assert isinstance(got.failure, ConvergenceError)
    assert got.point == 0.5 and (got.lo, got.hi) == (0.5, 1.0) and got.at_lo == 0.5


MU, ZETA, ALPHA, H = 0.05, 0.1, 1.0, 0.5


def _multiplier_near_one(sigma, y0):
    """scipy shooting of x'' + x = mu (-2 zeta x' - alpha x^3 + h cos(nu t)),
    nu = 1 + mu sigma: the Floquet multiplier nearest 1."""
    nu = 1 + MU * sigma

    def f(t, Y):
        x, v = Y[0], Y[1]
        J = np.array([[0.0, 1.0], [-1 - 3 * MU * ALPHA * x * x, -2 * MU * ZETA]])
        return np.concatenate([[v, -x + MU * (-2 * ZETA * v - ALPHA * x**3
                                              + H * math.cos(nu * t))],
                               (J @ Y[2:].reshape(2, 2)).ravel()])

    y = np.array(y0, float)
    for _ in range(40):
        s = solve_ivp(f, (0, 2 * math.pi / nu), np.concatenate([y, np.eye(2).ravel()]),
                      method="DOP853", rtol=1e-13, atol=1e-13)
        yT, P = s.y[:2, -1], s.y[2:, -1].reshape(2, 2)
        dy = np.linalg.solve(P - np.eye(2), y - yT)
        y = y + dy
        if np.max(np.abs(dy)) < 1e-13:
            break
    z = np.linalg.eigvals(P)
    return float(z[np.argmin(np.abs(z - 1))].real)


@pytest.fixture(scope="module")
def duffing_branch():
    system = ForcedSystem("duffing-forced", {"mu": MU, "zeta": ZETA, "alpha": ALPHA, "h": H},
                          rtol=1e-12)
    start = periodic_response(system, 0.3, (0.3, 0.0))
    return system, *continue_response(system, start, (0.3, 2.2), n_points=40)


def test_forced_folds_against_scipy_extrapolation(duffing_branch):
    """Both folds of the hardening Duffing response (the jump points): (1 - lambda)^2 from
    scipy shooting 1e-9 and 4e-9 inside, extrapolated to zero, agrees within 1e-10."""
    _, branch, folds = duffing_branch
    assert len(folds) == 2
    for q in folds:
        side = 1 if q.sigma < 1 else -1  # three responses between the folds
        (s1, g1), (s2, g2) = [(q.sigma + side * d,
                               (1 - _multiplier_near_one(q.sigma + side * d, q.y0)) ** 2)
                              for d in (1e-9, 4e-9)]
        ref = s1 - g1 * (s2 - s1) / (g2 - g1)
        assert q.sigma == pytest.approx(ref, abs=1e-10)
        assert min(abs(m - 1) for m in q.multipliers) < 1e-5


def test_branch_points_are_orbits_at_their_own_detuning(duffing_branch):
    """Every fourth point of the branch, shot again at its fixed sigma from its own state,
    is the same orbit (the acceptance standard, never a residual minimum)."""
    system, branch, _ = duffing_branch
    assert branch[0].sigma == pytest.approx(0.3) and branch[-1].sigma == pytest.approx(2.2)
    for o in branch[::4]:
        r = periodic_response(system, o.sigma, o.y0, tol=1e-12)
        assert np.max(np.abs(np.subtract(r.y0, o.y0))) < 1e-9
