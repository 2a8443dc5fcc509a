"""Limit cycles of the full equation by shooting (issue 3), against independent references."""

from __future__ import annotations

import json
import math

import mpmath
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.integrate import solve_ivp

from kbm import NonAutonomousError
from numerics.cli import main
from numerics import ConvergenceError, NoCycleError, limit_cycle

# van der Pol, mu = 1: published period and maximum amplitude (e.g. Strogatz, Nonlinear
# Dynamics and Chaos, ex. 7.5; J. Grasman, Asymptotic Methods for Relaxation Oscillations,
# table 1.1: T = 6.66328685933, max x = 2.00861986087)
T_VDP1 = 6.66328685933
A_VDP1 = 2.00861986087


@pytest.fixture(scope="module")
def vdp1():
    return limit_cycle("vdp", {"mu": 1})


def test_vdp_mu1_published_values(vdp1):
    """van der Pol mu = 1: period 6.66328685933 and max amplitude 2.00861986087 (published),
    to the 11 digits given."""
    assert vdp1.success
    assert abs(vdp1.period - T_VDP1) < 1e-10
    assert abs(vdp1.amplitude_max - A_VDP1) < 1e-10


def test_vdp_mu1_high_precision_digit_by_digit(vdp1):
    """digits=25 agrees with an independent 34-digit run (other Taylor order and steps) to
    >= 22 digits, and the double-precision cycle agrees with both to >= 10 digits."""
    c25 = limit_cycle("vdp", {"mu": 1}, digits=25, guess=(vdp1.amplitude_max, vdp1.period))
    c34 = limit_cycle("vdp", {"mu": 1}, digits=34, guess=(vdp1.amplitude_max, vdp1.period))
    with mpmath.workdps(40):
        for key in ("period", "amplitude_max", "amplitude_first_harmonic"):
            a, b = c25.mp[key], c34.mp[key]
            assert abs(a - b) < mpmath.mpf(10)**-22 * abs(b), key
    assert abs(float(c34.mp["period"]) - vdp1.period) < 1e-10 * vdp1.period
    assert abs(float(c34.mp["amplitude_max"]) - vdp1.amplitude_max) < 1e-10
    assert abs(float(c34.mp["amplitude_first_harmonic"]) - vdp1.amplitude_first_harmonic) < 1e-10
    assert str(mpmath.nstr(c34.mp["period"], 12)).startswith("6.6632868593")


def _div_integral(c, beta=1.0):
    """-mu * oint (beta x^2 - 1) dt from the orbit samples (trapezoid rule, periodic:
    spectrally accurate), independent of the integrated variational equations."""
    mu = c.params["mu"]
    return -mu * np.mean(beta * c.x**2 - 1.0) * c.period


@pytest.mark.parametrize("mu", [0.1, 1.0, 3.0])
def test_liouville_formula(mu):
    """Liouville: the product of the Floquet multipliers equals exp(oint div f dt)
    = exp(-mu oint (x^2 - 1) dt), the latter computed from the orbit samples; the
    trivial multiplier is 1 to 1e-8."""
    c = limit_cycle("vdp", {"mu": mu})
    prod = (c.floquet_multipliers[0] * c.floquet_multipliers[1]).real
    ref = math.exp(_div_integral(c))
    assert abs(prod - ref) < 1e-8 * max(ref, 1e-12) + 1e-12
    assert abs(c.floquet_multipliers[0] - 1) < 1e-8
    assert c.stable


@settings(max_examples=8)
@given(mu=st.floats(0.05, 0.5), beta=st.floats(0.3, 1.0), Delta_rel=st.floats(0.0, 0.5))
def test_dissipation_vanishes_on_the_cycle(mu, beta, Delta_rel):
    """Paper eqs. 10-11: on a limit cycle Gamma = beta Gamma_+ - Gamma_- = 0; here
    |Gamma| < 1e-9 Gamma_- and the energy balance E(0) - E(T) - Gamma closes to ~1e-10."""
    c = limit_cycle("sedf", {"mu": mu, "beta": beta, "Delta": Delta_rel * mu, "lam": 1})
    d = c.dissipation
    assert abs(d.total) < 1e-9 * d.gamma_minus
    assert abs(d.plus_factor - beta) < 1e-15
    assert abs(beta * d.gamma_plus - d.gamma_minus - d.total) < 1e-12 * d.gamma_minus
    assert abs(c.energy_residual) < 1e-9


def test_shooting_agrees_with_long_transient():
    """Shooting and a long DOP853 transient (200 periods, maxima by event location) agree on
    period and maximum amplitude (Rayleigh, mu = 0.5)."""
    c = limit_cycle("rayleigh", {"mu": 0.5})
    mu = 0.5

    def f(t, y):
        return [y[1], -y[0] + mu * (1 - y[1]**2 / 3) * y[1]]

    def ev(t, y):
        return y[1]
    ev.direction = -1
    sol = solve_ivp(f, (0, 200 * 2 * math.pi), [1.0, 0.0], method="DOP853", rtol=1e-12,
                    atol=1e-12, events=ev)
    te, ye = sol.t_events[0], sol.y_events[0]
    assert abs((te[-1] - te[-11]) / 10 - c.period) < 1e-8
    assert abs(ye[-1][0] - c.amplitude_max) < 1e-8


def test_no_cycle_decay_cdc():
    """The undriven CDC (paper eq. 12) is damped: no cycle, the message gives the decay."""
    with pytest.raises(NoCycleError, match="decays to rest"):
        limit_cycle("cdc", {"mu": 0.2, "Delta": 0.1, "lam": 1})


def test_no_cycle_divergence_beta0():
    """SEDF with beta = 0 has pure negative damping: the amplitude grows without bound."""
    with pytest.raises(NoCycleError, match="grows without bound"):
        limit_cycle("sedf", {"mu": 0.2, "Delta": 0.05, "lam": 1, "beta": 0})


def test_newton_non_convergence_is_reported():
    """A bad guess with a tiny iteration budget: ConvergenceError with the residual history."""
    with pytest.raises(ConvergenceError, match="did not converge"):
        limit_cycle("vdp", {"mu": 1}, guess=(3.5, 5.0), max_iter=1)


def test_non_autonomous_is_refused():
    """A slider pulled at v != 0 has no limit cycle in this sense."""
    with pytest.raises(NonAutonomousError):
        limit_cycle("sedf", {"mu": 0.1, "Delta": 0.1, "lam": 1, "beta": 1, "v": 0.1})


def test_stiff_relaxation_oscillation():
    """van der Pol mu = 10 (relaxation oscillation; LSODA switches to BDF): period
    19.0784 (Grasman 1987, table 1.1: 19.07836957)."""
    c = limit_cycle("vdp", {"mu": 10}, rtol=1e-11)
    assert abs(c.period - 19.07836957) < 1e-6


def test_cli_cycle_json(capsys):
    """kbm cycle --json has the documented keys; --digits gives strings."""
    assert main(["cycle", "vdp", "--param", "mu=1", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    for key in ("period", "frequency", "amplitude_max", "amplitude_first_harmonic",
                "floquet_multipliers", "stable", "dissipation", "energy_residual",
                "iterations"):
        assert key in data
    assert set(data["dissipation"]) == {"total", "gamma_plus", "gamma_minus"}
    assert abs(data["period"] - T_VDP1) < 1e-10
    assert main(["cycle", "vdp", "--param", "mu=1", "--digits", "20", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert isinstance(data["period"], str) and data["period"].startswith("6.66328685932313")
    assert main(["cycle", "cdc", "--param", "mu=0.2", "--param", "Delta=0.1",
                 "--param", "lam=1"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "decays to rest" in err[0]


def test_rest_in_a_side_well_is_not_a_cycle():
    """SEDF with Delta = 3 (mu = 0.1, beta = 1) has a stable rest point in a side well of the
    potential (x = 1.8914, where Omega^2 x + Delta sin(2 pi x) = 0) next to its limit cycle:
    Newton from a start near it settles there and the answer is NoCycleError (not a 'cycle'
    of zero amplitude); the default search (classical KBM fails here) finds the cycle from
    the energy-balance prediction about the conservative orbit (issue 10: x_max ~ 2.0906,
    T ~ 8.142)."""
    p = {"mu": 0.1, "Delta": 3, "beta": 1, "lam": 1}
    with pytest.raises(NoCycleError, match="settles to rest at x = 1.891"):
        limit_cycle("sedf", p, guess=(1.9, 6.0))
    assert 1.89143 + 3 * math.sin(2 * math.pi * 1.89143) == pytest.approx(0, abs=1e-4)
    c = limit_cycle("sedf", p, x_start=1.0)
    assert c.success and "energy-balance" in c.message
    assert c.amplitude_max == pytest.approx(2.0906, abs=1e-4)
    assert c.period == pytest.approx(8.142, abs=1e-3)
    assert c.stable and c.energy_residual == pytest.approx(0, abs=1e-10)


def test_non_smooth_model_is_a_clear_error(capsys):
    """F with sign(x') (Coulomb friction) has no classical variational equations: a
    ModelError that names the smooth replacement, and one line with exit 2 on the CLI."""
    from kbm.errors import ModelError
    from kbm.model.builtins import custom_model

    with pytest.raises(ModelError, match="tanh"):
        limit_cycle(custom_model("-sign(xdot) + (1 - x**2)*xdot"), {"mu": 0.5})
    assert main(["cycle", "--rhs", "-Abs(xdot)*xdot + (1 - x**2)*xdot", "--param",
                 "mu=0.5"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "smooth" in err[0]
