"""The stationary Kramers route below mu = 0.01 (issue 36: "at any damping"): the SEDF at
rest, Delta = 3, beta = 1, D = mu/2, where six digits are beyond kbm noise's budget.

* The velocity scale's floor (:data:`numerics.fokker_planck._stationary_points.TOP_REACH`):
  at mu = 0.002 the resolution rule alone chose 0.136, whose 258 functions reach
  ``|v| = 3.1`` of a density that reaches 6.5, and <a^2> came out 3.669 (stated 0.14);
  the route must agree with the first-order energy-envelope averaging (an independent
  method whose error is O(mu)) and with a solve in another basis (another velocity scale
  and more functions) within its stated error.
* A hopeless check stops the ladder (:data:`._stationary_orthonormal.HOPELESS`): the
  climb is not made and the change is stated.
* What kbm noise says of such a solve (:func:`numerics.thermal._kramers_outputs.fp_advice`).
"""

from __future__ import annotations

import math

import pytest

from numerics.fokker_planck import stationary_kramers

SEDF = {"Delta": 3.0, "beta": 1.0, "Omega": 1.0, "lam": 1.0}


@pytest.mark.slow
def test_sedf_mu_0002_against_averaging_and_another_scale():
    """mu = 0.002, kbm noise's budget: <a^2> within 1e-3 of the first-order
    energy-envelope averaging (:func:`numerics.thermal.averaged.averaged_stationary`; its
    gap to the route falls like mu: 6.8e-4, 3.7e-4, 6e-5 at mu = 0.01, 0.005, 0.002),
    where the route without the scale's floor was 8 % low (3.669 against 4.005),
    and <x^2>, <v^2> within the stated error (which is above six digits: this friction is
    beyond the budget; above six digits the sum of the Hermite and grid changes) of an
    independent solve: 300 functions at the scale 0.82 times the route's (another basis)
    on 1100 intervals with the well's points (1.6e-4 from the route; 362 x 1200 at the
    scales 0.157 and 0.191 are 1.1e-4 to 1.4e-4 from it and agree to 4e-5)."""
    from numerics.thermal.averaged import averaged_stationary
    from numerics.noise.budget import FP_BUDGET

    mu = 0.002
    params = dict(SEDF, mu=mu)
    sol = stationary_kramers("sedf", params, mu / 2, basis="orthonormal", max_cost=FP_BUDGET)
    avg, why = averaged_stationary("sedf", params, mu / 2, 1.0)
    assert avg is not None, why
    assert sol.a2 == pytest.approx(avg.a2, rel=1e-3)
    assert 1e-6 < sol.hermite_change < 1e-2
    _assert_within_its_change(sol, params, 0.82, 300, 1100)


@pytest.mark.slow  # 3-4 s; kept out of the default run (five-minute rule)
def test_a_hopeless_check_stops_the_ladder():
    """With the velocity scale of the resolution rule alone at mu = 0.002 (0.136) and a
    tenth of kbm noise's budget, step 7's check (the rung up on the grid where the climb
    would start) moves the moments by more than ``HOPELESS``: the ladder stops there, on
    no grid beyond the budget and with no grid step kept for P(E), and states that change;
    the stop is justified: <a^2> is more than ``HOPELESS`` from the first-order averaging
    (an independent method, O(mu) = 1e-4 from the truth here), and the advice says the
    solve has no digits."""
    from numerics.fokker_planck._stationary_orthonormal import HOPELESS
    from numerics.thermal._kramers_outputs import fp_advice
    from numerics.thermal.averaged import averaged_stationary

    mu = 0.002
    params = dict(SEDF, mu=mu)
    sol = stationary_kramers("sedf", params, mu / 2, basis="orthonormal", max_cost=2.5e6,
                             sigma=0.136)
    assert sol.hermite_change > HOPELESS and sol.refine is None
    n, m = sol.coef.shape[0], sol.x.size - 1
    assert n * (m / 2) ** 2 <= 2.5e6
    avg, _ = averaged_stationary("sedf", params, mu / 2, 1.0)
    assert abs(sol.a2 - avg.a2) > HOPELESS * avg.a2
    rec = {"hermite_change": sol.hermite_change, "hermite": n, "chebyshev": m + 1}
    assert "about 0 digits" in fp_advice(rec, 2.5e6)


def test_advice_states_the_digits_and_the_least_sizes():
    """Beyond a stated 1e-5 the advice says how many digits the solve has and the least
    sizes six digits need (``ceil(log10(e/5e-7))`` steps of 2^(1/2) functions and of 1.25
    intervals, ``e`` each ladder's part of the stated error): e = 1.5e-4 on 258 x 1040
    with no grid part has about 3 digits and needs 3 steps of each, 730 x 2032 at the
    least; SEDF mu = 0.005's 1.8e-5, 1.5e-5 of it the grid's, needs one step of the
    functions and two of the grid; within a digit of six the earlier advice (1.4 times
    both).  It names ``kbm noise --fp-budget`` with the budget times the ratio of the costs
    ``N m^2`` of those sizes and the solve's (the least raise that affords them), not a
    Python call."""
    from numerics.thermal._kramers_outputs import fp_advice

    rec = {"hermite_change": 1.5e-4, "hermite": 258, "chebyshev": 1041}
    text = fp_advice(rec, 2.5e7)
    assert "about 3 digits" in text and "3 steps of the functions and 3 of the grid" in text
    assert "at least 730 x 2032" in text
    assert math.isclose(730 / 258, 2 ** 1.5, rel_tol=3e-3)
    assert math.isclose(2032 / 1040, 1.25**3, rel_tol=3e-3)
    low = fp_advice(dict(rec, hermite_change=1.8e-5, chebyshev_change=1.5e-5), 2.5e7)
    assert "about 4 digits" in low and "at least 364 x 1624" in low
    near = fp_advice(dict(rec, hermite_change=9e-6), 2.5e7)
    assert "about 362 x 1456" in near and "about 4 digits" not in near
    for advice, (n, m) in ((text, (730, 2032)), (low, (364, 1624)), (near, (362, 1456))):
        assert "stationary_kramers" not in advice and "max_cost" not in advice
        budget = float(advice.split("--fp-budget ")[1].split()[0])
        assert budget == pytest.approx(2.5e7 * n * m**2 / (258 * 1040**2), rel=0.05)
        assert budget > 2.5e7


@pytest.mark.slow
def test_sedf_mu_0005_six_digits_within_a_raised_budget():
    """mu = 0.005, D = 0.0025 with the budget kbm noise's advice names at its default
    (``--fp-budget 8.6e7``: 2.5e7 times the cost ratio of 364 x 1624 to the default's
    258 x 1040, stated 1.8e-5): the Hermite rung 258 moved the moments by 2.4e-6 against
    364 on the climb's coarser grid, so the rung 364 climbs in turn
    (:func:`numerics.fokker_planck._stationary_climb._climb_again`), and the stated error
    is below six digits; <x^2> and <v^2> lie within it of an independent finer solve, 456
    functions at 1.1 times the velocity scale (another basis, reaching farther and
    resolving the velocity as finely) on 1800 intervals with the well's points (the
    climb's 258 x 1544 was 2.4e-6 from it in <x^2>, 364 x 1544 5.6e-8)."""

    mu = 0.005
    params = dict(SEDF, mu=mu)
    sol = stationary_kramers("sedf", params, mu / 2, basis="orthonormal", max_cost=8.6e7)
    assert sol.coef.shape[0] >= 364 and sol.hermite_change < 1e-6
    _assert_within_its_change(sol, params, 1.1, 456, 1800)


def _assert_within_its_change(sol, params, scale: float, n_hermite: int, n_intervals: int):
    """``<x^2>`` and ``<v^2>`` of ``sol`` within its stated Hermite change of an independent
    solve: ``n_hermite`` functions at ``scale`` times its velocity scale on ``n_intervals``
    intervals with the well's points (another basis and grid)."""
    from kbm.model.conservative import split_conservative

    from numerics.fokker_planck._stationary_points import stationary_points
    from numerics.fokker_planck._stationary_solve import orthonormal_stationary

    mu = params["mu"]
    split = split_conservative("sedf", params)
    G = split.numpy_functions()[2]
    half = float(sol.x[0])
    s = scale * sol.sigma
    _, points = stationary_points(split, mu / 2, G, half, 2.4, s, well=True)
    other = orthonormal_stationary(split, mu / 2, s, half, n_hermite, n_intervals, G, 1.0,
                                   **points)
    for a, b in ((sol.x2, other.x2), (sol.v2, other.v2)):
        assert abs(a - b) <= sol.hermite_change * abs(b)
