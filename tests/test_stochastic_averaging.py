"""First-order stochastic averaging of the amplitude (kbm.noise.stochastic; issue 22, part 1).

Independent references:

- the drift's deterministic part against a direct sympy quadrature over the phase of
  ``-<F(a cos psi, -a w0 sin psi) sin psi>/w0`` (Roberts & Spanos 1986, eq. 19), not the
  Fourier algebra of kbm;
- linear damping: Rayleigh's density, whose ``<a^2> = D/(mu zeta)`` must equal
  ``<x^2> + <x'^2>`` of the exact stationary covariance of the linear SDE (the continuous
  Lyapunov equation, scipy);
- van der Pol: ``ln P(a) = ln a + (mu/D)(a^2/2 - a^4/16)`` (Stratonovich, *Topics in the
  Theory of Random Noise* vol. 2, ch. 9), and ``<a^2>`` by scipy's quadrature of that
  closed form against kbm's mpmath quadrature;
- invariants (hypothesis): a conservative ``F(x)`` leaves only the Ito term ``D/(2 w0^2
  a)`` in the drift, at any coefficients; numpy = mpmath = sympy evaluation.
"""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings, strategies as st
from scipy.integrate import quad
from scipy.linalg import solve_continuous_lyapunov

from kbm.errors import KBMError, ModelError, NonAutonomousError, ParameterError
from kbm.model.builtins import custom_model, get_model
from kbm.noise.stochastic import NOISE, stochastic_average
from kbm.symbols import a, mu, x, xdot

psi = sp.Symbol("psi")


def _direct_A1(F, w0=1):
    """-<F sin psi>/w0 by sympy's definite integral over one period."""
    e = F.subs({x: a * sp.cos(psi), xdot: -a * w0 * sp.sin(psi)}) * sp.sin(psi)
    return sp.expand(-sp.integrate(sp.expand(e), (psi, 0, 2 * sp.pi)) / (2 * sp.pi * w0))


@pytest.mark.parametrize("name", ["vdp", "rayleigh", "linear_damping", "duffing"])
def test_drift_is_kbm_first_order_plus_ito_term(name):
    m = get_model(name)
    stoch = stochastic_average(m)
    expect = mu * _direct_A1(m.F) + NOISE / (2 * a)
    assert sp.simplify(stoch.drift_a - expect) == 0
    assert stoch.diffusion_a == NOISE
    assert sp.simplify(stoch.diffusion_phase - NOISE / a**2) == 0


@settings(max_examples=25, deadline=None)
@given(st.lists(st.integers(-5, 5), min_size=1, max_size=4))
def test_conservative_force_only_ito_drift(coeffs):
    """F(x) (no x'): mu A_1 = 0 at any coefficients, so the drift is D/(2 a) alone and no
    stationary density exists (the noise heats without bound)."""
    F = sum(c * x**(k + 1) for k, c in enumerate(coeffs))
    if F == 0:
        return
    stoch = stochastic_average(custom_model(F))
    assert sp.simplify(stoch.drift_a - NOISE / (2 * a)) == 0
    assert stoch.log_density is None and "conservative" in stoch.reason


@settings(max_examples=20, deadline=None)
@given(st.lists(st.integers(-4, 4), min_size=2, max_size=4), st.integers(1, 3))
def test_polynomial_damping_against_direct_quadrature(coeffs, w0):
    """F = sum c_k x^k x' (a polynomial damping): the averaged drift against direct
    quadrature, with omega0 != 1."""
    F = sum(c * x**k for k, c in enumerate(coeffs)) * xdot
    if F == 0:
        return
    stoch = stochastic_average(custom_model(F, omega0=w0))
    expect = mu * _direct_A1(F, w0) + NOISE / (2 * w0**2 * a)
    assert sp.simplify(stoch.drift_a - expect) == 0


def test_linear_damping_exact_second_moment():
    """x'' + 2 mu zeta x' + x = sqrt(2D) xi: <a^2> = D/(mu zeta) = <x^2> + <x'^2> of the
    exact stationary covariance (Lyapunov equation): averaging is exact here."""
    vals = {"mu": 0.1, "zeta": 0.5, "D": 0.02}
    A = np.array([[0.0, 1.0], [-1.0, -2 * vals["mu"] * vals["zeta"]]])
    Q = np.array([[0.0, 0.0], [0.0, 2 * vals["D"]]])
    S = solve_continuous_lyapunov(A, -Q)
    got = stochastic_average("linear_damping").moment(2, vals)
    assert got == pytest.approx(S[0, 0] + S[1, 1], rel=1e-12)


def test_van_der_pol_density_textbook():
    stoch = stochastic_average("vdp")
    D = NOISE
    book = sp.log(a) + mu / D * (a**2 / 2 - a**4 / 16)
    assert sp.simplify(stoch.log_density - book) == 0
    m, Dv = 0.05, 0.01

    def w(z, k):
        return z**k * z * math.exp(m / Dv * (z**2 / 2 - z**4 / 16) - 5.0)

    ref = quad(lambda z: w(z, 2), 0, 10, limit=200)[0] / quad(lambda z: w(z, 0), 0, 10,
                                                                limit=200)[0]
    assert stoch.moment(2, {"mu": m, "D": Dv}) == pytest.approx(ref, rel=1e-9)
    grid = np.linspace(0.05, 4, 40)
    dens = stoch.density(grid, {"mu": m, "D": Dv})
    Z = quad(lambda z: w(z, 0), 0, 10, limit=200)[0]
    np.testing.assert_allclose(dens, [w(z, 0) / Z for z in grid], rtol=1e-9)


@settings(max_examples=15, deadline=None)
@given(st.floats(0.2, 3.0), st.floats(0.01, 1.0), st.floats(0.001, 0.5), st.floats(0.5, 2))
def test_numpy_equals_mpmath_equals_sympy(amp, m, Dv, beta):
    stoch = stochastic_average("sedf", {"Omega": 1})
    names = stoch.parameters
    vals = {"beta": beta, "delta": 3.0, "k": 2 * math.pi}
    f_np = stoch.numpy_functions()[0]
    got = f_np(amp, m, Dv, *[vals[n] for n in names])
    subs = {a: amp, mu: m, NOISE: Dv, **{sp.Symbol(n): vals[n] for n in names}}
    exact = float(stoch.drift_a.subs(subs))
    mp = float(sp.lambdify([a, mu, NOISE, *[sp.Symbol(n) for n in names]], stoch.drift_a,
                           "mpmath")(amp, m, Dv, *[vals[n] for n in names]))
    assert got == pytest.approx(exact, rel=1e-12) and mp == pytest.approx(exact, rel=1e-12)


def test_latex_same_bytes_under_any_hash_seed():
    code = ("from kbm.noise.stochastic import stochastic_average as s;"
            "print(s('sedf').latex()); print(s('vdp').latex())")
    outs = {subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                           env={"PYTHONHASHSEED": str(seed), "PATH": "/usr/bin:/bin"},
                           check=True).stdout for seed in (0, 12345)}
    assert len(outs) == 1


@pytest.mark.parametrize("D, message", [(-0.1, "D = -0.1: .* D > 0"), (float("nan"), "finite"),
                                        ("abc", "D = abc: give")])
def test_bad_noise(D, message):
    with pytest.raises(ParameterError, match=message):
        stochastic_average("vdp").moment(2, {"mu": 0.1, "D": D})


def test_refusals():
    with pytest.raises(NonAutonomousError):
        stochastic_average(get_model("cdc", {"v": 0.1}))
    with pytest.raises(ParameterError, match="named D"):
        stochastic_average(custom_model("-D*xdot"))
    with pytest.raises(ModelError, match="no stationary amplitude density"):
        stochastic_average("duffing").moment(2, {"mu": 0.1, "D": 0.01})
    assert issubclass(ModelError, KBMError)
