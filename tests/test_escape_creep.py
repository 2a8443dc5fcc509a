"""Thermally activated slips of the Prandtl-Tomlinson slider by rate theory
(numerics.escape.creep): Sang, Dube, Grant, PRL 87 (2001) 174301."""

from __future__ import annotations

import numpy as np
import pytest

from kbm.errors import ParameterError
from numerics.escape.creep import _ramp, barrier_at, slip_force
from numerics.sliding.potential import saddle_node

PT = dict(Delta=3.0, lam=1.0, Omega=1.0)


@pytest.mark.slow  # 4-8 s; kept out of the default run (five-minute rule)
def test_barrier_closes_like_three_halves():
    """Saddle-node normal form: E_b ~ (L_0 - L)^{3/2} as the stage nears the slip point."""
    L, F, Eb, ww, I, L0, Fc = _ramp(3.0, 1.0, 1.0, 4000)
    m = (L0 - L > 1e-5) & (L0 - L < 1e-3)
    slope = np.polyfit(np.log(L0 - L[m]), np.log(Eb[m]), 1)[0]
    assert slope == pytest.approx(1.5, abs=1e-3)


def test_barrier_at_rest_is_symmetric_well():
    """At L = 0 the well is the CDC's central well: saddle x_s with x_s + Delta sin(k x_s)
    = 0 and E_b = x_s^2/2 + (Delta/k)(1 - cos k x_s)."""
    xw, xs, Eb, ww, I = barrier_at(0.0, **PT)
    k = 2 * np.pi
    assert xw == pytest.approx(0.0, abs=1e-14)
    assert xs + 3 * np.sin(k * xs) == pytest.approx(0.0, abs=1e-12)
    assert Eb == pytest.approx(xs**2 / 2 + 3 / k * (1 - np.cos(k * xs)), rel=1e-12)
    assert ww == pytest.approx(np.sqrt(1 + 3 * k), rel=1e-12)


def test_zero_temperature_joins_the_athermal_slip():
    """As kT -> 0 the mean slip force tends to the quasi-static static friction F_c
    (the saddle node of numerics.sliding.potential), and the slip stage position to L_0,
    monotonically.  (Near the saddle node the spring force Omega^2 (L - x_w) exceeds F_c:
    it peaks at Delta where x_w = lam/4, so F_c is approached from above.)"""
    sn = saddle_node(**PT)
    res = [slip_force(1e-3, kT, mu=0.1, **PT) for kT in (1e-4, 1e-5, 1e-6, 1e-7)]
    gaps = [abs(r.mean - sn.static_force) for r in res]
    adv = [r.advance for r in res]
    assert all(a > 0 for a in adv) and adv == sorted(adv, reverse=True)
    assert gaps == sorted(gaps, reverse=True)
    assert gaps[-1] < 1e-5 * sn.static_force
    assert max(r.mean for r in res) <= 3.0 + 1e-9   # never above the peak force Delta


@pytest.mark.parametrize("kT", [3e-4, 3e-3])
def test_slip_force_grows_with_velocity(kT):
    """Thermal activation: the slower the pull, the earlier the slip (creep)."""
    F = [slip_force(v, kT, mu=0.1, **PT).mean for v in (1e-8, 1e-6, 1e-4, 1e-2)]
    assert F == sorted(F)


@pytest.mark.parametrize("bad", [dict(v=0), dict(kT=-1), dict(mu=float("nan"))])
def test_bad_input(bad):
    args = dict(v=1e-3, kT=1e-3, mu=0.1) | bad
    with pytest.raises(ParameterError):
        slip_force(args["v"], args["kT"], mu=args["mu"], **PT)
