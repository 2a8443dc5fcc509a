"""Phase diffusion of a noisy limit cycle against simulation (issue 22: the linewidth).

:func:`numerics.spectrum.phase_diffusion.cycle_phase_diffusion` predicts ``Var psi(t) ~ 2 D_phi
t``; for the van der Pol oscillator ``D_phi = D/8`` (first-order stochastic averaging, Stratonovich vol. 2
ch. 9; the cycle's frequency does not depend on the amplitude at first order).  The
simulation unwraps the phase ``atan2(-x', x)`` of Langevin paths started on the cycle and
compares the variance of its increment over ``T`` with ``2 D_phi T`` within three standard
errors of the sample variance (``sqrt(2/(N-1))`` relative, Gaussian increments).  With the
Duffing shear ``mu alpha x^3`` added the amplitude noise feeds the phase: ``D_phi = (D/8)(1 +
9 alpha^2)``, checked the same way.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from kbm.model.builtins import custom_model
from numerics.spectrum.phase_diffusion import cycle_phase_diffusion as phase_diffusion
from numerics.noise import langevin_system


def _phase_variance(model, params, D, T, dt, N, stride):
    system = langevin_system(model, params, D)
    inc = []
    for i in range(N):
        t, y = system.path((2.0, 0.0), T, dt, stride=stride, seed=9, index=i)
        ph = np.unwrap(np.arctan2(-y[:, 1], y[:, 0]))
        inc.append(ph[-1] - ph[0])
    inc = np.asarray(inc)
    return float(np.var(inc, ddof=1)), N


@pytest.mark.parametrize("alpha", [0.0, 0.5])
def test_phase_variance_grows_like_2_D_phi_t(alpha):
    F = f"(1 - x**2)*xdot - {alpha}*x**3"
    model = custom_model(F, name="vdp_shear")
    params, D, T = {"mu": 0.05}, 0.004, 300.0
    pred = phase_diffusion(model, params, D)
    var, N = _phase_variance(model, params, D, T, 0.05, 400, 20)
    # the deterministic part of the increment (frequency x T) is common to all paths
    expect = 2 * pred.D_phi * T
    assert abs(var - expect) < 3 * expect * math.sqrt(2 / (N - 1)), (var, expect)
