"""The numeric forced KBM backend (kbm.backend.forced) against independent references.

- polynomial F: the exact rational engine (kbm.expansion.forced.derive_forced), a different
  algebra (exact two-angle Fourier series, no grid, no FFT);
- the slider seen from its stage, F = (1 - beta x^2)(x' + nu/k) - delta sin(k x + theta):
  first order against the Jacobi-Anger closed form (A&S 9.1.44-45, 9.1.27) and against
  direct quadrature of the averaging integrals; orders 2-3 against the exact engine on the
  Taylor polynomial of sin(k x + theta) (truncation 1e-13 at k a <= 1.5);
- the true periodic responses (shooting): the order-N amplitude error falls like mu**N;
- an invariance: a phase c of the washboard, sin(k x + theta + c), shifts the slow flow in
  phi by (q/p) c (theta -> theta + c with psi = (q/p) theta + phi).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.special
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from kbm.errors import ModelError, OrderError, ParameterError, UnsupportedTermError
from kbm.model.forced import ForcedOscillator
from kbm.expansion.forced import derive_forced
from kbm.backend.forced import forced_expansion, numeric_derive_forced
from kbm.model.forced import nu, phi, sigma, theta
from kbm.symbols import a, x, xdot

SLIDER = {"delta": 0.8, "k": 1.3, "beta": 1, "Omega": 1.5}


def _lam(expr):
    return sp.lambdify((a, phi, sigma), expr, "numpy")


# ----------------------------------------------------------------------------- polynomial F
@pytest.mark.parametrize("model, pars, order", [
    ("duffing-forced", {"zeta": 0.1, "alpha": 1, "h": 1}, 3),
    ("vdp-forced", {"h": 0.5}, 3),
    ("parametric", {"zeta": 0.1, "alpha": 1, "h": 1}, 3),
    ("duffing-super", {"zeta": 0.1, "alpha": 1, "h": 1}, 3),
])
def test_polynomial_models_equal_the_exact_engine(model, pars, order):
    """Same slow flow as the exact rational engine, every order, every sigma (Nayfeh & Mook
    4.1 for Duffing; the exact engine is checked against textbook results elsewhere)."""
    num = numeric_derive_forced(model, order, (0.5, 2), pars)
    ex = derive_forced(model, order, pars)
    rng = np.random.default_rng(1)
    av, ph, sg = rng.uniform(0.5, 2, 20), rng.uniform(0, 2 * np.pi, 20), rng.uniform(-2, 2, 20)
    for n in range(order):
        scale = 1 + np.max(np.abs(_lam(ex.A[n])(av, ph, sg)))
        assert np.max(np.abs(num.A[n](av, ph, sg) - _lam(ex.A[n])(av, ph, sg))) < 1e-12 * scale
        scale = 1 + np.max(np.abs(_lam(ex.B[n])(av, ph, sg)))
        assert np.max(np.abs(num.B[n](av, ph, sg) - _lam(ex.B[n])(av, ph, sg))) < 1e-12 * scale
        assert num.A_error[n] < 1e-12 and num.B_error[n] < 1e-12


# ----------------------------------------------------------------------------- the slider
@pytest.fixture(scope="module")
def slider3():
    return numeric_derive_forced("slider", 3, (0.5, 3), SLIDER)


def test_slider_first_order_is_the_jacobi_anger_closed_form(slider3):
    """A_1 = a/2 (1 - beta a^2/4) + delta J_1(k a) cos(phi)/(omega0 k a),
    B_1 = -delta J_1'(k a) sin(phi)/(omega0 a): the resonant harmonics of
    sin(k a cos psi + psi - phi) by Jacobi-Anger (A&S 9.1.44-45) with J_0 + J_2 = 2 J_1/z and
    J_0 - J_2 = 2 J_1' (A&S 9.1.27)."""
    d, k, b, w0 = SLIDER["delta"], SLIDER["k"], SLIDER["beta"], SLIDER["Omega"]
    av = np.linspace(0.55, 2.95, 9)
    ph = np.linspace(0, 6, 9)
    A1 = av / 2 * (1 - b * av**2 / 4) + d * scipy.special.jv(1, k * av) * np.cos(ph) / (w0 * k * av)
    B1 = -d * scipy.special.jvp(1, k * av) * np.sin(ph) / (w0 * av)
    assert np.max(np.abs(slider3.A[0](av, ph, 0.3) - A1)) < 1e-13
    assert np.max(np.abs(slider3.B[0](av, ph, 0.3) - B1)) < 1e-13


def test_slider_first_order_by_quadrature(slider3):
    """First-order averaging as integrals over the unperturbed orbit at fixed phi
    (Bogoliubov & Mitropolsky ch. 3): A_1 = -1/(2 pi omega0) int F sin(psi),
    B_1 = -1/(2 pi omega0 a) int F cos(psi), theta = psi - phi."""
    d, k, b, w0 = SLIDER["delta"], SLIDER["k"], SLIDER["beta"], SLIDER["Omega"]
    v = w0 / k  # nu/k at exact resonance

    def F(psi, av, ph):
        xv, vv = av * np.cos(psi), -w0 * av * np.sin(psi)
        return (1 - b * xv**2) * (vv + v) - d * np.sin(k * xv + psi - ph)

    psi = 2 * math.pi * np.arange(4096) / 4096  # trapezoid rule: exact for periodic F
    for av, ph in [(0.7, 0.4), (1.9, 2.8), (2.6, 5.1)]:
        f = F(psi, av, ph)
        iA, iB = np.mean(f * np.sin(psi)), np.mean(f * np.cos(psi))
        assert abs(slider3.A[0](av, ph, 0.0) + iA / w0) < 1e-12
        assert abs(slider3.B[0](av, ph, 0.0) + iB / (w0 * av)) < 1e-12


def _taylor_slider(degree: int) -> ForcedOscillator:
    """The slider (k = 1, beta = 1, delta = 4/5) with sin(k x), cos(k x) replaced by their
    Taylor polynomials: a model for the exact engine."""
    z = sp.Symbol("z")
    s_ = sp.series(sp.sin(z), z, 0, degree + 1).removeO()
    c_ = sp.series(sp.cos(z), z, 0, degree + 1).removeO()
    F = (1 - x**2) * (xdot + nu) - sp.Rational(4, 5) * (s_.subs(z, x) * sp.cos(theta)
                                                       + c_.subs(z, x) * sp.sin(theta))
    return ForcedOscillator("taylor-slider", F)


@pytest.mark.parametrize("order", [2, pytest.param(3, marks=pytest.mark.slow)])
def test_slider_higher_orders_equal_the_exact_engine_on_the_taylor_polynomial(order):
    """Orders 2 and 3, sigma-dependence included (sigma enters through D_1 and through
    the stage velocity nu/k = (omega0 + mu sigma)/k): the exact engine on the degree-17
    Taylor polynomial of sin(x + theta) (its remainder is below 1e-13 for |x| <= 1.5)."""
    ex = derive_forced(_taylor_slider(17), order)
    num = numeric_derive_forced("slider", order, (0.5, 1.5), {"delta": "0.8", "k": 1, "beta": 1})
    rng = np.random.default_rng(7)
    av, ph, sg = rng.uniform(0.5, 1.5, 12), rng.uniform(0, 2 * np.pi, 12), rng.uniform(-2, 2, 12)
    for n in range(order):
        assert np.max(np.abs(num.A[n](av, ph, sg) - _lam(ex.A[n])(av, ph, sg))) < 1e-12
        assert np.max(np.abs(num.B[n](av, ph, sg) - _lam(ex.B[n])(av, ph, sg))) < 1e-12


@settings(max_examples=8, deadline=None)
@given(c=st.floats(-3.0, 3.0), av=st.floats(0.6, 2.4), ph=st.floats(0.0, 6.28))
def test_washboard_phase_shifts_the_slow_flow(c, av, ph):
    """sin(k x + theta + c) is the slider with theta -> theta + c: its slow flow is the
    slider's at phi - c (q/p = 1), at every order."""
    base = _SHIFT_BASE
    model = ForcedOscillator(
        "shifted", (1 - x**2) * (xdot + nu) - sp.Rational(4, 5) * sp.sin(x + theta + c))
    shifted = numeric_derive_forced(model, 2, (0.5, 2.5))
    for n in range(2):
        assert abs(shifted.A[n](av, ph, 0.4) - base.A[n](av, ph - c, 0.4)) < 1e-11
        assert abs(shifted.B[n](av, ph, 0.4) - base.B[n](av, ph - c, 0.4)) < 1e-11


_SHIFT_BASE = numeric_derive_forced(
    ForcedOscillator("base", (1 - x**2) * (xdot + nu) - sp.Rational(4, 5) * sp.sin(x + theta)),
    2, (0.5, 2.5))


def test_slider_error_against_shooting_falls_like_mu_to_the_order():
    """The order-N amplitude of the locked slider differs from the true periodic response
    (shooting, Floquet) by O(mu**N): fitted slopes near 1, 2, 3."""
    from numerics.comparison.response_convergence import amplitude_study

    t = amplitude_study("slider", {"delta": 0.5, "k": 1, "beta": 1}, 0.1, [0.01, 0.02, 0.04],
                        (1, 2, 3), amplitudes=(0.5, 3))
    slopes = t.slopes
    for n in (1, 2, 3):
        assert abs(slopes[n] - n) < 0.25, slopes
    assert all(e3 < e2 < e1 for e1, e2, e3 in zip(t.errors[1], t.errors[2], t.errors[3]))


# ----------------------------------------------------------------------------- bad input
def test_bad_input_is_refused_with_the_reason():
    with pytest.raises(UnsupportedTermError, match="numeric forced backend"):
        derive_forced("slider", 1)
    with pytest.raises(ParameterError, match="a_range"):
        forced_expansion("slider", 1, SLIDER)
    with pytest.raises(ParameterError, match="missing: delta"):
        numeric_derive_forced("slider", 1, (0.5, 2), {"k": 1})
    with pytest.raises(ParameterError, match="a-range must lie in a > 0"):
        numeric_derive_forced("slider", 1, (0, 2), SLIDER)
    with pytest.raises(OrderError, match="limit"):
        numeric_derive_forced("slider", 99, (0.5, 2), SLIDER)
    with pytest.raises(ModelError, match="hard forcing"):
        numeric_derive_forced("duffing-super-hard", 1, (0.5, 2), {"zeta": 0.1, "alpha": 1,
                                                                  "K": 1})
    with pytest.raises(UnsupportedTermError, match="tanh"):
        ForcedOscillator("coulomb", "-sign(xdot) + h*cos(theta)")
    r = numeric_derive_forced("slider", 1, (0.5, 2), SLIDER)
    with pytest.raises(ParameterError, match="k = 2 differs"):
        r.slow_flow({"mu": 0.1, "k": 2})
    with pytest.raises(ParameterError, match="pole"):
        numeric_derive_forced(ForcedOscillator("pole", "1/(x - 1) + cos(theta)"), 1, (0.5, 2))


def test_expansion_reports_its_resolution_and_errors(slider3):
    P, M, N = slider3.resolution
    assert P >= 17 and M >= 16 and N >= 8
    assert all(e < 1e-9 for e in slider3.A_error + slider3.B_error)
    js = slider3.to_json([1.0, 2.0])
    assert set(js["A"]) == {"1", "2", "3"} and js["method"] == "numeric"


def test_command_line_slider(tmp_path):
    """kbm response on a smooth F: the JSON contract of the issue, and one-line refusals."""
    import json
    import subprocess
    import sys

    base = [sys.executable, "-m", "numerics.cli", "response", "slider", "--param", "mu=0.05",
            "--param", "delta=1", "--param", "k=1"]
    out = subprocess.run(base + ["--vary", "sigma=-0.3:0.3:40", "--order", "2", "--a-range",
                                 "0.5:3", "--no-numeric", "--json"],
                         capture_output=True, text=True, check=True)
    js = json.loads(out.stdout)
    assert js["order"] == 2 and js["analytic"] and len(js["folds"]) == 4
    assert {"sigma", "amplitude", "stable"} <= set(js["analytic"][0])
    assert all(0.5 <= p["amplitude"] <= 3 for p in js["analytic"])
    bad = subprocess.run(base + ["--nu", "0.5"], capture_output=True, text=True)
    assert bad.returncode != 0 and "--resonance" in bad.stderr
    assert len(bad.stderr.strip().splitlines()) == 1
    bad = subprocess.run(base + ["--detuning", "0", "--a-range", "0:3"], capture_output=True,
                         text=True)
    assert bad.returncode != 0 and "a > 0" in bad.stderr
