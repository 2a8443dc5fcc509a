"""Mathieu tongues from the forced KBM engine against independent references.

x'' + (delta + eps cos t) x = 0 near delta = 1/4 (the built-in ``mathieu`` model). With
z = t/2 it is Abramowitz & Stegun's y'' + (a - 2 q cos 2z) y = 0 with a = 4 delta,
q = -2 eps, so the transition curves are delta = a_1(2 eps)/4 and b_1(2 eps)/4
(A&S 20.2.25; the sign of q swaps a_1 and b_1).  References: the A&S series (typed here,
and itself checked against scipy), scipy.special.mathieu_a/b, and Floquet numerics (the
monodromy matrix over 2 pi has trace +-2 on a transition curve).
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp
from scipy.optimize import brentq
from scipy.special import mathieu_a, mathieu_b

from kbm.expansion.forced import derive_forced
from kbm.slowflow.tongues import epsilon, mathieu_transition, transition_curves
from numerics.comparison.response_convergence import slope

q = sp.Symbol("q")
#: A&S 20.2.25 (the characteristic values with q small)
AS_A1 = 1 + q - q**2 / 8 - q**3 / 64 - q**4 / 1536 + 11 * q**5 / 36864 \
    + 49 * q**6 / 589824
AS_B1 = 1 - q - q**2 / 8 + q**3 / 64 - q**4 / 1536 - 11 * q**5 / 36864 \
    + 49 * q**6 / 589824


@pytest.fixture(scope="module")
def curves6():
    return [mathieu_transition(c) for c in transition_curves(derive_forced("mathieu", 6))]


def test_as_series_transcription_against_scipy():
    """The typed A&S series agree with scipy's characteristic values to O(q^7)."""
    for qq in (0.05, 0.1, 0.2):
        assert abs(float(AS_A1.subs(q, qq)) - mathieu_a(1, qq)) < 2 * qq**7
        assert abs(float(AS_B1.subs(q, qq)) - mathieu_b(1, qq)) < 2 * qq**7


def test_order6_series_equals_abramowitz_stegun(curves6):
    """delta(eps) through eps^6 from KBM order 6 equals a_1/4 and b_1/4 at q = 2 eps."""
    ref = {sp.expand(AS_A1.subs(q, 2 * epsilon) / 4), sp.expand(AS_B1.subs(q, 2 * epsilon) / 4)}
    assert {sp.expand(c) for c in curves6} == ref


def test_first_orders_textbook():
    """delta = 1/4 +- eps/2 - eps^2/8 -+ eps^3/32 (order 3)."""
    got = {sp.expand(mathieu_transition(c)) for c in transition_curves(derive_forced("mathieu", 3))}
    e = epsilon
    assert got == {sp.Rational(1, 4) + e / 2 - e**2 / 8 - e**3 / 32,
                   sp.Rational(1, 4) - e / 2 - e**2 / 8 + e**3 / 32}


@pytest.mark.parametrize("order", [1, 2, 3, 4])
def test_kbm_tongue_error_against_scipy_scales(order):
    """The order-N transition curves differ from scipy's a_1/4, b_1/4 by O(eps^(N+1))."""
    cs = [sp.lambdify(epsilon, mathieu_transition(c)) for c in
          transition_curves(derive_forced("mathieu", order))]
    eps = np.array([0.02, 0.04, 0.08])
    errs = []
    for e in eps:
        ref = sorted([mathieu_a(1, 2 * e) / 4, mathieu_b(1, 2 * e) / 4])
        got = sorted(float(f(e)) for f in cs)
        errs.append(max(abs(g - r) for g, r in zip(got, ref)))
    assert slope(eps, errs) > order + 0.7, (errs, slope(eps, errs))


def _trace(delta: float, eps: float) -> float:
    def f(t, y):
        return [y[1], -(delta + eps * np.cos(t)) * y[0], y[3], -(delta + eps * np.cos(t)) * y[2]]

    s = solve_ivp(f, (0, 2 * np.pi), [1, 0, 0, 1], rtol=1e-12, atol=1e-13, method="DOP853")
    return s.y[0, -1] + s.y[3, -1]


def test_kbm_tongue_against_floquet_numerics(curves6):
    """At eps = 0.2 the Floquet boundaries (trace of the monodromy = -2, period 4 pi)
    agree with the order-6 curves to ~eps^7."""
    e = 0.2
    for c in curves6:
        d_kbm = float(c.subs(epsilon, e))
        d_true = brentq(lambda d: _trace(d, e) + 2, d_kbm - 0.01, d_kbm + 0.01, xtol=1e-14)
        assert abs(d_true - d_kbm) < 5e-6, (d_true, d_kbm)
        assert abs(d_true - d_kbm) > 1e-12  # a truncated series, not the exact curve


def test_inside_the_tongue_trivial_state_unstable():
    """The slow flow's trivial state is unstable inside the first-order tongue |sigma| < 1
    (with damping: parametric model, alpha = 0) and stable outside it."""
    from kbm.slowflow.steady import trivial_state

    r = derive_forced("parametric", 1, {"alpha": 0})
    sf = r.slow_flow({"mu": 0.1, "zeta": 0.1, "h": 1})
    # first order, omega0 = 1 (Nayfeh & Mook 5.7): unstable for sigma^2 < h^2/4 - 4 zeta^2
    r2 = derive_forced("parametric", 1, {"alpha": 0, "zeta": sp.Rational(1, 10), "h": 1})
    bounds = sorted(float(c.sigma) for c in transition_curves(r2))
    assert np.allclose(bounds, [-np.sqrt(0.25 - 0.04), np.sqrt(0.25 - 0.04)], rtol=1e-14)
    assert trivial_state(sf, 0.0) == "unstable"
    assert trivial_state(sf, bounds[1] + 0.05) == "stable"
    assert trivial_state(sf, bounds[1] - 0.05) == "unstable"
    assert trivial_state(sf, bounds[0] - 0.05) == "stable"


def _damped_boundary_residual(s, mu, h, z):
    """tr M + 1 + det M for x'' + 2 mu z x' + (1 + mu h cos nu t) x = 0 over one forcing
    period (zero when a multiplier is -1: the edge of the principal tongue)."""
    nu = 2 + mu * s

    def f(t, y):
        k = 1 + mu * h * np.cos(nu * t)
        return [y[1], -k * y[0] - 2 * mu * z * y[1], y[3], -k * y[2] - 2 * mu * z * y[3]]

    sol = solve_ivp(f, (0, 2 * np.pi / nu), [1, 0, 0, 1], rtol=1e-12, atol=1e-13,
                    method="DOP853")
    M = sol.y[:, -1].reshape(2, 2).T
    return np.trace(M) + 1 + np.linalg.det(M)


def test_damped_tongue_sigma_of_h_against_floquet():
    """The tongue sigma(h, zeta) of the damped parametric oscillator, symbolic in h and
    zeta, at orders 1-3 against the Floquet boundary (a multiplier -1); errors fall."""
    import sympy as sp

    mu, h, z = 0.1, 1.0, 0.1
    errs = {}
    for n in (1, 2, 3):
        curves = transition_curves(derive_forced("parametric", n, {"alpha": 0}))
        assert {s.name for s in curves[0].sigma.free_symbols} == ({"h", "zeta"} if n == 1
                                                                   else {"h", "zeta", "mu"})
        pred = sorted(float(c.sigma.subs({sp.Symbol("h"): h, sp.Symbol("zeta"): z,
                                          sp.Symbol("mu"): mu})) for c in curves)
        true = [brentq(_damped_boundary_residual, p - 0.1, p + 0.1, args=(mu, h, z),
                       xtol=1e-13) for p in pred]
        errs[n] = max(abs(p - t) for p, t in zip(pred, true))
    assert errs[2] < errs[1] / 5 and errs[3] < errs[2] / 3, errs


def test_undamped_trivial_state_neutral_outside_unstable_inside():
    """Without damping the trivial state is a centre outside the tongue (neutral, not
    'stable') and a saddle inside; the edges at order 3 match the transition curves."""
    from kbm.slowflow.steady import trivial_state

    r = derive_forced("mathieu", 3)
    sf = r.slow_flow({"mu": 0.1})
    import sympy as sp

    edges = sorted(float(c.sigma.subs(sp.Symbol("mu"), 0.1)) for c in transition_curves(r))
    assert trivial_state(sf, edges[0] - 0.02) == "neutral"
    assert trivial_state(sf, edges[0] + 0.02) == "unstable"
    assert trivial_state(sf, edges[1] - 0.02) == "unstable"
    assert trivial_state(sf, edges[1] + 0.02) == "neutral"


def test_tongue_opening_at_second_order_is_refused_at_first_order_with_reason():
    """x'' + x = -mu x cos(t) (delta = 1): no resonant term at first order; the tongue
    opens at order 2, which order 1 cannot reach (orders >= 2: tests/test_forced_tongues)."""
    from kbm.errors import ModelError
    from kbm.model.forced import ForcedOscillator

    r = derive_forced(ForcedOscillator("m1", "-x*cos(theta)", resonance="1/1"), 1)
    with pytest.raises(ModelError, match="the tongue opens at order 2"):
        transition_curves(r)
