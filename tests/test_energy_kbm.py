"""Energy averaging against classical KBM where g is linear, and against h = 0.

For ``g = omega0**2 x`` the energy-angle averaging with the first-harmonic gauge
must reproduce the KBM normal form (``kbm.derive``, ``kbm.averaged_cycles``) at
every order: ``M_n(eps) = omega0**2 a A_n(a)``, ``eps = omega0**2 a**2/2``,
``Theta_n = B_n``.  For ``h = 0`` (conservative) every ``M_n`` vanishes and the
frequency is ``2 pi/T(E)``.
"""

import json

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings, strategies as st

import kbm
from kbm.model.conservative import split_conservative
from kbm.errors import OrderError
from numerics.energy import average, phase_portrait, predict_cycles


@pytest.mark.parametrize("name", ["vdp", "rayleigh"])
@pytest.mark.parametrize("mu", [0.05, 0.2, 0.5])
def test_linear_g_equals_kbm_cycles(name, mu):
    """Cycle amplitude (first harmonic), frequency and Floquet multiplier of the order-N
    energy averaging equal kbm.averaged_cycles at N = 1, 2, 3 (to 1e-9)."""
    r = kbm.derive(name, 3)
    (a,) = phase_portrait(split_conservative(name, {"mu": mu})).annuli
    av = average(a, mu, 3, (1.0, 3.0), n_energy=24, n_theta=64)
    assert av.error < 1e-8
    for N in (1, 2, 3):
        (c,) = kbm.averaged_cycles(r, {"mu": mu}, order=N)
        (eps,) = av.roots(N)
        A = np.sqrt(2 * eps)
        freq = av.frequency(eps, N)
        mult = np.exp(2 * np.pi / freq * av.rate(eps, N, derivative=1))
        xw = av.waveform(eps, N)
        a1 = 2 * abs(np.fft.rfft(xw)[1]) / len(xw)
        assert A == pytest.approx(c.amplitude, abs=1e-9)
        assert a1 == pytest.approx(c.amplitude, abs=1e-9)
        assert freq == pytest.approx(c.frequency, abs=1e-9)
        assert mult == pytest.approx(c.floquet_multiplier, abs=1e-9)


@pytest.mark.parametrize("name,omega0", [("vdp", 1.0), ("sedf", 1.7)])
def test_linear_g_rates_equal_kbm(name, omega0):
    """M_n(eps) = omega0^2 a A_n(a) and Theta_n(eps) = B_n(a) on the whole interval, n <= 3."""
    params = {"mu": 0.1} if name == "vdp" else {"mu": 0.1, "Delta": 0, "beta": 0.5,
                                                 "lam": 1, "Omega": omega0}
    model = kbm.get_model(name) if name == "vdp" else kbm.get_model(
        name, {"beta": 0.5, "delta": 0, "k": 1, "Omega": sp.Rational(17, 10)})
    r = kbm.derive(model, 3)
    (a,) = phase_portrait(split_conservative(name, params)).annuli
    av = average(a, 0.1, 3, (0.5, 4.0), n_energy=32, n_theta=64)
    eps = np.linspace(0.6, 3.9, 7)
    amp = np.sqrt(2 * eps) / omega0
    lo, hi = av.interval
    u = (2 * eps - lo - hi) / (hi - lo)
    for n in (1, 2, 3):
        An = sp.lambdify(kbm.a, r.A[n])(amp)
        Bn = sp.lambdify(kbm.a, r.B[n])(amp)
        Mn = np.polynomial.chebyshev.chebval(u, av.M[n])
        Tn = np.polynomial.chebyshev.chebval(u, av.Theta[n])
        assert np.allclose(Mn, omega0**2 * amp * An, atol=1e-9)
        assert np.allclose(Tn, Bn, atol=1e-9)


def test_predict_cycles_equals_kbm_first_order():
    """predict_cycles(order=1) for vdp: amplitude 2, frequency 1, multiplier exp(-2 pi mu)."""
    P = predict_cycles("vdp", {"mu": 0.2})
    (c,) = P.cycles
    (k,) = kbm.averaged_cycles(kbm.derive("vdp", 1), {"mu": 0.2})
    assert c.amplitude_first_harmonic == pytest.approx(k.amplitude, abs=1e-9)
    assert c.amplitude_max == pytest.approx(2.0, abs=1e-12)
    assert c.frequency == pytest.approx(k.frequency, abs=1e-12)
    assert c.floquet_multiplier == pytest.approx(k.floquet_multiplier, abs=1e-9)
    assert c.stable and c.annulus == "central well"
    js = json.dumps(P.to_json(), allow_nan=False)
    for key in ("amplitude_max", "amplitude_min", "amplitude_first_harmonic", "period",
                "frequency", "energy", "stable", "annulus"):
        assert key in json.loads(js)["cycles"][0]


#: w^2 > |delta| makes g' = w^2 + 3 c3 x^2 + delta cos x > 0: one well (as the test states);
#: several wells put the outer annulus's interval against a separatrix
_conservative_g = st.tuples(st.floats(0.7, 3.0), st.floats(0.0, 1.0), st.floats(-0.4, 0.4))


@settings(max_examples=8)
@given(_conservative_g)
def test_conservative_rates_vanish(coefs):
    """h = 0 (g = w^2 x + c3 x^3 + delta sin x, confining, one well): M_n = 0 at every order
    and the averaged frequency is 2 pi/T(E) (Theta_n = 0)."""
    w, c3, d = coefs
    model = kbm.custom_model(f"-{c3}*x**3 - {d}*sin(x)", omega0=sp.nsimplify(w))
    s = split_conservative(model, {"mu": 1})
    p = phase_portrait(s)
    assert len(p.annuli) == 1
    a = p.annuli[0]
    lo = a.energy_min + 0.5
    av = average(a, 0.1, 3, (lo, lo + 1.0), n_energy=16, n_theta=64)
    E = np.linspace(lo + 0.1, lo + 0.9, 5)
    for n in (1, 2, 3):
        assert np.max(np.abs(av.rate(E, n) - (av.rate(E, n - 1) if n > 1 else 0))) < 1e-12
    assert np.allclose(av.frequency(E), 2 * np.pi / a.period(E), rtol=1e-10)


def test_no_cycle_reasons():
    """Duffing (h = 0): no isolated cycle; linear damping: Gamma < 0 on every annulus."""
    P = predict_cycles("duffing", {"mu": 0.1}, order=2)
    assert P.cycles == () and "conservative" in P.reason
    P = predict_cycles("linear_damping", {"mu": 0.1, "zeta": 0.5})
    assert P.cycles == ()
    assert "no root of Gamma(E) found, Gamma < 0 wherever evaluated" in P.reason
    assert "searched" in P.reason
    assert json.loads(json.dumps(P.to_json(), allow_nan=False))["cycles"] == []
    with pytest.raises(OrderError):
        predict_cycles("vdp", {"mu": 0.1}, order=0)


@pytest.mark.parametrize("name", ["vdp", "rayleigh"])
@pytest.mark.parametrize("order", [2, 3])
def test_predict_cycles_kbm_convention(name, order):
    """predict_cycles(order=N, rate_order=N) is KBM order N for linear g: first-harmonic
    amplitude, frequency and multiplier equal kbm.averaged_cycles to 1e-9."""
    mu = 0.3
    (c,) = predict_cycles(name, {"mu": mu}, order=order, rate_order=order).cycles
    (k,) = kbm.averaged_cycles(kbm.derive(name, order), {"mu": mu})
    assert c.amplitude_first_harmonic == pytest.approx(k.amplitude, abs=1e-9)
    assert c.frequency == pytest.approx(k.frequency, abs=1e-9)
    assert c.floquet_multiplier == pytest.approx(k.floquet_multiplier, abs=1e-9)
