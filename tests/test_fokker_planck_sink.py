"""The escape rate's limit of a perfectly absorbing sink (:mod:`numerics.fokker_planck._sink`,
issue 36: the rate at any damping to 6 digits).

References, none produced by the sink ladder under test:

* Aitken's ``Delta^2`` process is exact on ``r + a q^j`` (a closed form; hypothesis draws
  ``r``, ``a`` and ``q``);
* a second ladder of sinks, centred on the next wells' bottoms (``offset = 0``: the rates
  fall toward the limit, where the default ladder's rise), extrapolated the same way: the
  two limits agree within their stated errors;
* the first sink's rate at low friction, where the sink does not matter (the ladder does
  not run there, so the rate is the one of the Hermite and Chebyshev ladders alone);
* Smoluchowski's mean first-passage time to ``x = +-x_w`` (Gardiner, *Handbook of
  Stochastic Methods*, eq. 5.2.158, by quadrature) times the friction, which the rate
  times the friction approaches from below as the friction grows past the barrier
  frequency (Kramers' factor ``(gamma^2/4 + omega_b^2)^(1/2) - gamma/2 < omega_b^2/gamma``).

The CDC at rest (paper eq. 12), Delta = 3, lam = 1, kT = 0.35 (the issue's case: the next
wells' bottoms 1.65 kT under the saddles).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.integrate import quad
from scipy.optimize import brentq

from kbm.conservative import split_conservative
from numerics.fokker_planck import kramers_escape
from numerics.fokker_planck._bases import cheb_centred
from numerics.fokker_planck._rungs import FractionRungs
from numerics.fokker_planck._sink import WEIGHT, aitken, sink_limit, sink_rung
from numerics.fokker_planck.escape import (ALPHA, SINK_HERMITE, SINK_INTERVALS, _sink,
                                           escape_problem, kT_gamma)

PARAMS = {"Delta": 3, "lam": 1, "Omega": 1}
KT = 0.35


def _saddles():
    g = split_conservative("cdc", dict(PARAMS, mu=1)).numpy_functions()[0]
    xs = brentq(lambda z: float(g(np.array(z))), 0.3, 0.7, xtol=1e-15)
    return (-xs, xs)


@settings(max_examples=50, deadline=None)
@given(r=st.floats(-10, 10), a=st.floats(0.01, 10), q=st.floats(0.05, 0.9),
       sign=st.sampled_from([-1.0, 1.0]))
def test_aitken_is_exact_on_a_geometric_sequence(r, a, q, sign):
    """``Delta^2`` gives ``r`` from ``r + a q^j``, ``j = 0, 1, 2`` (closed form)."""
    seq = [r + sign * a * q**j for j in range(3)]
    assert aitken(*seq) == pytest.approx(r, abs=1e-9 * (abs(r) + a))


def test_aitken_does_not_extrapolate_a_growing_or_oscillating_sequence():
    assert aitken(1.0, 2.0, 4.0) == 4.0
    assert aitken(1.0, 2.0, 1.5) == 1.5


def test_sink_limit_stops_within_its_stated_error():
    """Two geometric terms (ratios 1/2.4 and 1/6): the ladder's limit lies within its stated
    error of the exact one."""
    exact = 0.0387

    def rates(j):
        return exact - 1e-4 * 2.4**-j + 3e-5 * 6.0**-j

    out = sink_limit(rates, max_rungs=12)
    assert abs(out["rate"] - exact) <= out["sink_error"]
    assert out["sink_error"] <= 1e-7 * exact


def test_rungs_sharpen():
    """Each rung halves the width, quadruples the strength and keeps the centre outside the
    bottoms (``(2 + j ln2/2) w_j`` past them)."""
    wells = (-0.95, 0.95)
    for j in range(5):
        (cl, cr), kap, w = sink_rung(wells, 20.0, 0.04, j)
        assert w == 0.04 / 2**j and kap == 20.0 * 4**j
        assert cr - 0.95 == pytest.approx((2 + j * math.log(2) / 2) * w)
        assert cl == -cr


def _other_ladder(mu, offset, rungs, nh=SINK_HERMITE, nc=SINK_INTERVALS):
    """The sink ladder centred ``offset`` widths past the bottoms, solved here with the
    pair's rungs (:class:`FractionRungs`) on its own points."""
    split = split_conservative("cdc", dict(PARAMS, mu=mu))
    D = KT * mu
    xl, xr = _saddles()
    sigma, wells, half, kappa0, width = escape_problem(split, D, (xl, xr))
    gamma = kT_gamma(split, D)[1]

    def rate(j):
        c, kap, w = sink_rung(wells, kappa0, width, j, offset=offset)

        def pts(m):
            return cheb_centred(m, half, ALPHA, (xl, xr) + c, (-xl / 2, xr / 2, 2.5 * w,
                                                                2.5 * w),
                                (0.0, 0.0, WEIGHT, WEIGHT))

        return FractionRungs(split, sigma, gamma, c, lambda xs, s=1: _sink(xs, c, kap, w),
                             pts).rate(nh, nc)

    return sink_limit(rate, max_rungs=rungs)


def test_small_ladder_rises_to_its_limit():
    """mu = 1 on a small grid (64 Hermite functions, 160 intervals; the default run's
    sibling of the slow tests below): the rungs rise, by steps that shrink by more than 2,
    and the extrapolation lies above the last rung by less than its last step."""
    out = _other_ladder(1.0, 2.0, 5, nh=64, nc=160)
    r = out["rungs"]
    steps = np.diff(r)
    assert np.all(steps > 0) and np.all(steps[1:] < steps[:-1] / 2)
    assert 0 < out["rate"] - r[-1] < steps[-1]


@pytest.fixture(scope="module")
def moderate():
    return kramers_escape("cdc", dict(PARAMS, mu=1), KT, _saddles())


@pytest.mark.slow
def test_moderate_friction_reaches_the_absorbing_limit(moderate):
    """mu = 1: the ladder ran, its stated sink error is below 1e-7 of the rate, and the
    rate lies above every rung (they rise toward the limit) by less than the last step."""
    fp = moderate
    r = fp.sink_ladder
    assert len(r) >= 4 and fp.sink_error <= 1e-7 * fp.rate
    assert all(b > a for a, b in zip(r, r[1:]))
    assert 0 < fp.rate - r[-1] < r[-1] - r[-2]
    assert fp.chebyshev_error < 1e-8 * fp.rate and fp.truncation_error < 1e-6 * fp.rate


@pytest.mark.slow
def test_moderate_friction_another_sink(moderate):
    """mu = 1: the ladder of sinks centred on the bottoms (rates falling from above, 3.4e-6
    above the limit at the first rung) extrapolates to the same limit within the two
    stated errors (3e-8 apart measured, 8e-8 stated for it)."""
    other = _other_ladder(1.0, 0.0, 7)
    assert all(b < a for a, b in zip(other["rungs"], other["rungs"][1:]))
    tol = moderate.sink_error + moderate.truncation_error + other["sink_error"]
    assert abs(other["rate"] - moderate.rate) <= tol


def _smoluchowski_rate(mu):
    """``1/T(0)``: Smoluchowski's mean first-passage time from the bottom to ``x = +-x_w``
    (reflecting at 0 by symmetry, Gardiner eq. 5.2.158), by adaptive quadrature."""
    g, _, G = split_conservative("cdc", dict(PARAMS, mu=mu)).numpy_functions()[:3]
    xw = brentq(lambda z: float(g(np.array(z))), 0.8, 1.1, xtol=1e-15)

    def inner(y):
        return quad(lambda z: math.exp(-float(G(np.array(z))) / KT), 0, y, epsabs=0,
                    epsrel=1e-12, limit=200)[0]

    T = quad(lambda y: math.exp(float(G(np.array(y))) / KT) * inner(y), 0, xw, epsabs=0,
             epsrel=1e-11, limit=200)[0] * mu / KT
    return 1.0 / T


@pytest.mark.slow
def test_high_friction_below_smoluchowski():
    """mu = 2 and 5 (gamma/omega_b = 0.48, 1.2): the rate (to first passage at ``x_w``)
    is below Smoluchowski's for the same line, and its ratio to it grows toward 1 with the
    friction (the inertial correction, O(omega_b^2/gamma^2) for large gamma); the stated
    sink error is at most 1e-5 of the rate (mu = 5: the ladder's last rungs still shrink
    by 2.4 per rung)."""
    ratios = []
    for mu in (2.0, 5.0):
        fp = kramers_escape("cdc", dict(PARAMS, mu=mu), KT * mu, _saddles())
        assert fp.sink_error <= 1e-5 * fp.rate
        ratios.append(fp.rate / _smoluchowski_rate(mu))
    assert ratios[0] < ratios[1] < 1
