"""The turnover rate of a well with two equal exits (numerics.escape.turnover, issue 36).

``r = (lambda_+/omega_b) 2 A(delta/2) (omega_0/2 pi) exp(-E_b/kT)``.  References, none
produced by the formula's code:

* ``lambda_+`` is the unstable eigenvalue of the saddle's linearisation ``x'' + gamma x' -
  omega_b^2 x = 0`` (Kramers 1940; Hanggi, Talkner and Borkovec, Rev. Mod. Phys. 62 (1990)
  251, sec. IV), here from numpy's eigenvalues;
* Mel'nikov-Meshkov's ``A(delta)`` (J. Chem. Phys. 85 (1986) 1018; HTB eq. 4.49) against
  its expansions, derived by the Mellin transform of ``ln(1 - e^(-u))`` (``-Gamma(s)
  zeta(s + 1)``): ``ln(A/delta) = zeta(1/2) (delta/pi)^(1/2) - zeta(-1/2) delta^(3/2)/(12
  pi^(1/2)) + zeta(-3/2) delta^(5/2)/(160 pi^(1/2)) + ...`` (no integer powers: ``1/Gamma``
  vanishes at the poles there) and, by Watson's lemma, ``1 - A = 2 exp(-delta/4)/(pi
  delta)^(1/2) (1 - 2/delta + 12/delta^2 - 120/delta^3 + ...)``;
* the limits: Kramers' energy-diffusion rate ``(gamma I/kT) (omega_0/2 pi) exp(-E_b/kT)``
  (HTB eq. 4.8) and the spatial-diffusion rate over two saddles;
* the exact Fokker-Planck transition rate (:mod:`numerics.fokker_planck.escape`, slow test).
"""

from __future__ import annotations

import json
import math
import subprocess
import sys

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.optimize import brentq
from scipy.special import zeta

from kbm.errors import ParameterError
from numerics.escape import (averaged_escape, kramers_low_friction, melnikov_meshkov_factor,
                             spatial_diffusion_factor, turnover_rate, two_exit_factor)
from numerics.escape.envelope import origin_well_envelope

CDC = {"Delta": 3, "lam": 1, "Omega": 1}


@settings(max_examples=40, deadline=None)
@given(st.floats(1e-4, 1e3), st.floats(0.1, 10))
def test_spatial_factor_is_the_saddles_unstable_eigenvalue(gamma, omega_b):
    """``lambda_+`` is the positive eigenvalue of ``[[0, 1], [omega_b^2, -gamma]]``, taken
    as ``-omega_b^2/lambda_-`` (the determinant) from numpy's ``lambda_-``, the eigenvalue
    of largest size (accurate to rounding; ``lambda_+`` itself is not, where ``gamma >>
    omega_b``); the characteristic polynomial vanishes there."""
    eig = np.linalg.eigvals(np.array([[0.0, 1.0], [omega_b ** 2, -gamma]])).real
    lam = -omega_b ** 2 / min(eig)
    factor = spatial_diffusion_factor(gamma, omega_b)
    assert factor * omega_b == pytest.approx(lam, rel=1e-12)
    got = factor * omega_b
    assert abs(got * got + gamma * got - omega_b ** 2) < 1e-13 * (gamma * got + omega_b ** 2)


def test_spatial_factor_limits():
    """``1 - gamma/(2 omega_b) + O(gamma^2)`` at low friction, ``omega_b/gamma (1 -
    omega_b^2/gamma^2 + ...)`` at high friction (no cancellation at gamma = 1e8)."""
    assert spatial_diffusion_factor(1e-6, 2.0) == pytest.approx(1 - 0.25e-6, abs=1e-12)
    assert spatial_diffusion_factor(1e8, 2.0) == pytest.approx(2e-8 * (1 - 4e-16),
                                                               rel=1e-14)


@pytest.mark.parametrize("delta", [1e-6, 1e-4, 1e-3, 1e-2, 0.1])
def test_melnikov_meshkov_small_delta_expansion(delta):
    """``ln(A/delta)`` against its first two terms; the rest is the third term,
    ``zeta(-3/2)/(160 pi^(1/2)) = -9.0e-5`` times ``delta^(5/2)`` (bound 2e-4), plus the
    quadrature's 1e-12."""
    a = melnikov_meshkov_factor(delta)
    two = zeta(0.5) * math.sqrt(delta / math.pi) - zeta(-0.5) * delta ** 1.5 / (
        12 * math.sqrt(math.pi))
    assert abs(math.log(a / delta) - two) < 2e-4 * delta ** 2.5 + 1e-12


@pytest.mark.parametrize("delta", [20.0, 40.0, 80.0])
def test_melnikov_meshkov_large_delta_expansion(delta):
    """``(1 - A)/(2 exp(-delta/4)/(pi delta)^(1/2))`` against ``1 - 2/delta + 12/delta^2``
    within the first omitted term ``120/delta^3`` (an alternating asymptotic series)."""
    a = melnikov_meshkov_factor(delta)
    q = (1 - a) / (2 * math.exp(-delta / 4) / math.sqrt(math.pi * delta))
    assert abs(q - (1 - 2 / delta + 12 / delta ** 2)) < 120 / delta ** 3


def test_two_exit_factor_limits():
    """``2 A(delta/2)``: ``delta`` (the full loop's loss, both exits together) as ``delta ->
    0``, with ``2 A(delta/2)/delta = exp(zeta(1/2) (delta/2 pi)^(1/2) + O(delta^(3/2)))``
    (the ``delta^(3/2)`` term: ``-zeta(-1/2)/(12 (8 pi)^(1/2)) = 3.5e-3``, bound 1e-2)
    above one exit's ``A(delta)/delta`` (half the loss between barrier encounters, less
    depletion); 2 (two transition-state exits) as ``delta -> inf``."""
    for d in (1e-6, 1e-3, 0.1, 1.0):
        two = two_exit_factor(d)
        assert math.log(two / d) == pytest.approx(zeta(0.5) * math.sqrt(d / (2 * math.pi)),
                                                  abs=1e-2 * d ** 1.5 + 1e-12)
        assert melnikov_meshkov_factor(d) < two < d
    s = 100.0   # delta = 200: 2 - 2 A(s) from the large-delta expansion above
    gap = 4 * math.exp(-s / 4) / math.sqrt(math.pi * s) * (1 - 2 / s + 12 / s ** 2)
    assert 2 - two_exit_factor(2 * s) == pytest.approx(gap, rel=120 / s ** 3 + 1e-3)


def test_turnover_rate_limits():
    """Low friction: Kramers' energy-diffusion rate (the full loop's action, HTB eq. 4.8)
    times ``1 + zeta(1/2) (delta/2 pi)^(1/2) - gamma/(2 omega_b) + O(delta)``; high
    friction: ``2 (lambda_+/omega_b) (omega_0/2 pi) exp(-E_b/kT)`` (Kramers' spatial-
    diffusion rate over two saddles) up to ``exp(-delta/8)``."""
    kT, Eb, action, w0, wb = 0.35, 1.087, 2.05, 4.46, 4.19
    gamma = 1e-7
    d = gamma * action / kT
    low = turnover_rate(gamma, kT, Eb, action, w0, wb)
    expected = 1 + zeta(0.5) * math.sqrt(d / (2 * math.pi)) - gamma / (2 * wb)
    assert low / kramers_low_friction(gamma, kT, Eb, action, w0) == pytest.approx(
        expected, abs=10 * d)
    gamma = 60.0
    lam = math.sqrt(gamma ** 2 / 4 + wb ** 2) - gamma / 2
    high = 2 * lam / wb * w0 / (2 * math.pi) * math.exp(-Eb / kT)
    assert turnover_rate(gamma, kT, Eb, action, w0, wb) == pytest.approx(high, rel=1e-12)


@pytest.mark.parametrize("bad", [0.0, -1.0, math.inf, math.nan])
def test_turnover_rate_refuses_bad_input(bad):
    with pytest.raises(ParameterError, match="positive, finite"):
        turnover_rate(bad, 0.35, 1.0, 2.0, 4.0, 4.0)
    with pytest.raises(ParameterError, match="omega_b"):
        spatial_diffusion_factor(1.0, bad)


def test_averaged_escape_barrier_frequency_and_turnover():
    """CDC, Delta = 3: ``omega_b = (-g'(x_s))^(1/2)``, ``g' = Omega^2 + 2 pi Delta
    cos(2 pi x)`` at the saddle ``g(x_s) = 0`` (brentq), and ``rate_turnover`` is the
    formula with the well's own action, frequency and barrier."""
    mu, kT = 0.2, 0.35
    esc = averaged_escape(origin_well_envelope("cdc", dict(CDC, mu=mu), kT * mu))
    xs = brentq(lambda z: z + 3 * math.sin(2 * math.pi * z), 0.3, 0.7, xtol=1e-15)
    wb = math.sqrt(-(1 + 6 * math.pi * math.cos(2 * math.pi * xs)))
    assert esc.omega_b == pytest.approx(wb, rel=1e-9)
    assert esc.rate_turnover == pytest.approx(
        turnover_rate(mu, kT, esc.barrier, esc.action, esc.omega0, wb), rel=1e-9)
    assert esc.rate_melnikov == pytest.approx(
        melnikov_meshkov_factor(mu * esc.action / kT) * esc.omega0 / (2 * math.pi)
        * math.exp(-esc.barrier / kT), rel=1e-12)


@pytest.mark.slow  # 4-7 s; the default run keeps its siblings (five-minute rule)
def test_escape_cli_reports_the_turnover():
    """``kbm escape`` keeps every key and adds ``rate_turnover`` and ``omega_b``; the text
    names the formula of each line."""
    args = [sys.executable, "-m", "numerics.cli", "escape", "cdc", "-p", "mu=0.2", "-p",
            "Delta=3", "-p", "D=0.07", "--no-simulation"]
    rep = json.loads(subprocess.run(args + ["--json"], capture_output=True, text=True,
                                    check=True, timeout=300).stdout)
    assert {"rate_kramers", "rate_melnikov", "rate_averaged", "rate_turnover",
            "omega_b"} <= set(rep)
    assert rep["rate_turnover"] < rep["rate_kramers"]
    text = subprocess.run(args, capture_output=True, text=True, check=True,
                          timeout=300).stdout
    assert "turnover, two exits:       rate = " in text
    assert "(lambda_+/omega_b) 2 A(delta/2) (omega0/2 pi) exp(-E_b/kT)" in text
    assert "(one exit: A(delta) (omega0/2 pi) exp(-E_b/kT))" in text


def _against_fokker_planck(mu: float, kT: float) -> dict:
    """``kbm escape cdc -p Delta=3 --method fokker-planck --no-simulation`` as a dict, with
    the Fokker-Planck rate's stated errors below 1e-5 of it (far below the asymptotic
    formulas' deviations measured here)."""
    from numerics.escape.report import escape_report

    rep = escape_report("cdc", {"mu": repr(mu), "Delta": "3", "D": repr(kT * mu)},
                        simulate=False, method="fokker-planck")
    f = rep["fokker_planck"]
    assert f["sink_error"] + f["truncation_error"] + f["chebyshev_error"] < (
        1e-5 * rep["rate_fokker_planck"])
    return rep


@pytest.mark.slow
def test_turnover_tends_to_the_fokker_planck_rate():
    """CDC Delta = 3 against the exact Fokker-Planck transition rate at E_b/kT = 3.11 and
    6.04 (kT = 0.35, 0.18).  The formula is asymptotic in E_b/kT; docs/noise-escape.rst
    tabulates ``|ratio - 1| E_b/kT`` over E_b/kT = 3.1, 6.0, 9.1.

    * High friction, mu = 50 (gamma/omega_b = 12): ``rate_turnover`` over the FP rate is
      1.238 and 1.138; ``|ratio - 1| E_b/kT`` = 0.74, 0.83, 0.75 (0.46, 0.48, 0.42 at mu =
      5): an O(kT/E_b) correction with a coefficient below 1.  Asserted: below 1 at E_b/kT
      = 6.04, and the gap falls by at least 1.4 times as E_b/kT doubles (2 for a pure
      kT/E_b, 1.7 measured).
    * The two-exit depopulation factor at the turnover, delta = mu I/kT = 1.124 (mu = 0.2,
      then 0.1029: delta held, so E_b/kT grows along the formula's own asymptotics).  Its
      own error is isolated from Kramers' energy-diffusion rate's, whose finite-barrier
      correction is of order (kT/E_b) ln(E_b/kT) (Mel'nikov, Phys. Rev. E 48 (1993) 3271;
      r_K is 2.19 and 2.27 times the FP rate, the exact averaged-energy MFPT rate 1.44 and
      1.59 times): the MFPT rate times ``rate_turnover/rate_kramers`` is 0.763 and 0.852 of
      the FP rate, ``|ratio - 1| E_b/kT`` = 0.74, 0.90 (0.87 at 9.06).  Asserted below 1 at
      both barriers.  One exit's ``A(delta)`` in its place gives 0.595 and 0.664 (2.03 at
      6.04, 2.67 at 9.06: no O(kT/E_b) convergence); asserted above 1.5 at 6.04."""
    gaps = []
    for kT in (0.35, 0.18):
        rep = _against_fokker_planck(50.0, kT)
        ratio = rep["rate_turnover"] / rep["rate_fokker_planck"]
        gaps.append(abs(ratio - 1))
        assert rep["barrier_over_kT"] == pytest.approx(1.0870 / kT, rel=1e-3)
    assert gaps[1] * 1.0870 / 0.18 < 1
    assert gaps[0] / gaps[1] > 1.4
    for kT, mu in ((0.35, 0.2), (0.18, 0.2 * 0.18 / 0.35)):
        rep = _against_fokker_planck(mu, kT)
        b = rep["barrier_over_kT"]
        depleted = rep["rate_turnover"] / rep["rate_kramers"]
        assert abs(rep["rate_averaged"] * depleted / rep["rate_fokker_planck"] - 1) * b < 1
        lam = spatial_diffusion_factor(mu, rep["omega_b"])
        delta = mu * rep["action_at_barrier"] / rep["kT"]
        assert delta == pytest.approx(1.124, rel=1e-3)
        one_exit = rep["rate_averaged"] * lam * melnikov_meshkov_factor(delta) / delta
        if kT == 0.18:
            assert abs(one_exit / rep["rate_fokker_planck"] - 1) * b > 1.5
