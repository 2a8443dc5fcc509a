"""Brent's bounded minimiser and the composite Gauss--Legendre rule of
:mod:`numerics.cycles.localmin` against scipy (a second implementation of the same
method, and an adaptive quadrature of another kind) and closed forms."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from numerics.cycles.localmin import fminbound, integral


@settings(max_examples=300, deadline=None)
@given(st.lists(st.floats(-3, 3), min_size=2, max_size=6), st.floats(-4.0, 0.5),
       st.floats(0.01, 6.0), st.sampled_from([1e-10, 1e-5, 1e-12]))
def test_fminbound_is_scipys_bounded_minimize_scalar_to_the_last_bit(coefs, a, w, xatol):
    """Brent's method (Brent 1973, ch. 5) as ``scipy.optimize.minimize_scalar(method=
    "bounded")`` runs it: on polynomials (several local minima, or a minimum at an end)
    the same ``res.x``, bit for bit."""
    from scipy.optimize import minimize_scalar

    def f(x):
        return float(np.polyval(coefs, x))

    b = a + w
    res = minimize_scalar(f, bounds=(a, b), method="bounded", options={"xatol": xatol})
    assert fminbound(f, a, b, xatol=xatol) == float(res.x)


def test_fminbound_is_scipys_on_the_period_law_spread():
    """The homoclinic end's objective (:func:`numerics.cycles.homoclinic.period_law_fit`:
    the spread of ``T + k ln|p_h - p|`` in ``ln|p_h - p_last|``) on exact law data:
    scipy's minimiser to the bit, and ``p_h`` recovered (the data obey the law with
    ``p_h = 1.5``)."""
    from scipy.optimize import minimize_scalar

    from numerics.cycles.homoclinic import period_law_fit

    ph, k = 1.5, 0.8
    p = np.array([1.49, 1.495, 1.499])
    T = 3.0 - k * np.log(ph - p)

    def spread(logd):
        return float(np.var(T + k * np.log(np.abs(p[-1] + math.exp(logd) - p))))

    span = abs(p[-1] - p[0])
    lo, hi = math.log(1e-9 * span), math.log(100 * span)
    res = minimize_scalar(spread, bounds=(lo, hi), method="bounded", options={"xatol": 1e-10})
    assert fminbound(spread, lo, hi, xatol=1e-10) == float(res.x)
    assert abs(period_law_fit(p, T, k, 1) - ph) < 1e-8


def test_fminbound_refuses_bad_bounds():
    with pytest.raises(ValueError, match="finite"):
        fminbound(abs, 0.0, math.inf)
    with pytest.raises(ValueError, match="exceeds"):
        fminbound(abs, 1.0, 0.0)


@pytest.mark.parametrize("f, F", [
    (lambda s: s + np.sin(s), lambda x: x * x / 2 + 1 - math.cos(x)),
    (lambda s: s ** 3 - s, lambda x: x ** 4 / 4 - x ** 2 / 2),
    (lambda s: np.exp(-s * s), lambda x: math.sqrt(math.pi) / 2 * math.erf(x))])
@pytest.mark.parametrize("x", [-7.3, -1.0, 0.0, 0.4, 2.5, 11.0])
def test_integral_equals_the_antiderivative_and_quad(f, F, x):
    """``int_0^x f`` by the composite 20-point rule: the closed-form antiderivative and
    ``scipy.integrate.quad`` (adaptive Gauss--Kronrod) to ~1e-14 relative."""
    from scipy.integrate import quad

    got = integral(f, 0.0, x)
    assert abs(got - F(x)) <= 1e-13 * max(1.0, abs(F(x)))
    assert abs(got - quad(lambda s: float(f(s)), 0.0, x, epsabs=1e-14, epsrel=1e-13,
                          limit=200)[0]) <= 1e-13 * max(1.0, abs(F(x)))


def test_integral_of_the_sedf_force_is_quads():
    """The SEDF force along the axis, ``g(x) = -x''(x, 0)`` (compiled, mu = 0.1, Delta = 2,
    beta = lam = 1: the force whose energies choose the saddles of the homoclinic end),
    integrated from 0 to points past the saddles: the rule and ``quad`` agree to 1e-13."""
    from scipy.integrate import quad

    from kbm.parameters.bound import bind
    from numerics.flow import compile_model

    cm = compile_model(bind("sedf", {"mu": 0.1, "beta": 1, "lam": 1, "Delta": 2}))

    def g(xs):
        return np.array([-float(cm.acc(0.0, x, 0.0)) for x in np.atleast_1d(xs)])

    for x in (-3.2, -0.7, 1.9, 4.6):
        ref = quad(lambda s: float(g(s)[0]), 0.0, x, epsabs=1e-14, epsrel=1e-13, limit=200)[0]
        assert abs(integral(g, 0.0, x) - ref) <= 1e-13 * max(1.0, abs(ref))
