"""Backbone curves of duffing-1-3 (two cubic oscillators in 1:3 internal resonance, potential
coupling k x1^3 x2, no damping; Nayfeh & Mook 1979, sec. 6.6): the averaged backbones
(fixed points of the slow flow with gamma = 0 or pi) against the true reversible periodic
orbits found by shooting (numerics.comparison.backbone).  At the true orbit's first-harmonic
amplitude a1, the averaged frequency of order n is off by O(mu^(n+1)) and the averaged a2
by O(mu^n): halving mu divides the errors by 2^(n+1) and 2^n (n = 1, 2, 3).
"""

from __future__ import annotations

import math

import pytest

from kbm.expansion.coupled import derive_coupled
from numerics.comparison.backbone import averaged_backbone_point, true_backbone_point

VALS = {"zeta1": 0, "zeta2": 0, "alpha1": 1, "alpha2": 1, "k": 1, "h": 0}


@pytest.mark.parametrize("gamma", [0.0, math.pi])
def test_backbone_against_shooting(gamma):
    results = [derive_coupled("duffing-1-3", n, VALS) for n in (1, 2, 3)]
    errors = {}
    for mu in (0.02, 0.01):
        guess = averaged_backbone_point(results[0], {"mu": mu}, 1.0, gamma, (1e-6, 5))
        true = true_backbone_point("duffing-1-3", {"mu": mu, "sigma": 0, **VALS}, 1.0,
                                   guess.a2 * math.cos(gamma), 2 * math.pi / guess.frequency, 3)
        assert abs(math.remainder(true.gamma - gamma, 2 * math.pi)) < 1e-8
        for n, res in enumerate(results, 1):
            av = averaged_backbone_point(res, {"mu": mu}, true.a1, gamma, (1e-6, 5))
            errors[(n, mu)] = (abs(av.frequency - true.frequency), abs(av.a2 - true.a2))
    for n in (1, 2, 3):
        rf = errors[(n, 0.02)][0] / errors[(n, 0.01)][0]
        ra = errors[(n, 0.02)][1] / errors[(n, 0.01)][1]
        assert 0.8 * 2 ** (n + 1) < rf < 1.25 * 2 ** (n + 1), (n, rf)
        assert 0.8 * 2**n < ra < 1.25 * 2**n, (n, ra)
