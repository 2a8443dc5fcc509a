"""True periodic responses of forced oscillators (numerics.shooting) and the KBM predictions.

Independent references: the exact response and Floquet multipliers of the linear damped
forced oscillator; a hand-written scipy solve_ivp shooting; long simulations (locking).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from kbm.errors import ParameterError
from kbm.model.forced import ForcedOscillator
from kbm.expansion.forced import derive_forced
from kbm.slowflow.steady import response_curve
from numerics.errors import ConvergenceError
from numerics.flow.forced_system import ForcedSystem
from numerics.shooting.forced_branch import numeric_response
from numerics.shooting.forced_orbit import periodic_response
from numerics.comparison.response_convergence import amplitude_study, fold_study, slope
from numerics.locking.entrainment import (locked_by_simulation, predicted_boundary, start_orbit,
                                     true_boundary)

DUFF = {"zeta": 0.1, "alpha": 1, "h": 0.5}


def test_linear_forced_response_exact():
    """x'' + 2 mu zeta x' + x = mu h cos(nu t): amplitude mu h/sqrt((1-nu^2)^2 + (2 mu zeta
    nu)^2), multipliers of modulus exp(-mu zeta T), Liouville holds."""
    m = ForcedOscillator("lin", "h*cos(theta) - 2*zeta*xdot")
    mu, z, h, s = 0.1, 0.3, 0.7, 0.4
    sys_ = ForcedSystem(m, {"mu": mu, "zeta": z, "h": h})
    o = periodic_response(sys_, s, (0.0, 0.0))
    nu = 1 + mu * s
    exact = mu * h / math.sqrt((1 - nu**2)**2 + (2 * mu * z * nu)**2)
    assert abs(o.amplitude - exact) < 1e-9 and abs(o.amplitude_max - exact) < 1e-6
    T = 2 * math.pi / nu
    assert abs(o.period - T) < 1e-15
    assert np.allclose([abs(x) for x in o.multipliers], math.exp(-mu * z * T), rtol=1e-8)
    assert o.liouville < 1e-9 and o.stable


def _scipy_shooting(sigma, y0, mu=0.05):
    """Newton on the stroboscopic map with scipy's DOP853 and a finite-difference Jacobian."""
    nu = 1 + mu * sigma
    T = 2 * math.pi / nu

    def f(t, y):
        return [y[1], -y[0] + mu * (-2 * DUFF["zeta"] * y[1] - DUFF["alpha"] * y[0]**3
                                    + DUFF["h"] * math.cos(nu * t))]

    def P(y):
        return solve_ivp(f, (0, T), y, method="DOP853", rtol=1e-12, atol=1e-12).y[:, -1]

    y = np.array(y0, float)
    for _ in range(30):
        r = P(y) - y
        J = np.column_stack([(P(y + 1e-7 * e) - P(y)) / 1e-7 for e in np.eye(2)]) - np.eye(2)
        dy = np.linalg.solve(J, -r)
        y = y + dy
        if np.max(np.abs(dy)) < 1e-11:
            return y
    raise AssertionError("scipy shooting did not converge")


def test_duffing_responses_agree_with_handwritten_solve_ivp_shooting():
    """At sigma = 1 (three responses) the compiled shooting and a scipy one agree."""
    sys_ = ForcedSystem("duffing-forced", {**DUFF, "mu": 0.05})
    sf = derive_forced("duffing-forced", 2).slow_flow({**DUFF, "mu": 0.05})
    from kbm.slowflow.steady import fixed_points
    from numerics.shooting.forced_branch import guess_from

    fps = fixed_points(sf, 1.0, (1e-3, 4))
    assert len(fps) == 3
    stab = []
    for fp in fps:
        o = periodic_response(sys_, 1.0, guess_from(sys_, fp.amplitude, fp.phase, 1.0))
        ref = _scipy_shooting(1.0, o.y0)
        assert np.allclose(ref, o.y0, atol=1e-8)
        assert abs(o.amplitude - fp.amplitude) < 0.05 * 0.05 * 10
        assert o.liouville < 1e-8
        stab.append(o.stable)
    assert stab == [True, False, True]


def test_numeric_response_both_branches_and_folds_near_kbm_order2():
    vals = {**DUFF, "mu": 0.05}
    r = derive_forced("duffing-forced", 2)
    sys_ = ForcedSystem("duffing-forced", vals)
    nr = numeric_response(sys_, r.slow_flow(vals), (-1.0, 1.5), (1e-3, 4), n_points=150)
    # in this window: the resonant branch (from sigma = -1 over the peak to 1.5) and the
    # lower branch that turns at the jump point into the middle (unstable) one
    assert len(nr.branches) == 2 and len(nr.folds) == 1 and not nr.failures
    b = [o for br in nr.branches for o in br]
    st = np.array([o.stable for o in b])
    assert st.any() and (~st).any()
    # an unstable response has a multiplier outside the unit circle, real and > 1 (saddle)
    un = [o for o in b if not o.stable]
    assert all(max(m.real for m in o.multipliers) > 1 for o in un)
    f_true = nr.folds[0].sigma
    f1 = response_curve(r.slow_flow(vals, order=1), (-1.0, 1.5), (1e-3, 4)).folds[0].sigma
    f2 = response_curve(r.slow_flow(vals, order=2), (-1.0, 1.5), (1e-3, 4)).folds[0].sigma
    assert abs(f2 - f_true) < abs(f1 - f_true) / 10
    # at the fold one multiplier is 1
    assert min(abs(m - 1) for m in nr.folds[0].multipliers) < 1e-4


def test_amplitude_error_slopes_duffing():
    """Order-N amplitude error at sigma = 0 against shooting: slopes ~N (N = 1, 2)."""
    t = amplitude_study("duffing-forced", DUFF, 0.0, [0.01, 0.02, 0.04], (1, 2))
    s = t.slopes
    assert 0.85 < s[1] < 1.2 and 1.8 < s[2] < 2.3, t.errors
    assert all(e2 < e1 for e1, e2 in zip(t.errors[1], t.errors[2]))


@pytest.mark.slow  # 4-8 s; kept out of the default run (five-minute rule)
def test_fold_error_slopes_duffing():
    """The lower jump point's detuning: errors of orders 1, 2, 3 with slopes ~1, 2, 3."""
    t = fold_study("duffing-forced", DUFF, (0.0, 1.2), [0.01, 0.02, 0.04], (1, 2, 3))
    s = t.slopes
    assert 0.85 < s[1] < 1.2 and 1.8 < s[2] < 2.2 and 2.6 < s[3] < 3.3, t.to_json()


def test_parametric_duffing_amplitude_orders():
    """Principal parametric resonance of x'' + x = mu (-2 zeta x' - x^3 - h x cos nu t) at
    sigma = 0.8: both nontrivial responses (a saddle and a node) by shooting; the order-N
    amplitudes' errors fall with slopes ~N (N = 1, 2, 3)."""
    from numerics.comparison.response_diagram import steady_states

    vals = {"zeta": 0.05, "alpha": 1, "h": 1}
    mus = [0.01, 0.02, 0.04]
    errs = {1: [], 2: [], 3: []}
    for m in mus:
        s = {n: steady_states("parametric", {**vals, "mu": m}, 0.8, order=n,
                              amplitudes=(1e-3, 3), numeric=n == 1) for n in (1, 2, 3)}
        assert [f.stable for f in s[1].analytic] == [False, True] and s[1].trivial == "stable"
        true = [o.amplitude for o in s[1].numeric]
        assert [o.stable for o in s[1].numeric] == [False, True]
        for n in (1, 2, 3):
            errs[n].append(max(abs(f.amplitude - t) for f, t in zip(s[n].analytic, true)))
    sl = {n: slope(mus, e) for n, e in errs.items()}
    assert 0.85 < sl[1] < 1.2 and 1.7 < sl[2] < 2.3 and 2.5 < sl[3] < 3.4, (errs, sl)


def test_vdp_locking_boundary():
    """The locking boundary of x'' - mu (1 - x^2) x' + x = mu h cos(nu t), h = 0.4: first
    and second order against shooting + Floquet, errors O(mu) and O(mu^2); a long simulation
    confirms locked / drifting on either side of the true boundary."""
    r = derive_forced("vdp-forced", 2)
    mus = [0.05, 0.1, 0.2]
    e1, e2 = [], []
    for m in mus:
        vals = {"h": 0.4, "mu": m}
        s = ForcedSystem("vdp-forced", vals)
        tb = true_boundary(s, start_orbit(s, r.slow_flow(vals)), 1.0).sigma
        e1.append(abs(predicted_boundary(r.slow_flow(vals, order=1), 1.0).sigma - tb))
        e2.append(abs(predicted_boundary(r.slow_flow(vals, order=2), 1.0).sigma - tb))
        if m == 0.1:
            assert locked_by_simulation(s, 0.95 * tb, (2.0, 0.0))
            assert not locked_by_simulation(s, 1.05 * tb, (2.0, 0.0))
    assert 0.8 < slope(mus, e1) < 1.2 and 1.7 < slope(mus, e2) < 2.4, (e1, e2)
    assert all(b < a for a, b in zip(e1, e2))


def test_system_errors():
    with pytest.raises(ParameterError, match="needs a value of mu"):
        ForcedSystem("duffing-forced", DUFF)
    with pytest.raises(ParameterError, match="needs values of h"):
        ForcedSystem("duffing-forced", {"zeta": 1, "alpha": 1, "mu": 0.1})
    s = ForcedSystem("duffing-forced", {**DUFF, "mu": 0.5})
    with pytest.raises(ParameterError, match="not positive"):
        s.period(-3.0)
    with pytest.raises(ConvergenceError, match="no periodic response"):
        periodic_response(ForcedSystem("vdp-forced", {"h": 0.1, "mu": 0.1}), 3.0, (2.0, 0.0),
                          max_iter=3)


def test_subharmonic_response_of_period_three_forcing_periods():
    """Duffing near nu = 3 omega0 (resonance 3): the subharmonic pair (a saddle and a node)
    of period 6 pi/nu appears at order 2 (weak forcing); shooting finds both, and the
    order-3 amplitudes are closer (in sum) than the order-2 ones."""
    from numerics.comparison.response_diagram import steady_states

    m = ForcedOscillator("sub", "-2*zeta*xdot - x**3 + h*cos(theta)", resonance="3")
    vals = {"mu": 0.04, "zeta": 0.001, "h": 3}
    s2 = steady_states(m, vals, 1.0, order=2, amplitudes=(1e-3, 3))
    s3 = steady_states(m, vals, 1.0, order=3, amplitudes=(1e-3, 3), numeric=False)
    assert [o.stable for o in s2.numeric] == [False, True]
    nu = 3 + 0.04 * 1.0
    assert all(abs(o.period - 6 * math.pi / nu) < 1e-12 for o in s2.numeric)
    e2 = [abs(f.amplitude - o.amplitude) for o, f in zip(s2.numeric, s2.analytic)]
    e3 = [abs(f.amplitude - o.amplitude) for o, f in zip(s2.numeric, s3.analytic)]
    assert sum(e3) < sum(e2) / 5 and max(e3) < 1e-4, (e2, e3)


def test_hard_superharmonic_amplitude_slopes():
    """Hard superharmonic resonance (K = 1, sigma = 0): orders 1-3 against shooting, slopes
    ~1, 2, 3 (the response x = y + Lambda cos(nu t): its harmonic at 3 nu is KBM's a)."""
    t = amplitude_study("duffing-super-hard", {"zeta": 0.02, "alpha": 1, "K": 1}, 0.0,
                        [0.01, 0.02, 0.04], (1, 2, 3), amplitudes=(1e-3, 3))
    s = t.slopes
    assert 0.8 < s[1] < 1.2 and 1.8 < s[2] < 2.3 and 2.6 < s[3] < 3.4, t.to_json()


def test_hard_subharmonic_pair_against_shooting():
    """Hard subharmonic resonance (nu near 3, K = 2): the saddle-node pair of period
    6 pi/nu; order 3 within 1e-5 of shooting at mu = 0.02, order 1 within 2e-3."""
    from numerics.comparison.response_diagram import steady_states

    vals = {"mu": 0.02, "zeta": 0.01, "alpha": 1, "K": 2}
    s1 = steady_states("duffing-sub-hard", vals, 1.0, order=1, amplitudes=(1e-3, 3))
    s3 = steady_states("duffing-sub-hard", vals, 1.0, order=3, amplitudes=(1e-3, 3),
                       numeric=False)
    assert [o.stable for o in s1.numeric] == [False, True]
    assert all(abs(o.period - 6 * math.pi / 3.02) < 1e-12 for o in s1.numeric)
    for o, f1, f3 in zip(s1.numeric, s1.analytic, s3.analytic):
        assert abs(f1.amplitude - o.amplitude) < 2e-3
        assert abs(f3.amplitude - o.amplitude) < 1e-5
