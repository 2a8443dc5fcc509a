"""The averaged stationary density of the energy against the exact Boltzmann density
(issue 22, part 1: energy-envelope averaging).

For linear damping the stationary density is ``exp(-H/kT)`` (Gibbs; Risken sec. 10.1),
whatever the potential: the mass of an energy bin ``[E_a, E_b)`` is
``int dx exp(-G/kT) int_{E_a < v^2/2 + G < E_b} exp(-v^2/(2 kT)) dv``, whose inner integral
is a difference of error functions.  The energy-envelope average (glued over the graph of
period annuli, :meth:`numerics.escape.envelope.EnergyEnvelope.energy_bins`) must equal it
for the CDC (paper eq. 12) at any temperature, separatrix energies included.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.special import erf

from kbm.model.conservative import split_conservative
from numerics.escape import energy_envelope

PARAMS = {"mu": 0.1, "Delta": 3, "lam": 1, "Omega": 1}


def _boltzmann_bins(edges, kT):
    G = split_conservative("cdc", PARAMS).numpy_functions()[2]
    xs = np.linspace(-12, 12, 240001)
    Gx = G(xs)
    s = math.sqrt(2 * kT)

    def mass(a, b):
        va = np.sqrt(2 * np.clip(a - Gx, 0, None))
        vb = np.sqrt(2 * np.clip(b - Gx, 0, None))
        inner = 2 * math.sqrt(math.pi * kT / 2) * (erf(vb / s) - erf(va / s))
        return float(np.sum(np.exp(-Gx / kT) * inner))

    Z = mass(0.0, 60 * kT + 10)
    return np.array([mass(a, b) for a, b in zip(edges[:-1], edges[1:])]) / Z / np.diff(edges)


@pytest.mark.parametrize("kT", [pytest.param(0.25, marks=pytest.mark.slow), 1.0])
def test_energy_density_is_boltzmann(kT):
    """Bin by bin within 2 % over the bins holding 1 % of the peak or more (1e-4 below the
    highest separatrix; above it the degree-64 Chebyshev fit of the action over the outer
    annulus, whose end is a separatrix with a logarithmic kink, leaves 1-4 % in the far
    tail), and <x'^2> = kT (equipartition) to 1e-3."""
    env = energy_envelope("cdc", PARAMS, 0.1 * kT)
    edges = np.linspace(0.0, 6.0 * kT + 1.0, 31)
    ref = _boltzmann_bins(edges, kT)
    avg = env.energy_bins(edges)
    big = ref > 1e-2 * ref.max()
    assert np.max(np.abs(avg[big] / ref[big] - 1)) < 2e-2
    assert np.median(np.abs(avg[big] / ref[big] - 1)) < 1e-3
    assert abs(env.stationary_moment_v2() / kT - 1) < 1e-3
