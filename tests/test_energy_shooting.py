"""Energy-averaging predictions against the true limit cycles of the slider (paper parameters).

The reference is the periodic orbit found by shooting (``numerics.limit_cycle``,
Newton on the return map with a DOP853 flow at rtol 1e-12), started from a
plain scipy transient where Newton from the prediction does not converge:
independent of the averaging.  mu = 0.1, Omega = 1, lam = 1.  Order 2 is the
default position scheme (:mod:`numerics.energy.position`); the energy-angle
scheme is tested where it differs.
"""

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp

import kbm
import numerics
from kbm.model.conservative import split_conservative
from numerics.energy import phase_portrait, position_cycle, predict_cycles

CASES = [(1.5, 1.0), (3.0, 1.0), (1.5, 0.25)]


def _true_cycle(D, beta, mu, guess):
    pars = {"mu": mu, "Delta": D, "beta": beta, "lam": 1}
    try:
        return numerics.limit_cycle("sedf", pars, guess=guess)
    except numerics.NumericsError:
        pass
    # a transient from the predicted maximum, then shooting from where it settles

    def f(_, y):
        return [y[1], -mu * (beta * y[0] ** 2 - 1) * y[1] - D * np.sin(2 * np.pi * y[0]) - y[0]]

    def turn(_, y):
        return y[1]
    turn.direction = -1
    sol = solve_ivp(f, (0, 60 / mu), [guess[0], 0.0], rtol=1e-11, atol=1e-12, events=turn)
    te, ye = sol.t_events[0], sol.y_events[0]
    top = ye[:, 0] > 0
    return numerics.limit_cycle("sedf", pars, guess=(ye[top][-1, 0], np.diff(te[top])[-1]))


_cache: dict = {}


def _data(D, beta, mu=0.1):
    key = (D, beta, mu)
    if key not in _cache:
        pars = {"mu": mu, "Delta": D, "beta": beta, "lam": 1}
        p1 = predict_cycles("sedf", pars, order=1)
        p2 = predict_cycles("sedf", pars, order=2)
        # the cycle around the origin (the largest one the shooting's section x' = 0, x > 0 sees)
        c1 = max(p1.cycles, key=lambda c: c.amplitude_max)
        c2 = max(p2.cycles, key=lambda c: c.amplitude_max)
        assert c2.scheme == "position"
        true = _true_cycle(D, beta, mu, (c1.amplitude_max, c1.period))
        _cache[key] = (c1, c2, true)
    return _cache[key]


@pytest.mark.parametrize("D,beta", CASES)
def test_first_order_amplitude_within_1e3(D, beta):
    """Order 1 (energy balance Gamma(E*) = 0): max x within 1e-3 of the true cycle; stable."""
    c1, _, true = _data(D, beta)
    assert true.success and true.stable
    assert abs(c1.amplitude_max - true.amplitude_max) < 1e-3
    assert abs(c1.amplitude_min + true.amplitude_max) < 1e-3  # odd symmetry of sedf
    assert c1.stable


@pytest.mark.parametrize("D,beta", CASES)
def test_second_order_improves_period(D, beta):
    """Order 2 has a smaller period error than order 1, and smaller first-harmonic, max x
    and multiplier errors, also at Delta = 3 where E* is 0.12 energy swings above the
    separatrix (period_sensitivity 1.2): there |dT| drops from 0.21 to < 2e-4."""
    c1, c2, true = _data(D, beta)
    for q in ("period", "amplitude_first_harmonic", "amplitude_max"):
        assert abs(getattr(c2, q) - getattr(true, q)) < abs(getattr(c1, q) - getattr(true, q))
    m = true.floquet_multipliers[1].real
    assert abs(c2.floquet_multiplier - m) < abs(c1.floquet_multiplier - m)
    assert abs(c2.period - true.period) < 2e-4 and abs(c2.amplitude_max - true.amplitude_max) < 1e-5
    assert c2.stable


def test_energy_angle_breaks_down_at_delta_3():
    """The energy-angle series at order 2 is worse than order 1 at Delta = 3 (it diverges
    near the separatrix); the default position scheme is not."""
    c1, _, true = _data(3.0, 1.0)
    pars = {"mu": 0.1, "Delta": 3.0, "beta": 1.0, "lam": 1}
    ea = max(predict_cycles("sedf", pars, order=2, scheme="energy-angle").cycles,
             key=lambda c: c.amplitude_max)
    assert ea.scheme == "energy-angle"
    assert abs(ea.period - true.period) > abs(c1.period - true.period)


def test_validity_indicators():
    """The energy-angle breakdown at Delta = 3 is flagged: separatrix_margin < 1 and
    period_sensitivity > 1 there, both on the good side at Delta = 1.5 (beta = 1, 0.25)."""
    c3 = _data(3.0, 1.0)[0]
    assert c3.separatrix_margin < 1 and c3.period_sensitivity > 1
    for beta in (1.0, 0.25):
        c = _data(1.5, beta)[0]
        assert c.separatrix_margin > 1 and c.period_sensitivity < 0.5


def _slope(mus, errs):
    return np.polyfit(np.log(mus), np.log(np.abs(errs)), 1)[0]


def test_period_error_convergence_in_mu():
    """Delta = 1.5, beta = 1, mu = 0.1, 0.05, 0.025: period and max x errors ~ mu^2 at
    order 1 and ~ mu^4 at order 2 (h odd in x': the period is even in mu, and so are the
    errors of both schemes)."""
    mus = np.array([0.1, 0.05, 0.025])
    e1, e2, x2 = [], [], []
    for mu in mus:
        c1, c2, true = _data(1.5, 1.0, mu)
        e1.append(c1.period - true.period)
        e2.append(c2.period - true.period)
        x2.append(c2.amplitude_max - true.amplitude_max)
    assert _slope(mus, e1) == pytest.approx(2.0, abs=0.2)
    assert _slope(mus, e2) == pytest.approx(4.0, abs=0.3)
    assert _slope(mus, x2) > 3.5
    assert np.all(np.abs(e2) < 0.01 * np.abs(e1))


def test_asymmetric_side_well_cycle():
    """Delta = 1.5, beta = 1.3: an unstable cycle inside each side well (x in (0.648, 1.068))
    besides the stable outer one; the side-well cycle at x > 0 agrees with shooting to 1e-5
    (order 1) and 1e-8 (order 2) in max x and period, and the mirror cycle is its negative."""
    pars = {"mu": 0.1, "Delta": 1.5, "beta": 1.3, "lam": 1}
    p1 = predict_cycles("sedf", pars, order=1)
    p2 = predict_cycles("sedf", pars, order=2)
    labels = sorted(c.annulus for c in p1.cycles)
    assert labels == ["outer", "side well at x=+0.898", "side well at x=-0.898"]
    right = [next(c for c in p.cycles if c.annulus == "side well at x=+0.898") for p in (p1, p2)]
    left = next(c for c in p1.cycles if c.annulus == "side well at x=-0.898")
    assert left.amplitude_max == pytest.approx(-right[0].amplitude_min, abs=1e-12)
    assert not right[0].stable and not right[1].stable
    true = numerics.limit_cycle("sedf", pars, guess=(right[0].amplitude_max, right[0].period))
    assert true.success and not true.stable and np.min(true.x) > 0
    for c, tol in zip(right, (1e-5, 1e-8)):
        assert abs(c.amplitude_max - true.amplitude_max) < tol
        assert abs(c.period - true.period) < 10 * tol
        assert abs(c.floquet_multiplier - true.floquet_multipliers[1].real) < tol


def test_outer_cycle_beta_13():
    """Delta = 1.5, beta = 1.3, outer cycle: the orbit crawls past the nearly flat stretch of
    G near x = 1.76 (g ~ 0.25); period_sensitivity > 1 flags it, and the energy-angle order 2
    is worse than order 1 there; the position order 2 improves the period from 2.6e-2 to
    < 1e-4, and max x, first harmonic and multiplier too."""
    pars = {"mu": 0.1, "Delta": 1.5, "beta": 1.3, "lam": 1}
    c1, c2, ea = (next(c for c in predict_cycles("sedf", pars, order=n, scheme=s).cycles
                       if c.annulus == "outer")
                  for n, s in ((1, None), (2, None), (2, "energy-angle")))
    assert c1.period_sensitivity > 1
    true = numerics.limit_cycle("sedf", pars, guess=(c1.amplitude_max, c1.period))
    assert abs(c1.amplitude_max - true.amplitude_max) < 1e-3
    assert abs(ea.period - true.period) > abs(c1.period - true.period)
    assert abs(c2.period - true.period) < 1e-4
    m = true.floquet_multipliers[1].real
    for q, t in (("amplitude_max", true.amplitude_max), ("floquet_multiplier", m),
                 ("amplitude_first_harmonic", true.amplitude_first_harmonic)):
        assert abs(getattr(c2, q) - t) < abs(getattr(c1, q) - t)


def test_each_integration_gains_an_order():
    """Delta = 1.5, beta = 1, position scheme after k = 0..4 integrations: the error of the
    3rd harmonic (the waveform's mirror-asymmetric part) ~ mu**(k+1); the period error
    ~ mu**2, mu**2, mu**4, mu**4, mu**6 (even in mu: only every other integration shows)."""
    mus = np.array([0.1, 0.05, 0.025])
    c3, dT = {k: [] for k in range(5)}, {k: [] for k in range(5)}
    for mu in mus:
        c1, _, true = _data(1.5, 1.0, mu)
        split = split_conservative("sedf", {"mu": mu, "Delta": 1.5, "beta": 1.0, "lam": 1})
        portrait = phase_portrait(split)
        a = next(a for a in portrait.annuli if a.label == c1.annulus)
        hv = sp.lambdify((kbm.x, kbm.xdot), sp.diff(split.h, kbm.xdot), "numpy")
        for k in range(5):
            p = position_cycle(a, portrait.functions, hv, mu, c1.energy, k)
            c3[k].append(abs(p.harmonics[3] - true.harmonics[3]))
            dT[k].append(p.period - true.period)
    for k, (lo, hi) in enumerate([(0.8, 1.2), (1.5, 3.0), (2.7, 3.3), (3.7, 4.3), (4.6, 5.4)]):
        assert lo < _slope(mus, c3[k]) < hi
        assert _slope(mus, dT[k]) == pytest.approx(2 * (k // 2 + 1), abs=0.4)


@pytest.mark.parametrize("D,beta", CASES + [(1.5, 1.3)])
def test_order_3_against_shooting(D, beta):
    """Order 3 (three integrations): max x, first harmonic and multiplier within 1e-5,
    period within 2e-4, at all cases (the outer cycle at beta = 1.3)."""
    pars = {"mu": 0.1, "Delta": D, "beta": beta, "lam": 1}
    c = max(predict_cycles("sedf", pars, order=3).cycles, key=lambda c: c.amplitude_max)
    true = _true_cycle(D, beta, 0.1, (c.amplitude_max, c.period))
    assert abs(c.amplitude_max - true.amplitude_max) < 1e-5
    assert abs(c.amplitude_first_harmonic - true.amplitude_first_harmonic) < 1e-5
    assert abs(c.floquet_multiplier - true.floquet_multipliers[1].real) < 1e-5
    assert abs(c.period - true.period) < 2e-4


def test_delta_3_larger_mu():
    """Delta = 3: at mu = 0.15 the true cycle passes the saddles at x = +-1.589 barely
    (period 8.62 against T(E*) = 7.93): order 2 has the period within 5e-3.  At mu = 0.2
    shooting finds no cycle (the motion settles in a side well); order 1 still predicts one
    (Gamma does not depend on mu), order 2 reports that its curve cannot pass the saddle."""
    pars = {"mu": 0.15, "Delta": 3.0, "beta": 1.0, "lam": 1}
    c1 = max(predict_cycles("sedf", pars, order=1).cycles, key=lambda c: c.amplitude_max)
    c2 = max(predict_cycles("sedf", pars, order=2).cycles, key=lambda c: c.amplitude_max)
    true = _true_cycle(3.0, 1.0, 0.15, (c1.amplitude_max, c1.period))
    assert abs(c1.period - true.period) > 0.5
    assert abs(c2.period - true.period) < 5e-3
    pars["mu"] = 0.2
    with pytest.raises(numerics.NumericsError):
        _true_cycle(3.0, 1.0, 0.2, (c1.amplitude_max, c1.period))
    assert any(c.amplitude_max > 2 for c in predict_cycles("sedf", pars, order=1).cycles)
    P = predict_cycles("sedf", pars, order=2)
    assert not any(c.amplitude_max > 2 for c in P.cycles)
    assert "cannot pass the saddle" in P.reason
