"""The escape rate's limit of a perfectly absorbing sink (:mod:`numerics.fokker_planck._sink`,
issue 36: the rate at any damping to 6 digits).

References, none produced by the sink ladder under test:

* the bracket of a rising and a falling sequence holds ``r`` for ``r - a q^j`` and ``r +
  b p^j`` (closed forms; hypothesis draws ``r``, ``a``, ``b``, ``q`` and ``p``);
* a third ladder of sinks, centred one width past the bottoms where the two ladders of the
  code are centred two widths past and (from the bottoms out to 1.6 widths) short of the
  critical offset: its top rung agrees with the rate within the stated errors and its own
  last step;
* the rates at the top rungs solved again in orthonormal Hermite functions at another
  velocity scale, sqrt 2 more of them, on 1.5 times the grid: the midpoint moves by less
  than the stated Chebyshev and truncation errors together;
* closed-form rungs (straight lines in the offset plus spectrally converging Hermite and
  grid errors): the adaptive rungs state errors that bound the true ones (hypothesis);
* the first sink's rate at low friction, where the sink does not matter (the ladder does
  not run there, so the rate is the one of the Hermite and Chebyshev ladders alone);
* Smoluchowski's mean first-passage time to ``x = +-x_w`` (Gardiner, *Handbook of
  Stochastic Methods*, eq. 5.2.158, by quadrature) times the friction, which the rate
  times the friction stays below at mu = 2 and 5 (Kramers' factor ``(gamma^2/4 +
  omega_b^2)^(1/2) - gamma/2 < omega_b^2/gamma``);
* the lowest eigenvalue of Smoluchowski's equation absorbing at ``x = +-x_w`` (Chebyshev
  collocation), the limit the rate times the friction approaches from below as the
  friction grows (mu = 20, 50; the reciprocal of the mean first passage from the bottom,
  above, is not that limit at E_b/kT = 3.1: the rate passes it by mu = 20);
* the pair's rungs unfolded, from a start of no parity: the folded rate to 1e-11 and an
  even slowest mode (hypothesis).

The CDC at rest (paper eq. 12), Delta = 3, lam = 1, kT = 0.35 (the issue's case: the next
wells' bottoms 1.65 kT under the saddles).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, example, given, settings, strategies as st
from scipy.integrate import quad
from scipy.optimize import brentq

from kbm.model.conservative import split_conservative
from numerics.fokker_planck import kramers_escape
from numerics.fokker_planck._bases import cheb_centred
from numerics.fokker_planck._rungs import FractionRungs
from numerics.fokker_planck._sink import (CAP, DRIFT, OFFSET, RAMP, SINK_HERMITE,
                                          SINK_INTERVALS, TRACK, WEIGHT, bracket_error,
                                          ladder_offsets, rung_intervals, sink_bracket,
                                          sink_grading, sink_rung, sink_scale, step_zero)
from numerics.fokker_planck.escape import ALPHA
from numerics.fokker_planck._problem import escape_problem, kT_gamma
from numerics.fokker_planck._sink_pairs import tanh_sink

PARAMS = {"Delta": 3, "lam": 1, "Omega": 1}
KT = 0.35


def _saddles():
    g = split_conservative("cdc", dict(PARAMS, mu=1)).numpy_functions()[0]
    xs = brentq(lambda z: float(g(np.array(z))), 0.3, 0.7, xtol=1e-15)
    return (-xs, xs)


@settings(max_examples=50, deadline=None)
@given(r=st.floats(-10, 10), a=st.floats(0.01, 10), b=st.floats(0.01, 10),
       q=st.floats(0.05, 0.9), p=st.floats(0.05, 0.9), n=st.integers(2, 8))
def test_bracket_holds_the_limit_of_a_rising_and_a_falling_sequence(r, a, b, q, p, n):
    """``r - a q^j`` rises and ``r + b p^j`` falls to ``r``: the midpoint of the last two
    terms lies within the stated error (half their gap) of ``r`` (closed form)."""
    low = [r - a * q**j for j in range(n)]
    high = [r + b * p**j for j in range(n)]
    err = bracket_error(low, high)
    assert err == pytest.approx((high[-1] - low[-1]) / 2)
    assert abs((low[-1] + high[-1]) / 2 - r) <= err * (1 + 1e-12) + 1e-15 * abs(r)


def test_a_broken_bracket_states_the_whole_gap_and_the_last_steps():
    """A lower ladder that falls (or crosses the upper one) brackets nothing: the error is
    the gap plus both last steps, larger than the distance to any limit between them."""
    assert bracket_error([1.0, 0.9], [1.2, 1.1]) == pytest.approx(0.2 + 0.1 + 0.1)
    assert bracket_error([1.0, 1.3], [1.2, 1.1]) == pytest.approx(0.2 + 0.3 + 0.1)


def test_sink_bracket_stops_within_its_stated_error():
    """Two geometric terms each side (ratios 1/2.4, 1/6 and 1/2.9; the ladders at fixed
    offsets): the bracket's rate lies within its stated error of the exact one, and the
    error reaches 1e-7 of it."""
    exact = 0.0387

    def rates(j, offset):
        if offset == OFFSET:
            return exact - 1e-4 * 2.4**-j + 3e-5 * 6.0**-j
        return exact + 2e-4 * 2.9**-j

    out = sink_bracket(rates, max_rungs=30,  # the falling ladder moves out to 1.6 widths
                       offsets=lambda history: (OFFSET, min(1.6, RAMP * len(history))))
    assert abs(out["rate"] - exact) <= out["sink_error"]
    assert out["sink_error"] <= 1e-7 * exact
    assert out["rungs"][-1] < exact < out["upper"][-1]


def _linear_model(r, a, o0, k):
    """The rates of rung ``j`` at the offset ``o``: ``r - a w_j (o - o0 - k j)``, ``w_j =
    2^-j`` (the module docstring's straight line with a critical offset growing by ``k``)."""
    return lambda j, o: r - a * 2.0**-j * (o - o0 - k * j)


@settings(max_examples=50, deadline=None)
@given(r=st.floats(0.01, 1.0), a=st.floats(1e-4, 1e-1), o0=st.floats(-1.0, 3.0),
       k=st.floats(0.0, 0.5), j=st.integers(0, 8), oa=st.floats(-1, 3), ob=st.floats(-1, 3))
def test_step_zero_is_the_critical_offset_one_rung_back(r, a, o0, k, j, oa, ob):
    """On the straight lines ``r - a w_j (o - o*_j)``, ``o*_j = o0 + k j`` (closed form), the
    rates of rungs ``j`` and ``j + 1`` are equal at ``o*_{j-1}``, whichever two offsets each
    rung was solved at."""
    if abs(oa - ob) < 0.05:
        return
    rate = _linear_model(r, a, o0, k)
    rungs = [(oa, ob, rate(i, oa), rate(i, ob)) for i in (j, j + 1)]
    assert step_zero(*rungs) == pytest.approx(o0 + k * (j - 1), abs=1e-6 * (1 + abs(o0)) / a)


@settings(max_examples=50, deadline=None)
@given(r=st.floats(0.01, 1.0), a=st.floats(1e-3, 1e-1), o0=st.floats(0.5, 2.5),
       k=st.floats(0.01, DRIFT))
def test_ladders_bracket_a_growing_critical_offset(r, a, o0, k):
    """Rates ``r - a w_j (o - o0 - k j)`` (a critical offset growing by ``k`` per rung, at
    most :data:`DRIFT`; closed form): from rung :data:`TRACK` on the rising ladder's offset
    lies past the critical offset of its rung and the falling ladder's short of it, the
    ladders are monotone from there, and the bracket holds ``r`` within its stated error."""
    rate = _linear_model(r, a, o0, k)
    history = []
    for j in range(12):
        o_low, o_high = ladder_offsets(history)
        if j >= TRACK:
            assert o_low > o0 + k * j > o_high
        history.append((o_low, o_high, rate(j, o_low), rate(j, o_high)))
    low = [h[2] for h in history[TRACK:]]
    high = [h[3] for h in history[TRACK:]]
    err = bracket_error(low, high)
    assert err == pytest.approx((high[-1] - low[-1]) / 2)
    assert abs((low[-1] + high[-1]) / 2 - r) <= err * (1 + 1e-9)


@settings(max_examples=50, deadline=None)
@given(r=st.floats(0.01, 1.0), a=st.floats(1e-3, 1e-1), o0=st.floats(0.6, 1.0),
       k=st.floats(0.01, 0.18))
def test_falling_ladder_stops_short_of_a_near_critical_offset(r, a, o0, k):
    """Rates ``r - a w_j (o - o0 - k j)`` with a critical offset near the ramp ``RAMP j``
    (closed form; CDC mu = 20 and 50 measured 0.9-1.3 over the first rungs, where the ramp
    reached it at the fifth rung and the falling ladder rose): from rung :data:`CAP` on
    the falling ladder stops short of the critical offset, so at every rung it lies short
    of it and the rising one past it, both ladders are monotone from the first rung, and
    the bracket holds ``r`` within its stated error."""
    rate = _linear_model(r, a, o0, k)
    history = []
    for j in range(12):
        o_low, o_high = ladder_offsets(history)
        assert o_low > o0 + k * j > o_high
        if j < TRACK:  # the ramp, capped from rung CAP on
            assert o_high <= RAMP * j and (o_high == RAMP * j or j >= CAP)
        history.append((o_low, o_high, rate(j, o_low), rate(j, o_high)))
    low, high = [h[2] for h in history], [h[3] for h in history]
    assert all(b > a_ for a_, b in zip(low, low[1:]))
    assert all(b < a_ for a_, b in zip(high, high[1:]))
    err = bracket_error(low, high)
    assert err == pytest.approx((high[-1] - low[-1]) / 2)
    assert abs((low[-1] + high[-1]) / 2 - r) <= err * (1 + 1e-9)


def test_rungs_sharpen():
    """Each rung halves the width, quadruples the strength and keeps the centre outside the
    bottoms (``(2 + j ln2/2) w_j`` past them)."""
    wells = (-0.95, 0.95)
    for j in range(5):
        (cl, cr), kap, w = sink_rung(wells, 20.0, 0.04, j)
        assert w == 0.04 / 2**j and kap == 20.0 * 4**j
        assert cr - 0.95 == pytest.approx((2 + j * math.log(2) / 2) * w)
        assert cl == -cr


def test_falling_offsets_and_rung_grids():
    """The falling ladder starts on the bottoms and moves out by RAMP per rung (the rule
    before TRACK); the rungs' grids are even and never shrink.  (The histories: rates of a
    critical offset ``2.5 + 0.1 j`` (closed form), past the ramp, which the cap from rung
    :data:`CAP` leaves alone; the early cap: the test below, a critical offset near the
    ramp.)"""
    rate = _linear_model(0.04, 1e-3, 2.5, 0.1)
    history = []
    for j in range(TRACK):
        o_low, o_high = ladder_offsets(history)
        history.append((o_low, o_high, rate(j, o_low), rate(j, o_high)))
    assert [h[:2] for h in history] == [(OFFSET, RAMP * j) for j in range(TRACK)]
    grids = [rung_intervals(280, j) for j in range(12)]
    assert grids[0] == 280 and all(n % 2 == 0 for n in grids)
    assert all(b >= a for a, b in zip(grids, grids[1:]))


def test_rung_points_scales_and_grids():
    """The rungs of linear damping (h-sink5): the points crowd at the sink from ``2.5 w_j``
    out on four-fold scales up to about a third of the first sink's width (``4^i <=
    2^j/8``), one scale up to rung 4, five by rung 11; the shares
    fall from 0.25 to 0.1; the velocity scale is 0.6 sqrt(kT) below rung 9 and 0.5 from
    it; the grid steps up 1.4 times at rungs 7, 9, 12 and 14 (200, 280, 392, 470, 548)."""
    for j in range(16):
        grading = sink_grading(j)
        widths = [f for f, _ in grading]
        assert widths[0] == 2.5 and all(b == 4 * a for a, b in zip(widths, widths[1:]))
        assert widths[-1] / 2.5 <= max(1.0, 2.0**j / 8) < 4 * widths[-1] / 2.5
        assert [q for _, q in grading][:4] == [0.25, 0.2, 0.15, 0.1][:len(grading)]
        assert sink_scale(j) == (0.6 if j < 9 else 0.5)
    assert len(sink_grading(4)) == 1 and len(sink_grading(11)) == 5
    grids = [rung_intervals(200, j) for j in range(16)]
    assert sorted(set(grids)) == [200, 280, 392, 470, 548]
    assert [grids.index(n) for n in (280, 392, 470, 548)] == [7, 9, 12, 14]


@settings(max_examples=30, deadline=None)
@given(r=st.floats(0.01, 1.0), a=st.floats(1e-3, 1e-1), o0=st.floats(0.6, 1.2),
       k=st.floats(0.05, 0.15), bh=st.floats(1e-4, 1e-2), lh=st.floats(15.0, 30.0),
       bg=st.floats(1e-4, 1e-1), lg=st.floats(20.0, 60.0))
@example(r=1.0, a=0.0625, o0=1.0, k=0.125, bh=0.009765625, lh=30.0, bg=0.0625, lg=20.0)
def test_adaptive_rungs_state_their_errors(r, a, o0, k, bh, lh, bg, lg):
    """:func:`absorbing_limit` with ``adaptive`` on closed-form rungs: the straight lines
    ``r - a w_j (o - o0 - k j)`` plus a Hermite error ``bh r exp(-n/lh)`` and a grid error
    ``bg r exp(-nc/lg)`` (spectral convergence; the grid's at least three times smaller
    per 1.25 times the intervals).  The truncation grows until its change is within
    HERMITE_TOL, the rate lies within the stated sink, grid and truncation errors of
    ``r``, and each stated discretisation error bounds the true one of the midpoint.

    The slope is at least a hundredth of the rate (the physical ones are about half of it:
    CDC mu = 10, ``tanh_sink``'s docstring): the ladders' placement measures the critical offset
    from the steps between rungs, and where the sink's signal ``a w_j`` is not much larger
    than the rung-to-rung changes of the discretisation errors that measure fails (found by
    this test in a CI run: ``r`` = 0.375, ``a`` = 1e-3, ``k`` = 0.125, ``bh`` = 0.0039, ``lh``
    = 15: both top rungs fell short of the critical offset, by 0.005 widths, and the
    midpoint was 3.5 % of the sink error past its half-gap).  The truncation stops short of
    HERMITE_TOL only where its next size, ``sqrt 2`` more, would pass MAX_HERMITE (a CI draw:
    514 functions, whose next size 726 is past 724)."""
    from numerics.fokker_planck._sink import HERMITE_TOL, MAX_HERMITE, _up, absorbing_limit

    assume(a >= 0.01 * r)

    def rung(j, o, nc, nh):
        return (r - a * 2.0**-j * (o - o0 - k * j) + bh * r * math.exp(-nh / lh)
                + bg * r * math.exp(-nc / lg))

    out = dict(rate=r, sink_error=1.0, chebyshev_error=0.0, truncation_error=0.0,
               hermite=64, chebyshev=129)
    res = absorbing_limit(out, rung, adaptive=True)
    nh, nc = res["hermite"], res["chebyshev"] - 1
    assert bh * r * (math.exp(-nh / math.sqrt(2) / lh) - math.exp(-nh / lh)) <= 1.01 * (
        HERMITE_TOL * r) or _up(nh) > MAX_HERMITE  # the next truncation past the cap
    eps = 1e-13 * r  # the rounding of the rates' differences
    assert bh * r * math.exp(-nh / lh) <= res["truncation_error"] + eps
    assert bg * r * math.exp(-nc / lg) <= res["chebyshev_error"] + eps
    total = res["sink_error"] + res["chebyshev_error"] + res["truncation_error"]
    assert abs(res["rate"] - r) <= total * (1 + 1e-9) + eps


@settings(max_examples=30, deadline=None)
@given(r=st.floats(0.01, 1.0), a=st.floats(1e-3, 1e-1), o0=st.floats(0.6, 1.2),
       k=st.floats(0.05, 0.15))
@example(r=0.75, a=0.0625, o0=1.2, k=0.15)
def test_loose_stop_from_its_rung(r, a, o0, k):
    """``loose = (tol2, j2)``: on closed-form straight lines the ladders stop at the first
    rung from ``j2`` on whose half-gap is within ``tol2`` of the rate (else at ``tol``).  The
    example: rungs 5 and 6 of the rising ladder equal but for one ulp (0.74990234375,
    0.7499023437499999), once read as a reversal."""
    rate = _linear_model(r, a, o0, k)
    strict = sink_bracket(rate, tol=1e-9, max_rungs=20)
    loose = sink_bracket(rate, tol=1e-9, max_rungs=20, loose=(1e-5, 9))
    gaps = [(h - lo) / 2 for lo, h in zip(strict["rungs"], strict["upper"])]
    want = next((j for j in range(9, len(gaps))
                 if gaps[j] <= 1e-5 * (strict["rungs"][j] + strict["upper"][j]) / 2),
                len(gaps) - 1)
    assert len(loose["rungs"]) == min(want, len(strict["rungs"]) - 1) + 1


def _six_digit_rates(mus, ratio) -> list:
    """The CDC escape at each friction of ``mus`` with its bracket, a total stated error
    within 1e-6 of the rate and the independent top rungs within the stated Chebyshev and
    truncation errors (:func:`_independent_top`); ``ratio(fp, mu)`` of each, to compare
    with its high-friction limit."""
    ratios = []
    for mu in mus:
        fp = kramers_escape("cdc", dict(PARAMS, mu=mu), KT * mu, _saddles())
        _assert_bracket(fp, 1e-6)
        assert fp.sink_error + fp.chebyshev_error + fp.truncation_error <= 1e-6 * fp.rate
        assert (abs(_independent_top(fp, mu) - fp.rate)
                < fp.chebyshev_error + fp.truncation_error)
        ratios.append(ratio(fp, mu))
    return ratios


def _other_ladder(mu, offset, rungs, nh=SINK_HERMITE, nc=SINK_INTERVALS):
    """The rates of the sink ladder centred ``offset (+ j ln2/2)`` widths past the bottoms,
    solved here with the pair's rungs (:class:`FractionRungs`) on its own points."""
    split = split_conservative("cdc", dict(PARAMS, mu=mu))
    D = KT * mu
    xl, xr = _saddles()
    sigma, wells, half, kappa0, width = escape_problem(split, D, (xl, xr))
    gamma = kT_gamma(split, D)[1]

    def rate(j, nc=nc):
        c, kap, w = sink_rung(wells, kappa0, width, j,
                              offset=offset(j) if callable(offset) else offset)

        def pts(m):
            return cheb_centred(m, half, ALPHA, (xl, xr) + c, (-xl / 2, xr / 2, 2.5 * w,
                                                                2.5 * w),
                                (0.0, 0.0, WEIGHT, WEIGHT))

        return FractionRungs(split, sigma, gamma, c, lambda xs, s=1: tanh_sink(xs, c, kap, w),
                             pts).rate(nh, nc)

    if isinstance(rungs, int):
        return [rate(j) for j in range(rungs)]
    return [rate(j, n) for j, n in rungs]  # (rung, intervals) pairs


def test_small_ladders_bracket_their_limit():
    """mu = 1 on a small grid (64 Hermite functions, 160 intervals; the default run's
    sibling of the slow tests below): the ladder centred two widths out rises, the one
    centred on the bottoms falls, and the first stays below the second (the bracket)."""
    low = _other_ladder(1.0, 2.0, 5, nh=64, nc=160)
    high = _other_ladder(1.0, 0.0, 5, nh=64, nc=160)
    for r, sign in ((low, 1), (high, -1)):
        steps = sign * np.diff(r)
        assert np.all(steps > 0)
    assert low[-1] < high[-1]


@pytest.fixture(scope="module")
def moderate():
    return kramers_escape("cdc", dict(PARAMS, mu=1), KT, _saddles())


@pytest.mark.slow
def test_moderate_friction_reaches_the_absorbing_limit(moderate):
    """mu = 1: the ladders ran, the rising one below the falling one, the rate between
    their top rungs, and the stated sink error (half the gap) within half a unit of the
    sixth significant digit (5e-6 of the rate; 2.8e-7 measured, the issue's target 1e-6)."""
    fp = moderate
    n = len(fp.sink_ladder) // 2
    low, high = fp.sink_ladder[:n], fp.sink_ladder[n:]
    assert n >= 2 and fp.sink_error <= 1e-6 * fp.rate
    assert all(b > a for a, b in zip(low, low[1:]))
    assert all(b < a for a, b in zip(high, high[1:]))
    assert low[-1] <= fp.rate <= high[-1]
    assert fp.chebyshev_error < 1e-8 * fp.rate and fp.truncation_error < 1e-6 * fp.rate


@pytest.mark.slow
def test_moderate_friction_another_sink(moderate):
    """mu = 1: a third ladder, centred one width past the bottoms (solved by the pair's
    rungs on its own points, ten rungs on the pair's grids with 362 Hermite functions: at
    the seventh its steps still fell only 1.7 times per rung, so its last step understated
    its distance to the limit; with the pair's 256 functions its tenth rung is 1.3e-7 of the
    rate high, more than the rate's stated errors since h-sink5), ends within the stated
    errors and its own last step of the rate."""
    other = _other_ladder(1.0, 1.0, [(j, rung_intervals(SINK_INTERVALS, j)) for j in range(10)],
                          nh=362)
    tol = (moderate.sink_error + moderate.truncation_error + moderate.chebyshev_error
           + abs(other[-1] - other[-2]))
    assert abs(other[-1] - moderate.rate) <= tol


def _assert_bracket(fp, bound: float) -> None:
    """The rising ladder rises, the falling one falls, the rate lies between their top rungs
    and the stated sink error is half their gap (no broken bracket), within ``bound`` of the
    rate."""
    n = len(fp.sink_ladder) // 2
    low, high = fp.sink_ladder[:n], fp.sink_ladder[n:]
    assert all(b > a for a, b in zip(low, low[1:]))
    assert all(b < a for a, b in zip(high, high[1:]))
    assert low[-1] <= fp.rate <= high[-1]
    assert fp.sink_error == pytest.approx((high[-1] - low[-1]) / 2)
    assert fp.sink_error <= bound * fp.rate


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
    friction (the inertial correction, O(omega_b^2/gamma^2) for large gamma); the rate lies
    between the two ladders' top rungs, the rising one below the falling one, and the total
    stated error (half their gap, the grid's and the truncation's) is within 1e-6 of the
    rate (measured 7.6e-7 at mu = 2 and 9.5e-7 at mu = 5, where h-sink4 stated 1.9e-6 and
    5.2e-6); the midpoint of the top rungs solved again (orthonormal functions at another
    velocity scale, :func:`_independent_top`) on 1.5 times the grid with sqrt 2 more
    Hermite functions moves by less than the stated Chebyshev and truncation errors
    together (measured, relative to the rate: 7.1e-10 against 8.6e-9 at mu = 2, 4.9e-8
    against 7.8e-8 at mu = 5)."""
    ratios = _six_digit_rates((2.0, 5.0), lambda fp, mu: fp.rate / _smoluchowski_rate(mu))
    assert ratios[0] < ratios[1] < 1


def _independent_top(fp, mu, scale=0.55):
    """The midpoint of the top rungs of both ladders solved again in orthonormal Hermite
    functions at another velocity scale (``scale sqrt(kT)``; the code's is
    :func:`sink_scale`, 0.5 at the top rungs) with ``sqrt 2`` more of them, on 1.5 times the
    grid (folded, :class:`._folded.FoldedRungs`; the points crowded at the sink on the
    scales of :func:`sink_grading`)."""
    from numerics.fokker_planck._folded import FoldedRungs

    top = len(fp.sink_offsets) - 1
    n_c, n_h = 2 * round(0.75 * (fp.chebyshev - 1)), 2 * round(fp.hermite / math.sqrt(2))
    split = split_conservative("cdc", dict(PARAMS, mu=mu))
    xl, xr = _saddles()
    _, wells, half, kappa0, width = escape_problem(split, KT * mu, (xl, xr))
    grading = sink_grading(top)
    rates = []
    for offset in fp.sink_offsets[top]:
        c, kap, w = sink_rung(wells, kappa0, width, top, offset)

        def pts(m, c=c, w=w):
            return cheb_centred(m, half, ALPHA, (xl, xr) + c * len(grading),
                                (-xl / 2, xr / 2) + tuple(f * w for f, _ in grading
                                                         for _ in (0, 1)),
                                (0.0, 0.0) + tuple(q for _, q in grading for _ in (0, 1)))

        rates.append(FoldedRungs(n_h)(split, KT * mu, scale * math.sqrt(KT), pts, n_h, n_c,
                                      lambda xs, c=c, kap=kap, w=w: tanh_sink(xs, c, kap, w)))
    return sum(rates) / 2


@pytest.mark.slow
def test_highest_friction_bracket_holds():
    """mu = 10 (gamma/omega_b = 2.4; the critical offset grows by 0.1 per rung, past
    h-sink2's falling ladder at 1.6 from the seventh rung): the rising ladder rises, the
    falling one falls, the rate lies between their top rungs and the stated sink error is
    half their gap (no broken bracket), the total stated error within 1e-6 of the rate
    (7.3e-7 measured; h-sink4 6e-6); the midpoint of the top rungs solved independently
    (:func:`_independent_top`: 1.5 times the grid, sqrt 2 more Hermite functions at another
    velocity scale) moves by less than the stated Chebyshev and truncation errors together
    (2.8e-9 against 5.8e-8 of the rate)."""
    mu = 10.0
    fp = kramers_escape("cdc", dict(PARAMS, mu=mu), KT * mu, _saddles())
    _assert_bracket(fp, 1e-6)
    assert fp.sink_error + fp.chebyshev_error + fp.truncation_error <= 1e-6 * fp.rate
    assert abs(_independent_top(fp, mu) - fp.rate) < fp.chebyshev_error + fp.truncation_error


@settings(max_examples=12, deadline=None)
@given(mu=st.floats(0.5, 50.0), kT=st.floats(0.25, 0.5), offset=st.floats(0.0, 2.0),
       j=st.integers(0, 3))
def test_pair_rungs_folded_equal_unfolded(mu, kT, offset, j):
    """The rungs of Risken's pair (:class:`._fraction.EscapeFraction`, what
    :class:`FractionRungs` solves for the sink ladders) folded onto ``x >= 0`` give the
    unfolded slowest rate to 1e-11, and the unfolded slowest mode is even under ``(x, v)
    -> (-x, -v)``, ``c_n(-x) = (-1)^n c_n(x)`` (the symmetry of an even potential with
    the sinks at both next wells; the quasi-stationary density is the operator's positive
    principal mode, unique, and its reflection is another, so it is invariant).  CDC
    Delta = 3 on 40 intervals, 24 Hermite functions."""
    from numerics.fokker_planck._blocks import one_blas_thread
    from numerics.fokker_planck._fraction import EscapeFraction

    split = split_conservative("cdc", dict(PARAMS, mu=mu))
    xl, xr = _saddles()
    sigma, wells, half, kappa0, width = escape_problem(split, kT * mu, (xl, xr))
    c, kap, w = sink_rung(wells, kappa0, width, j, offset)
    x, Dx = cheb_centred(40, half, ALPHA, (xl, xr) + c, (-xl / 2, xr / 2, 2.5 * w, 2.5 * w),
                         (0.0, 0.0, WEIGHT, WEIGHT))
    assert np.array_equal(x, -x[::-1])
    g = np.asarray(split.numpy_functions()[0](x), float)
    rates, modes = [], []
    with one_blas_thread():
        for fold in (True, False):
            frac = EscapeFraction(Dx, g, tanh_sink(x, c, kap, w), math.sqrt(kT), mu, 24, fold)
            # unfolded: from a start of no parity (c_0 = 1 would keep Arnoldi in the even
            # sector), so the mode found is the slowest of the whole operator
            rng = np.random.default_rng(j)
            rates.append(frac.slowest(tol=1e-14, start=None if fold else [
                rng.standard_normal(x.size) for _ in range(24)]))
            modes.append(frac.mode)
    assert rates[0] == pytest.approx(rates[1], rel=1e-11, abs=0)
    assert modes[1] is not None
    if True:
        top = max(float(np.max(np.abs(cn))) for cn in modes[1])
        for n, cn in enumerate(modes[1]):
            assert np.max(np.abs(cn[::-1] - (-1) ** n * cn)) <= 1e-8 * top


def _smoluchowski_eigenvalue(n=80):
    """``gamma`` times the lowest eigenvalue of Smoluchowski's equation ``P_t = (1/gamma)
    d/dx (G' P + kT P_x)`` on ``[-x_w, x_w]``, absorbing at both ends (the spatial-diffusion
    limit of the Kramers equation, Risken ch. 5 and sec. 10.4; Gardiner sec. 5.2), by
    Chebyshev collocation on ``n`` intervals, checked against ``3 n/4``."""
    from numerics.fokker_planck._bases import cheb

    g = split_conservative("cdc", dict(PARAMS, mu=1)).numpy_functions()[0]
    xw = brentq(lambda z: float(g(np.array(z))), 0.8, 1.1, xtol=1e-15)
    out = []
    for m in (3 * n // 4, n):
        x, Dm = cheb(m, xw)
        A = -(Dm @ (np.diag(np.asarray(g(x), float)) + KT * Dm))[1:-1, 1:-1]
        ev = np.linalg.eigvals(A)
        out.append(float(np.min(ev.real[np.abs(ev.imag) < 1e-9])))
    assert out[0] == pytest.approx(out[1], rel=1e-9)
    return out[1]


@pytest.mark.slow
def test_overdamped_bracket_holds_below_smoluchowski():
    """mu = 20 and 50 (gamma/omega_b = 4.7, 12; the critical offset 0.9-1.3 widths over the
    first rungs, where h-sink3's falling ladder, at ``RAMP j`` up to the sixth rung, passed
    it and rose: 4.0e-5 stated at mu = 20): both ladders are monotone, the rate lies
    between their top rungs and the stated sink error is half their gap, the total stated
    error within 1e-6 of the rate (7.8e-7 both measured; h-sink4 8e-6 and 1.1e-5);
    the midpoint of the top rungs solved independently (:func:`_independent_top`: 1.5
    times the grid, sqrt 2 more Hermite functions at another velocity scale) moves by less
    than the stated Chebyshev and truncation errors together (1.4e-9 against 1.7e-8, 8.8e-10
    against 1.7e-9 of the rate); and the rate times the friction is below the lowest eigenvalue of the
    Smoluchowski equation absorbing at ``x = +-x_w`` (:func:`_smoluchowski_eigenvalue`),
    its ratio to it growing toward 1 with the friction (measured 0.9581 and 0.9882; the
    inertial correction and the absorbing line's Milne layer both lower the rate).  Not
    ``1/T(0)`` (:func:`_smoluchowski_rate`): at E_b/kT = 3.1 the mean first passage from
    the bottom is longer than from the quasi-stationary density, whose exit rate the
    eigenvalue is, so the rate passes ``1/T(0)`` (3 % above it at mu = 20)."""
    ratios = _six_digit_rates((20.0, 50.0),
                              lambda fp, mu: fp.rate * mu / _smoluchowski_eigenvalue())
    assert 0.95 < ratios[0] < ratios[1] < 1
