"""Second-order stochastic averaging (kbm.noise.stochastic_order2; issue 36, second-order part).

Independent references:

- linear damping with a quartic potential, ``x'' + x = mu (-x' - x^3) + sqrt(2 D) xi``:
  the stationary density is Boltzmann's ``exp(-(x'^2/2 + x^2/2 + mu x^4/4)/kT)`` with
  ``kT = D/mu`` (Risken, *The Fokker-Planck Equation*, sec. 10.1), ``<x^2>`` by scipy's
  quadrature.  At fixed ``kT`` the first-order error must fall like ``mu`` and the
  second-order one like ``mu^3`` (fitted slopes);
- linear damping alone: the Gaussian density is exactly radial, so every correction
  vanishes;
- van der Pol: ``F(x, -x') = -F(x, x')`` makes the odd corrections vanish (``q_1 = 0``);
  at mu = 0.3, D = 0.15 against a long fixed-seed simulation at a small step (slow).
"""

from __future__ import annotations

import json
import math
import subprocess
import sys

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import quad

from kbm.errors import ModelError, ParameterError
from kbm.model.builtins import custom_model
from kbm.noise.stochastic import stochastic_average
from kbm.noise.stochastic_order2 import KAPPA, stochastic_average_order2
from kbm.symbols import a

QUARTIC = custom_model("-xdot - x**3", name="quartic")


def _boltzmann_x2(m: float, kT: float) -> float:
    def w(x):
        return math.exp(-(x * x / 2 + m * x**4 / 4) / kT)

    opts = dict(epsabs=0, epsrel=1e-13, limit=200)
    return quad(lambda x: x * x * w(x), -30, 30, **opts)[0] / quad(w, -30, 30, **opts)[0]


def _slope(mus, errs) -> float:
    return float(np.polyfit(np.log(mus), np.log(np.abs(errs)), 1)[0])


def test_quartic_boltzmann_errors_fall_like_mu_and_mu_cubed():
    kT = 0.5
    so = stochastic_average_order2(QUARTIC)
    first = stochastic_average(QUARTIC)
    mus = [0.01, 0.02, 0.04]
    e1, e2, ex = [], [], []
    for m in mus:
        vals = {"mu": m, "D": kT * m}
        x2 = _boltzmann_x2(m, kT)
        a2 = x2 + kT  # <x'^2> = kT exactly
        e1.append(first.moment(2, vals) / a2 - 1)
        e2.append(so.moment(2, vals) / a2 - 1)
        ex.append(so.x2(vals) / x2 - 1)
    s1, s2, sx = _slope(mus, e1), _slope(mus, e2), _slope(mus, ex)
    assert abs(s1 - 1) < 0.15, (s1, e1)
    assert abs(s2 - 3) < 0.3 and abs(sx - 3) < 0.3, (s2, sx, e2, ex)
    assert all(abs(b) < 0.06 * abs(c) for b, c in zip(e2, e1))


def test_linear_damping_has_no_correction():
    so = stochastic_average_order2("linear_damping")
    assert so.q == (0, 0) and so.h2 == (0, 0)
    vals = {"mu": 0.2, "D": 0.1, "zeta": 0.5}
    # <a^2> = D/(mu zeta omega0^2) exactly (the Gaussian; Risken sec. 10.1)
    assert so.moment(2, vals) == pytest.approx(0.1 / (0.2 * 0.5), rel=1e-12)
    assert so.x2(vals) == pytest.approx(0.1 / (0.2 * 0.5) / 2, rel=1e-12)


def test_vdp_odd_orders_vanish_and_density_normalised():
    so = stochastic_average_order2("vdp")
    assert so.q[0] == 0 and so.h2[0] == 0
    assert so.q[1] != 0 and sp.Poly(so.q[1], a).degree() == 12
    assert sp.expand(so.q[1]).subs(a, 0) == 0  # smooth at the origin of the phase plane
    grid = np.linspace(0, 8, 8001)
    dens = so.density(grid, {"mu": 0.3, "D": 0.15})
    assert np.trapezoid(dens, grid) == pytest.approx(1, abs=1e-8)
    assert np.trapezoid(grid**2 * dens, grid) == pytest.approx(
        so.moment(2, {"mu": 0.3, "D": 0.15}), rel=1e-8)
    assert KAPPA in so.q[1].free_symbols


def test_bad_input():
    with pytest.raises(ModelError, match="polynomial"):
        stochastic_average_order2("cdc", {"Omega": 1, "delta": 1, "k": 1})
    with pytest.raises(ParameterError, match="mu"):
        stochastic_average_order2("vdp").moment(2, {"mu": -0.1, "D": 0.1})


@pytest.mark.slow
def test_vdp_against_simulation_slopes():
    """vdp at D/mu = 0.5 against 3000-trajectory simulations at a small step (weak order 2:
    bias ~2e-4 at mu = 0.3, dt = 0.02, and ~1e-4 at mu = 0.5, dt = 0.01): at mu = 0.3 the
    order-2 <a^2> within 0.5 % (order 1 off by more than 1.5 %); between mu = 0.3 and 0.5
    the order-2 error grows at least one power of mu faster than the order-1 error."""
    from numerics.noise.ensemble import stationary_ensemble

    e1, e2 = [], []
    for m, dt in ((0.3, 0.02), (0.5, 0.01)):
        ens = stationary_ensemble("vdp", {"mu": m}, m / 2, trajectories=3000,
                                  t_end=round(400 / m / dt) * dt,
                                  burn_in=round(20 / m / dt) * dt, dt=dt, seed=2026)
        truth = ens.a2.value
        assert ens.a2.stderr < 1e-3 * truth
        vals = {"mu": m, "D": m / 2}
        e1.append(stochastic_average("vdp").moment(2, vals) / truth - 1)
        e2.append(stochastic_average_order2("vdp").moment(2, vals) / truth - 1)
    assert abs(e2[0]) < 0.005 and abs(e1[0]) > 0.015, (e1, e2)
    s1, s2 = _slope([0.3, 0.5], e1), _slope([0.3, 0.5], e2)
    assert s2 > s1 + 1, (s1, s2, e1, e2)


def test_cli_order_two():
    args = [sys.executable, "-m", "numerics.cli", "noise", "vdp", "-p", "mu=0.3", "-p",
            "D=0.15", "--trajectories", "8", "--t-end", "40", "--workers", "1", "--json"]
    one = json.loads(subprocess.run(args, capture_output=True, text=True, check=True).stdout)
    two = json.loads(subprocess.run(args + ["--order", "2"], capture_output=True, text=True,
                                    check=True).stdout)
    assert one["averaged_order"] == 1 and two["averaged_order"] == 2
    vals = {"mu": 0.3, "D": 0.15}
    assert two["moments"]["a2"]["averaged"] == stochastic_average_order2("vdp").moment(2, vals)
    assert one["moments"]["a2"]["averaged"] == pytest.approx(
        stochastic_average("vdp").moment(2, vals), rel=1e-12)
    assert two["moments"]["a2"]["simulated"] == one["moments"]["a2"]["simulated"]
    assert set(two) == set(one)
