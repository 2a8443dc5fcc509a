"""Issue 11, item 4: the non-trivial Floquet multiplier from Liouville's formula.

The reference ``oint mu (1 - x^2) dt`` is integrated here by scipy's DOP853 on a right-hand
side written in this file (not the model's compiled one), from the cycle's section point.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from numerics import limit_cycle
from numerics.shooting.floquet import floquet_multipliers, nontrivial_multiplier


def _div_integral(mu: float, x0: float, T: float) -> float:
    def rhs(t, y):
        x, v, _ = y
        return [v, mu * (1 - x * x) * v - x, mu * (1 - x * x)]
    sol = solve_ivp(rhs, (0.0, T), [x0, 0.0, 0.0], method="DOP853", rtol=1e-13, atol=1e-13)
    return float(sol.y[2, -1])


@pytest.mark.parametrize("mu", [1.0, 5.0, 10.0])
def test_vdp_nontrivial_multiplier_is_liouville(mu):
    c = limit_cycle("vdp", {"mu": mu})
    ref = math.exp(_div_integral(mu, c.amplitude_max, c.period))
    m = c.floquet_multipliers[1]
    assert abs(m.imag) == 0.0
    assert abs(m.real - ref) <= 1e-6 * ref
    assert c.stable
    assert abs(c.floquet_multipliers[0] - 1) < 1e-5


def test_vdp_mu5_not_rounding_noise():
    c = limit_cycle("vdp", {"mu": 5})
    assert 7.7e-38 < c.floquet_multipliers[1].real < 7.8e-38


def test_helpers():
    phi = np.array([[1.0, 0.3], [0.0, 0.25]])
    triv, other = floquet_multipliers(phi, math.log(0.25))
    assert triv == 1.0 and abs(other - 0.25) < 1e-15
    assert nontrivial_multiplier(-800.0) == 0.0
    with pytest.raises(ValueError, match="not finite"):
        nontrivial_multiplier(float("nan"))
    with pytest.raises(ValueError, match="not positive"):
        nontrivial_multiplier(0.0, -1.0)
