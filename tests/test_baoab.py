"""BAOAB and the measured default step of numerics.noise (issue 36, findings 2 and 3).

Independent references:

- BAOAB samples the configurational Boltzmann density of a harmonic potential exactly at
  any stable step (Leimkuhler & Matthews, Appl. Math. Res. Express 2013, 34, sec. 4): the
  stationary covariance of its linear map (the discrete Lyapunov equation, scipy) gives
  ``<x^2> = kT`` to rounding, and the compiled kernel agrees within 3 standard errors at a
  step where Kloeden-Platen's own covariance is visibly off;
- the toolkit's BAOAB against a hand-written BAOAB step in numpy on the same increments
  (the same states to 1e-12);
- van der Pol at mu = 0.3 and 0.5 (slow): a default ``kbm noise`` run against a
  Kloeden-Platen ensemble at a ten times smaller step.
"""

from __future__ import annotations

import json
import math
import subprocess
import sys

import numpy as np
import pytest
from scipy.linalg import solve_discrete_lyapunov

from kbm.errors import ParameterError
from numerics.noise import langevin_system
from numerics.noise.ensemble import stationary_ensemble
from numerics.noise.langevin import natural_step
from numerics.noise._pilot import measured_step
from numerics.noise.seeds import trajectory_states


def _baoab_map(h: float, gamma: float, w: float = 1.0):
    """BAOAB on x'' = -w^2 x - gamma x' + sigma xi as (x, v) -> M (x, v) + c dW-noise."""
    B = np.array([[1.0, 0.0], [-0.5 * h * w * w, 1.0]])
    A = np.array([[1.0, 0.5 * h], [0.0, 1.0]])
    e = math.exp(-gamma * h)
    O = np.array([[1.0, 0.0], [0.0, e]])
    M = B @ A @ O @ A @ B
    noise = B @ A @ np.array([0.0, math.sqrt((1 - e * e) / (2 * gamma))])
    return M, noise


@pytest.mark.parametrize("h", [0.1, 0.5, 1.2])
def test_baoab_linear_map_exact_configuration(h):
    gamma, kT = 1.0, 1.0
    M, c = _baoab_map(h, gamma)
    # sdw = sigma dW has variance 2 gamma kT h per step
    cov = solve_discrete_lyapunov(M, np.outer(c, c) * 2 * gamma * kT)
    assert cov[0, 0] == pytest.approx(kT, rel=1e-12)


def test_baoab_kernel_samples_the_harmonic_boltzmann_density():
    """linear_damping, gamma = 2 mu zeta = 1, D = 1 (kT = 1) at h = 0.5: BAOAB's <x^2> = 1
    within 3 standard errors; Kloeden-Platen's own stationary <x^2> (its linear map) is
    more than 5 standard errors away, and the kernel is weak order 2 there too."""
    h = 0.5
    ens = stationary_ensemble("linear_damping", {"mu": 1, "zeta": 0.5}, 1.0, trajectories=64,
                              t_end=4000.0, burn_in=20.0, dt=h, seed=3, scheme="baoab",
                              workers=1)
    assert abs(ens.x2.value - 1.0) < 3 * ens.x2.stderr
    A = np.array([[0.0, 1.0], [-1.0, -1.0]])
    eye = np.eye(2)
    Mkp = eye + h / 2 * (A + A @ (eye + A * h))
    ckp = h / 2 * A @ np.array([0.0, 1.0]) + np.array([0.0, 1.0])
    kp = solve_discrete_lyapunov(Mkp, np.outer(ckp, ckp) * 2 * h)[0, 0]
    assert abs(kp - 1.0) > 5 * ens.x2.stderr


def test_baoab_kernel_is_the_textbook_step():
    """One trajectory of the compiled BAOAB against B-A-O-A-B written out in numpy on the
    same three-point increments (van der Pol: gamma(x) = -mu (1 - x^2) at the midpoint)."""
    mu_, D, h, n = 0.3, 0.15, 0.05, 200
    s = langevin_system("vdp", {"mu": mu_}, D, "baoab")
    st = trajectory_states(9, 0, 1)
    got = s.final_states([[1.0, 0.0]], n * h, h, seed=9)[0]
    state = st[0].copy()
    sig, r3 = math.sqrt(2 * D), math.sqrt(3 * h)
    x, v = 1.0, 0.0
    for _ in range(n):
        dw = s.kernels._increment(state, r3)
        v += 0.5 * h * (-x)
        x += 0.5 * h * v
        g = -mu_ * (1 - x * x)
        e = math.exp(-g * h)
        v = e * v + math.sqrt((1 - e * e) / (2 * g * h)) * sig * dw
        x += 0.5 * h * v
        v += 0.5 * h * (-x)
    assert got == pytest.approx([x, v], abs=1e-12)


def test_scheme_choice_and_refusal():
    assert langevin_system("vdp", {"mu": 0.1}, 0.05, "auto").scheme == "baoab"
    assert langevin_system("rayleigh", {"mu": 0.1}, 0.05, "auto").scheme == "kp"
    with pytest.raises(ParameterError, match="affine"):
        langevin_system("rayleigh", {"mu": 0.1}, 0.05, "baoab")
    with pytest.raises(ParameterError, match="scheme"):
        langevin_system("vdp", {"mu": 0.1}, 0.05, "rk4")


def test_measured_step_shrinks_on_a_resolved_bias():
    """Issue 36 finding 2: Kloeden-Platen at the heating-rule step of vdp, mu = 0.3 is
    biased by about -0.6 %; the pilot resolves it and halves the step.  BAOAB from half
    that step (the same force evaluations) is accepted."""
    kp = langevin_system("vdp", {"mu": 0.3}, 0.15, "kp")
    h0 = natural_step(kp, per_period=50)
    h, info = measured_step(kp, h0)
    assert h < h0
    assert h == pytest.approx(info["h"])
    ba = langevin_system("vdp", {"mu": 0.3}, 0.15, "baoab")
    hb, info_b = measured_step(ba, h0)
    assert hb == pytest.approx(h0 / 2) and info_b["accepted"]
    assert abs(info_b["bias_a2"]) < 1e-3


@pytest.mark.slow
@pytest.mark.parametrize("mu", [0.3, 0.5])
def test_default_run_unbiased_vdp(mu):
    args = [sys.executable, "-m", "numerics.cli", "noise", "vdp", "-p", f"mu={mu}", "-p",
            f"D={mu / 2}", "--trajectories", "1000", "--json"]
    rep = json.loads(subprocess.run(args, capture_output=True, text=True, check=True).stdout)
    dt = 0.01
    ref = stationary_ensemble("vdp", {"mu": mu}, mu / 2, trajectories=2000,
                              t_end=round(400 / mu / dt) * dt, burn_in=round(20 / mu / dt) * dt,
                              dt=dt, seed=77, scheme="kp")
    m = rep["moments"]["a2"]
    z = (m["simulated"] - ref.a2.value) / math.hypot(m["stderr"], ref.a2.stderr)
    assert abs(z) < 3, (m, ref.a2)
    assert rep["scheme"] == "baoab"
