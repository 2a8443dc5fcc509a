"""The escape rate from the Kramers equation with a sink at the next wells' bottoms (issue 36).

References, none produced by the Kramers-equation solver:

* simulated first passages to the next wells' bottoms ``x = +-x_w`` (fixed seeds; the
  censoring-correct rate and its standard error, :mod:`numerics.escape.simulate`);
* Kramers' spatial-diffusion rate ``sum_saddles (sqrt(gamma^2/4 + omega_b^2) - gamma/2)/omega_b
  (omega_0/2 pi) exp(-E_b/kT)`` at high friction (H. A. Kramers, Physica 7 (1940) 284;
  Hanggi, Talkner and Borkovec, Rev. Mod. Phys. 62 (1990) 251, sec. IV: the
  moderate-to-strong friction rate), which the rate must approach as ``E_b/kT`` grows;
* the Mel'nikov-Meshkov rate at low friction (J. Chem. Phys. 85 (1986) 1018; Hanggi et
  al. eq. 4.49) and the mean first-passage time of the averaged energy diffusion (which
  ignores the depletion near the barrier and so lies above the true rate).

The CDC at rest (paper eq. 12), Delta = 2, lam = 1.3, kT = 0.15 (E_b/kT = 7.09).
"""

from __future__ import annotations

import json
import math
import subprocess
import sys

import numpy as np
import pytest
from scipy.optimize import brentq

from kbm.model.conservative import split_conservative
from numerics.escape import averaged_escape, energy_envelope
from numerics.escape.simulate import simulated_escape
from numerics.fokker_planck import kramers_escape
from numerics.fokker_planck._model import next_wells
from numerics.fokker_planck._problem import hermite_ladder
from numerics.noise.langevin import langevin_system, natural_step

PARAMS = {"Delta": 2, "lam": 1.3, "Omega": 1}
KT = 0.15


def _rates(mu, kT=KT, **sizes):
    p = dict(PARAMS, mu=mu)
    esc = averaged_escape(energy_envelope("cdc", p, kT * mu))
    return esc, kramers_escape("cdc", p, kT * mu, esc.saddles, **sizes)


def _simulated(mu, wells, trajectories, seed, kT=KT):
    """First passages to ``x = +-x_w`` from the well bottom, at half the natural step."""
    split = split_conservative("cdc", dict(PARAMS, mu=mu))
    system = langevin_system("cdc", dict(PARAMS, mu=mu), kT * mu)
    dt = natural_step(system, per_period=40) / 2
    return simulated_escape(split, kT * mu, wells, trajectories=trajectories,
                            t_end=200.0 / (1e-4 if mu < 0.1 else 3e-4), dt=dt, seed=seed)


def _kramers_spatial(mu, kT):
    """Kramers' spatial-diffusion rate over the two saddles of the CDC well (closed form)."""
    split = split_conservative("cdc", dict(PARAMS, mu=mu))
    g, gp, G = split.numpy_functions()[:3]
    xs = brentq(lambda z: float(g(np.array(z))), 0.3, 1.0, xtol=1e-15)
    w0 = math.sqrt(float(gp(np.array(0.0))))
    wb = math.sqrt(-float(gp(np.array(xs))))
    Eb = float(G(np.array(xs)) - G(np.array(0.0)))
    return 2 * (math.sqrt(mu * mu / 4 + wb * wb) - mu / 2) / wb * w0 / (2 * math.pi) * math.exp(
        -Eb / kT)


@pytest.fixture(scope="module")
def low_friction():
    """mu = 0.02 by the default ladder: folded orthonormal Hermite functions (64, 90, 128,
    182 on 2.2 L/l = 268 intervals, from the saddle's layer; Risken's pair needed 1448 and
    2048, starting at 8 omega_b/gamma = 1132)."""
    return _rates(0.02)


def test_next_wells_and_ladder():
    """The sink sits on the next wells' bottoms: ``g(x_w) = 0`` and ``g'(x_w) > 0``, beyond
    the saddles; the Hermite ladder grows by sqrt 2."""
    split = split_conservative("cdc", dict(PARAMS, mu=1))
    g, gp, G = split.numpy_functions()[:3]
    wl, wr = next_wells(g, (-0.726968, 0.726968))
    assert wl == pytest.approx(-wr, abs=1e-9)
    assert abs(float(g(np.array(wr)))) < 1e-12 and float(gp(np.array(wr))) > 0
    assert float(G(np.array(wr))) < float(G(np.array(0.726968)))
    assert 0.726968 < wr < 1.3
    assert hermite_ladder(64, 512) == [64, 90, 128, 182, 256, 362, 512]


@pytest.mark.slow
def test_low_friction_is_melnikov_meshkov(low_friction):
    """mu = 0.02 (delta = mu I(E_b)/kT = 0.35, the energy-diffusion regime): the rate
    converges in the Hermite truncation to 1e-3 (to 1e-6 with 2048 functions, the test
    below), a finer position grid moves it by < 5e-3, and it does not depend on the sink
    (< 1e-3; 7e-8 measured);
    it lies below the averaged MFPT rate (no depletion there) and within 10 % of
    Mel'nikov-Meshkov (an asymptotic formula in E_b/kT: at this barrier Kramers' low-friction
    rate, its delta -> 0 limit, is 37 % above the exact energy-diffusion MFPT rate)."""
    esc, fp = low_friction
    assert fp.truncation_error < 1e-3 * fp.rate
    assert fp.chebyshev_error < 5e-3 * fp.rate
    assert fp.sink_error < 1e-3 * fp.rate
    assert fp.rate == pytest.approx(esc.rate_melnikov, rel=0.1)
    assert fp.rate < esc.rate_averaged < esc.rate_kramers


@pytest.mark.slow
def test_low_friction_converges_to_six_digits(low_friction):
    """mu = 0.02: the Hermite ladder's last two rates agree to 1e-6 (the old ladder from 64
    stopped at 8e-4, 724 functions), 1.2 times as many mapped Chebyshev intervals agree to
    1e-6, and a second discretisation agrees to 1e-6: plain Chebyshev points (no map) on
    384 intervals and 2048 Hermite functions (docs/noise.rst: the plain points converge
    more slowly, 2.5e-6 off at 288)."""
    from numerics.fokker_planck._problem import escape_problem
    from test_fokker_planck_blocks import escape_matrix_rate

    _, fp = low_friction
    assert fp.truncation_error < 1e-6 * fp.rate
    assert fp.chebyshev_error < 1e-6 * fp.rate
    split = split_conservative("cdc", dict(PARAMS, mu=0.02))
    sigma, wells, half, kappa0, width = escape_problem(split, KT * 0.02, fp.saddles)
    plain = escape_matrix_rate(split, KT * 0.02, sigma, wells, half, 2048, 384, kappa0,
                               width, solver="fraction", alpha=0.0)
    assert plain == pytest.approx(fp.rate, rel=1e-6)


@pytest.mark.slow
def test_low_friction_asymptotes(low_friction):
    """mu = 0.02, E_b/kT = 7.09, delta = mu I(E_b)/kT = 0.35.  The converged rate against
    the energy-diffusion asymptotes, with the discrepancies docs/noise.rst documents: the
    exact MFPT of the averaged energy diffusion (no depletion near the barrier) is 30 %
    above it (1.120e-4 against 8.616e-5), Mel'nikov-Meshkov's interpolation 9.1 % above
    (its E_b >> kT asymptotics; Kramers' low-friction rate, its delta -> 0 limit, is 37 %
    above the MFPT rate at this barrier)."""
    esc, fp = low_friction
    assert 0.28 < esc.rate_averaged / fp.rate - 1 < 0.32
    assert 0.085 < esc.rate_melnikov / fp.rate - 1 < 0.097
    assert 0.35 < esc.rate_kramers / esc.rate_averaged - 1 < 0.39


@pytest.mark.slow
def test_low_friction_against_simulation(low_friction):
    """mu = 0.02: within 3 standard errors of 400 simulated first passages (seed 3)."""
    _, fp = low_friction
    sim = _simulated(0.02, fp.wells, 400, 3)
    assert abs(fp.rate - sim.rate) < 3 * sim.stderr


@pytest.mark.slow
def test_turnover_against_simulation():
    """mu = 0.2 (the turnover): converged in the truncation to 1e-3 and within 3 standard
    errors of 1600 simulated first passages (seed 1); the energy-diffusion formulas are
    2.5-3.4 times too large there."""
    esc, fp = _rates(0.2)
    assert fp.truncation_error < 1e-3 * fp.rate
    sim = _simulated(0.2, fp.wells, 1600, 1)
    assert abs(fp.rate - sim.rate) < 3 * sim.stderr
    assert esc.rate_averaged > 2 * fp.rate


def _saddle():
    g = split_conservative("cdc", dict(PARAMS, mu=1)).numpy_functions()[0]
    return brentq(lambda z: float(g(np.array(z))), 0.3, 1.0, xtol=1e-15)


@pytest.mark.slow
def test_moderate_friction_spectral_convergence():
    """mu = 1: the eigenvalue converges spectrally (successive truncations agree to 1e-4)
    and the rate lies below the energy-diffusion rates (the turnover)."""
    esc, fp = _rates(1.0)
    assert fp.truncation_error < 1e-4 * fp.rate
    assert fp.sink_error < 1e-3 * fp.rate and fp.chebyshev_error < 1e-3 * fp.rate
    assert fp.rate < esc.rate_averaged


def test_moderate_friction_against_simulation():
    """mu = 1 from a small grid (the default run's sibling of the test above): two Hermite
    truncations from 32 agree to 1e-4, 96 and 116 Chebyshev intervals to 1e-4, a sharper
    sink moves the rate by < 3e-3, and the rate is within 3 standard errors of 400
    simulated first passages to the next wells' bottoms (seed 2).  The first sink's rate and
    change (``sink_tol=inf``, as this check was written: 6.6260e-4, 6.9e-5 of it; the sink
    ladders' limit, 6.6237e-4, 3.6e-4 below it, cost 3 s more to climb and moves z by
    0.01 of the 5 % standard error; the ladders are checked in test_fokker_planck_sink.py)."""
    xs = _saddle()
    fp = kramers_escape("cdc", dict(PARAMS, mu=1), KT, (-xs, xs), n_hermite=32, n_cheb=96,
                        sink_tol=math.inf)
    assert fp.truncation_error < 1e-4 * fp.rate
    assert fp.chebyshev_error < 1e-4 * fp.rate and fp.sink_error < 3e-3 * fp.rate
    sim = _simulated(1.0, fp.wells, 400, 2)
    assert abs(fp.rate - sim.rate) < 3 * sim.stderr


@pytest.mark.slow
def test_high_friction_approaches_kramers():
    """mu = 5 (gamma/omega_b = 1.8): the rate over Kramers' spatial-diffusion rate moves
    towards 1 as E_b/kT grows from 7.1 to 10.6 (the corrections are O(kT/E_b)).  The bound
    was 0.1 on the first sink's rate, 1 % above the perfectly absorbing limit (ratio 0.904
    against 0.895 at kT = 0.15: 3.5e-6 off with 1.2e-6 stated; :mod:`._sink`)."""
    xs, ratios = _saddle(), []
    for kT in (0.15, 0.1):
        fp = kramers_escape("cdc", dict(PARAMS, mu=5), 5 * kT, (-xs, xs), n_hermite=16,
                            n_cheb=64)
        assert fp.truncation_error < 1e-3 * fp.rate and fp.chebyshev_error < 1e-3 * fp.rate
        ratios.append(fp.rate / _kramers_spatial(5.0, kT))
    assert abs(1 - ratios[1]) < abs(1 - ratios[0]) < 0.11


@pytest.mark.parametrize("mu", [pytest.param(0.2, marks=pytest.mark.slow), 1.0])
def test_turnover_converges_and_ignores_the_range(mu):
    """mu = 0.2 and 1: the default ladders reach 1e-6 in the Hermite truncation and the
    position grid, and the rate does not depend on where the range ends (half or the whole
    saddle-to-bottom distance past the bottoms: 1e-6; with the one-stage sink it moved by
    1e-5 at mu = 1 and converged only like 1/n_cheb, the pinned ends acting on a density
    that was not yet negligible there; the sink's second stage, ten times stronger from
    2.5 widths past the bottoms, makes it so).  mu = 0.2 is slow: its whole-distance range
    needs 514 Hermite functions and 471 intervals (78 s CPU, against 2.3 s for the default
    range; measured 2026-11-27)."""
    xs = _saddle()
    p = dict(PARAMS, mu=mu)
    fp = kramers_escape("cdc", p, KT * mu, (-xs, xs))
    assert fp.truncation_error < 1e-6 * fp.rate and fp.chebyshev_error < 1e-6 * fp.rate
    wide = kramers_escape("cdc", p, KT * mu, (-xs, xs), margin=fp.wells[1] - xs)
    assert wide.rate == pytest.approx(fp.rate, rel=1e-6)


def test_escape_cli_method_fokker_planck():
    proc = subprocess.run([sys.executable, "-m", "numerics.cli", "escape", "cdc", "-p",
                           "mu=1", "-p", "Delta=2", "-p", "lam=1.3", "-p", "D=0.15",
                           "--no-simulation", "--method", "fokker-planck", "--json"],
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    rep = json.loads(proc.stdout)
    assert rep["rate_fokker_planck"] > 0
    assert set(rep["fokker_planck"]) >= {"sink_error", "truncation_error"}
    assert "rate_averaged" in rep and "rate_melnikov" in rep



def test_escape_cli_prints_seven_digits_where_the_errors_allow():
    """The text line of the Fokker-Planck rate has 7 significant digits when the sink,
    truncation and Chebyshev errors are all at most 1e-6 of the rate (the CDC case of
    docs/noise.rst at mu = 0.02, 2.3255767e-3), 6 when one is larger (mu = 1: the sink moves
    the rate by 6.6e-5); the JSON keeps the full float."""
    from numerics.cli.escape import fokker_planck_line

    f = {"sink_error": 2.3e-12, "truncation_error": 1.5e-9, "chebyshev_error": 3.2e-12,
         "hermite": 2896, "chebyshev": 239}
    rep = {"rate_fokker_planck": 0.00232557665929561, "fokker_planck": f}
    assert "rate = 0.002325577 (" in fokker_planck_line(rep)
    rep["fokker_planck"] = dict(f, sink_error=4.4e-8)
    rep["rate_fokker_planck"] = 0.0006626046926060393
    assert "rate = 0.000662605 (" in fokker_planck_line(rep)
    rep["fokker_planck"] = dict(f, chebyshev_error=float("nan"))
    assert "rate = 0.000662605 (" in fokker_planck_line(rep)
