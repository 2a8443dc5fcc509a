"""The escape rate from the Kramers equation with a sink past the saddles (issue 36).

References: Mel'nikov and Meshkov, J. Chem. Phys. 85 (1986) 1018 (the low-friction rate
with the depletion of the population near the barrier; Hanggi, Talkner and Borkovec, Rev.
Mod. Phys. 62 (1990) 251, eq. 4.49), and the mean first-passage time of the averaged
energy diffusion (Kramers' energy-diffusion limit, which ignores the depletion and so lies
above the true rate).  The CDC at rest (paper eq. 12), Delta = 2, lam = 1.3, kT = 0.15
(E_b/kT = 7.1).
"""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from numerics.escape import averaged_escape, energy_envelope
from numerics.fokker_planck import kramers_escape

PARAMS = {"Delta": 2, "lam": 1.3, "Omega": 1}
KT = 0.15


def _rates(mu):
    p = dict(PARAMS, mu=mu)
    esc = averaged_escape(energy_envelope("cdc", p, KT * mu))
    return esc, kramers_escape("cdc", p, KT * mu, esc.saddles)


def test_low_friction_is_melnikov_meshkov():
    """mu = 0.02 (delta = mu I(E_b)/kT = 0.12, deep in the energy-diffusion regime): the
    Kramers-equation rate is within 5 % of Mel'nikov-Meshkov and below the averaged MFPT
    rate (no depletion there); its sink and truncation errors are below 10 %."""
    esc, fp = _rates(0.02)
    assert fp.rate == pytest.approx(esc.rate_melnikov, rel=0.05)
    assert fp.rate < esc.rate_averaged < esc.rate_kramers
    assert fp.sink_error < 0.1 * fp.rate and fp.truncation_error < 0.1 * fp.rate


def test_moderate_friction_spectral_convergence():
    """mu = 1: the eigenvalue of the discretised operator converges spectrally (32 and 64
    Hermite functions agree to 1e-4), and the rate lies below the energy-diffusion rates
    (the turnover)."""
    esc, fp = _rates(1.0)
    assert fp.truncation_error < 1e-4 * fp.rate
    assert fp.rate < esc.rate_averaged


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
