"""Noise spectra about driven steady states (numerics.spectrum.driven, driven_sim; issue 37).

References: the damped linear oscillator's exact spectrum ``S(w) = (2 D/pi)/((omega0^2 -
w^2)^2 + (2 mu zeta w)^2)`` (one-sided, angular; e.g. Risken, *The Fokker-Planck Equation*,
sec. 10.1) with variance ``D/(2 mu zeta omega0^2)``; the first-order slow flow of the forced
Duffing oscillator (kbm.forced, Nayfeh & Mook sec. 4.1.1); Liouville's formula for the
Floquet multipliers; the simulated PSD within its standard errors.
"""

from __future__ import annotations

import math
from argparse import Namespace

import numpy as np
import pytest

from kbm.errors import ParameterError
from numerics.spectrum.driven_sim import noisy_system
from numerics.spectrum.driven import (averaged_flow, averaged_spectrum, floquet_spectrum,
                                      periodic_orbit, stable_states)
from numerics.spectrum.driven_sim import coherent_part, response_spectra, simulate_fluctuations

LINEAR = {"zeta": 0.5, "alpha": 0, "h": 1}


def _exact_linear(w, mu, zeta, D):
    return (2 * D / math.pi) / ((1 - w**2) ** 2 + (2 * mu * zeta * w) ** 2)


def _linear(mu, sigma=0.3, D=0.01):
    system = noisy_system("duffing-forced", {**LINEAR, "mu": mu, "sigma": sigma}, D)
    flow = averaged_flow(system)
    (state,) = stable_states(flow)
    return system, flow, state


def test_floquet_route_is_the_exact_linear_spectrum():
    """A linear forced oscillator: the Floquet route (periodic Lyapunov equation and the
    transfer over one period) gives the closed form and the variance D/(2 mu zeta)."""
    mu, zeta, D = 0.05, 0.5, 0.01
    system, flow, state = _linear(mu, D=D)
    orbit = periodic_orbit(flow, state)
    w = np.linspace(0.5, 1.5, 41)
    S, var = floquet_spectrum(system, orbit, w)
    np.testing.assert_allclose(S, _exact_linear(w, mu, zeta, D), rtol=1e-7)
    assert var == pytest.approx(D / (2 * mu * zeta), rel=1e-8)


def test_floquet_route_two_degrees_of_freedom():
    """A forced system of two modes (duffing-1-3 made linear and uncoupled: k = alpha = 0):
    the second mode's Floquet spectrum is its damped oscillator's closed form at omega0 = 3,
    and the averaged route is within O(mu) of it at the line."""
    mu, z2, D = 0.1, 0.5, 0.01
    w = np.linspace(2.8, 3.2, 9)
    (s,) = response_spectra("duffing-1-3", {"mu": mu, "zeta1": 0.5, "zeta2": z2, "alpha1": 0,
                                            "alpha2": 0, "k": 0, "h": 1}, D, [0.5], mode=1,
                            omega=w)
    exact = (2 * D / math.pi) / ((9 - w**2) ** 2 + (2 * mu * z2 * w) ** 2)
    np.testing.assert_allclose(s.floquet, exact, rtol=1e-6)
    np.testing.assert_allclose(s.averaged, exact, rtol=0.1)


def test_floquet_multipliers_obey_liouville():
    """det M = exp(int div f) = exp(-2 mu zeta T) for the damping -2 mu zeta x' (the cubic
    term has no divergence), on the nonlinear upper branch of the Duffing oscillator."""
    mu, zeta = 0.05, 0.5
    system = noisy_system("duffing-forced", {"mu": mu, "zeta": zeta, "alpha": 1, "h": 2,
                                             "sigma": 0.8}, 0.001)
    flow = averaged_flow(system)
    orbit = periodic_orbit(flow, stable_states(flow)[-1])
    assert np.prod(orbit.multipliers).real == pytest.approx(
        math.exp(-2 * mu * zeta * orbit.period), rel=1e-8)
    assert orbit.stable


@pytest.mark.parametrize("offsets", [np.array([-3.0, -1.0, 0.0, 1.0, 3.0])])
def test_averaged_route_is_first_order(offsets):
    """The averaged (rotating-frame Ornstein-Uhlenbeck) spectrum of the linear oscillator
    differs from the closed form by O(mu) near the line: halving mu halves the error."""
    errs = []
    for mu in (0.02, 0.01):
        _, flow, state = _linear(mu)
        w = 1 + mu * 0.5 * offsets
        err = averaged_spectrum(flow, state, w) / _exact_linear(w, mu, 0.5, 0.01) - 1
        errs.append(np.max(np.abs(err)))
        assert errs[-1] < 2 * mu
    assert errs[0] / errs[1] == pytest.approx(2.0, rel=0.05)


def test_averaged_states_are_the_kbm_fixed_points():
    """The Cartesian averaged flow's stable states are kbm.forced's first-order fixed points
    (amplitude and phase), both branches of the bistable Duffing."""
    from kbm.forced import derive_forced, get_forced_model
    from kbm.forced.steady import fixed_points

    p = {"mu": 0.1, "zeta": 0.25, "alpha": 1, "h": 1}
    sf = derive_forced(get_forced_model("duffing-forced"), 1).slow_flow(p)
    ref = [f for f in fixed_points(sf, 1.0) if f.stable]
    flow = averaged_flow(noisy_system("duffing-forced", {**p, "sigma": 1.0}, 0.01))
    ours = stable_states(flow)
    assert len(ours) == len(ref) == 2
    for st, f in zip(ours, ref):
        assert st.amplitudes()[0] == pytest.approx(f.amplitude, rel=1e-9)
        ph = math.atan2(st.U[1], st.U[0]) % (2 * math.pi)
        assert ph == pytest.approx(f.phase, abs=1e-8)
        np.testing.assert_allclose(sorted(st.eigenvalues, key=lambda z: z.imag),
                                   sorted(f.eigenvalues, key=lambda z: z.imag), atol=1e-7)


def test_sidebands_are_asymmetric_on_the_upper_branch():
    """Near the jump the averaged spectrum has two sidebands Omega +- Im(lambda) of unequal
    height (J is not normal), and the Floquet route shows the same two peaks."""
    system = noisy_system("duffing-forced", {"mu": 0.05, "zeta": 0.5, "alpha": 1, "h": 2,
                                             "sigma": 0.8}, 0.001)
    flow = averaged_flow(system)
    st = stable_states(flow)[-1]
    W = flow.Omega[0]
    lo, hi = (W + e.imag for e in st.eigenvalues)
    S = averaged_spectrum(flow, st, np.array([lo, hi]))
    assert abs(S[0] / S[1] - 1) > 0.3


def test_simulated_psd_matches_floquet_within_stderr():
    """Floquet route against the simulated PSD of the driven Duffing (upper branch) at a
    fixed seed: the bins' standardised differences have mean ~ 0 and rms ~ 1."""
    (sp,) = response_spectra("duffing-forced", {"mu": 0.2, "zeta": 0.5, "alpha": 1, "h": 2},
                             0.002, [0.8], simulate=True, trajectories=16, seed=4, workers=1,
                             duration=2100.0)
    z = (sp.floquet - sp.simulated) / sp.stderr
    assert abs(np.mean(z)) < 3 / math.sqrt(len(z)) + 0.25
    assert np.sqrt(np.mean(z**2)) < 1.6


@pytest.mark.slow
def test_simulated_psd_matches_floquet_note_parameters():
    """The note's Duffing (mu = 0.05, zeta = 0.5, h = 2, D = 0.001) at two detunings of the
    upper branch: Floquet within the simulated band, the averaged route off by O(mu)."""
    specs = response_spectra("duffing-forced", {"mu": 0.05, "zeta": 0.5, "alpha": 1, "h": 2},
                             0.001, [0.8, 1.1], simulate=True, trajectories=16, seed=0,
                             workers=1)
    for sp in specs:
        if sp.state.amplitudes()[0] < 1:
            continue
        z = (sp.floquet - sp.simulated) / sp.stderr
        assert abs(np.mean(z)) < 0.3 and np.sqrt(np.mean(z**2)) < 1.5


def test_coherent_part_recovers_a_periodic_shift():
    """A known line 0.3 cos(w t) - 0.1 sin(w t) under white noise: recovered within its
    stderr, and removed (the remainder has no mean profile)."""
    rng = np.random.default_rng(1)
    sp, periods, n = 8, 400, 24
    t = np.arange(sp * periods) * 2 * math.pi / sp
    dx = 0.3 * np.cos(t) - 0.1 * np.sin(t) + rng.standard_normal((n, t.size))
    rest, shift = coherent_part(dx, sp, 1)
    assert abs(shift["cos"] - 0.3) < 4 * shift["stderr"]
    assert abs(shift["sin"] + 0.1) < 4 * shift["stderr"]
    assert shift["stderr"] == pytest.approx(math.sqrt(2 * 2 / (sp * periods * n)), rel=0.2)
    np.testing.assert_allclose(rest.reshape(n, periods, sp).mean(axis=(0, 1)), 0, atol=1e-12)


def test_same_bytes_on_any_chunking_and_workers():
    """Trajectory i's record depends on (seed, i) only: the same rows from 20 and 24
    trajectories (other last chunks), and from one and two workers."""
    p = {**LINEAR, "mu": 0.2, "sigma": 0.3}
    kw = dict(dt=2 * math.pi / 1.06 / 64, burn_in_steps=64, samples=50, stride=4, seed=5)
    a = simulate_fluctuations("duffing-forced", p, 0.01, (0.5, 0.1), trajectories=20,
                              workers=1, **kw)
    b = simulate_fluctuations("duffing-forced", p, 0.01, (0.5, 0.1), trajectories=24,
                              workers=2, **kw)
    assert a.tobytes() == b[:20].tobytes()
    assert np.std(a) > 0


def _args(**kw):
    base = dict(model="duffing-forced", param=["mu=0.05", "zeta=0.5", "alpha=1", "h=2",
                                               "D=0.001"],
                vary=["sigma=0.8"], json=True, out=None, trajectories=16, duration=None,
                seed=0, workers=1, store=None, resume=False, order=1)
    base.update(kw)
    return Namespace(**base)


@pytest.mark.parametrize("change, words", [
    ({"param": ["mu=0.05", "zeta=0.5", "alpha=1", "h=2", "D=0"]}, "D > 0"),
    ({"param": ["mu=0.05", "zeta=0.5", "alpha=1", "h=2", "T=0"]}, "D > 0"),
    ({"param": ["mu=0.05", "zeta=0.5", "alpha=1", "h=2", "D=0.01", "beta=1"]},
     "unknown parameter 'beta'"),
    ({"duration": 500.0}, "too short for the resolution"),
    ({"model": "vdp-forced", "param": ["mu=0.1", "h=0.5", "D=0.01"],
      "vary": ["sigma=1.0"]}, "no stable steady state at sigma = 1"),
    ({"vary": ["h=0.1:0.2"]}, "vary the detuning sigma"),
])
def test_run_driven_bad_input(change, words):
    """Bad input: one line naming what to change (the command prints it and exits 2)."""
    from numerics.cli._spectrum_driven import run_driven

    with pytest.raises(ParameterError) as exc:
        run_driven(_args(**change))
    assert words in str(exc.value) and "\n" not in str(exc.value)


def test_run_driven_duration_message_names_the_resolution():
    from numerics.cli._spectrum_driven import run_driven

    with pytest.raises(ParameterError, match=r"would give [0-9.]+ .*--duration >= "):
        run_driven(_args(duration=500.0))


@pytest.mark.parametrize("argv, words", [
    (["duffing-forced", "-p", "mu=0.05", "-p", "zeta=0.5", "-p", "alpha=1", "-p", "h=2",
      "-p", "D=0", "--vary", "sigma=0.8"], "needs noise"),
    (["duffing-forced", "-p", "mu=0.05", "-p", "zeta=0.5", "-p", "alpha=1", "-p", "h=2",
      "-p", "D=0.001", "--vary", "sigma=0.8", "--duration", "500"], "it would give 0.05"),
    (["coupled-vdp", "-p", "mu=0.1", "-p", "c=0.3", "-p", "T=-1", "-p", "sigma=0.2"],
     "negative"),
])
def test_kbm_spectrum_exits_2_with_one_line(argv, words, capsys):
    """The command line: exit status 2 and a one-line message on stderr."""
    from numerics.cli import main

    assert main(["spectrum", *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert words in err and "\n" not in err
