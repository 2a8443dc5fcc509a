"""``numerics.thermal.friction.thermal_friction_point`` on the one pulled slider with an
exact friction law: the CDC without a substrate (``Delta = 0``).

Then eq. (12) with noise is the linear Langevin equation ``x'' + mu x' + Omega^2 (x - v t) =
sqrt(2 D) xi``.  Its mean ``y = <x> - v t`` obeys ``y'' + mu y' + Omega^2 y = -mu v``, whose
stationary solution is ``y = -mu v/Omega^2``: the mean spring force ``Omega^2 <v t - x> = mu v``
(viscous friction) at any ``D``, and ``kT =
D/mu`` (fluctuation-dissipation).  The noise leaves the mean alone but scatters the
time averages: the estimates must fall within their stated standard errors.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from kbm.errors import ParameterError
from numerics.thermal.friction import thermal_friction_point

LINEAR = {"mu": 0.5, "Delta": 0.0, "Omega": 1.0}


@pytest.mark.parametrize("v", [0.3, 1.0])
def test_without_noise_the_friction_is_viscous(v):
    """``D = 0``: ``Omega^2 <v t - x> = mu v`` (the burn-in removes the transient, which
    decays like ``exp(-mu t/2)``; the integrator's bias is below 1e-5)."""
    p = thermal_friction_point("cdc", {**LINEAR, "v": v, "D": 0.0}, trajectories=4, wells=10)
    assert p.error is None and p.kT == 0.0
    assert p.mean_force.value == pytest.approx(LINEAR["mu"] * v, rel=1e-5)


def test_with_noise_the_mean_force_stays_viscous_within_its_standard_errors():
    """``D = 0.05`` (``kT = 0.1``), ``v = 1``, 20 seeds of 8 trajectories: the z-scores of
    the mean force against ``mu v`` are centred (|mean| below three standard errors of the
    mean) with a spread near 1 (Student's t with 7 degrees of freedom: 1.18)."""
    mu, v, D = LINEAR["mu"], 1.0, 0.05
    z = []
    for seed in range(20):
        p = thermal_friction_point("cdc", {**LINEAR, "v": v, "D": D}, trajectories=8,
                                   wells=10, seed=seed)
        assert p.kT == pytest.approx(D / mu, rel=1e-15)
        z.append((p.mean_force.value - mu * v) / p.mean_force.stderr)
    z = np.asarray(z)
    assert abs(z.mean()) < 3 * z.std(ddof=1) / math.sqrt(z.size), z
    assert 0.6 < z.std(ddof=1) < 1.6, z


@pytest.mark.parametrize("params, words", [
    ({"D": 0.01}, "needs the stage velocity"),
    ({"v": 0.0, "D": 0.01}, "v must be > 0"),
    ({"v": 1.0, "D": -0.01}, "D >= 0"),
    ({"v": 1.0}, "needs the noise"),
    # as the deterministic slider: mu <= 0 was blamed on D, Delta < 0 accepted
    ({"v": 1.0, "D": 0.01, "mu": -0.1}, "mu must be > 0, got -0.1"),
    ({"v": 1.0, "D": 0.01, "Delta": -3.0}, "Delta must be >= 0, got -3"),
    ({"v": 1.0, "D": 0.01, "lam": 0.0}, "lam must be > 0"),
])
def test_bad_parameters_are_refused_with_what_to_change(params, words):
    with pytest.raises(ParameterError, match=words):
        thermal_friction_point("cdc", {**LINEAR, **params})


def test_too_few_trajectories_are_refused():
    with pytest.raises(ParameterError, match="at least 4"):
        thermal_friction_point("cdc", {**LINEAR, "v": 1.0, "D": 0.01}, trajectories=2)
