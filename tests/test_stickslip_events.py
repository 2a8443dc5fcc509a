"""Slip events located on the dense output, not read off the output grid (issue 16, item 4).

The CDC slider at Delta = 3, v = 0.01 settles after its first slip on a periodic
stick-slip: three wells per slip, one slip per 3 lam/v = 300 time units, each
slip lasting 87.7704 (|x'| above the threshold).  With the events read off the
output grid (dt = 0.314) the printed durations differed by up to 1.57.
"""

from __future__ import annotations

import pytest

from kbm.errors import ParameterError
from numerics import analyze, slide
from numerics.sliding.reference import MAX_PERIODS


@pytest.fixture(scope="module")
def periodic_run():
    return slide("cdc", {"Delta": 3.0, "v": 0.01}, t_end=1300.0)


@pytest.fixture(scope="module")
def periodic_cdc(periodic_run):
    return analyze(periodic_run)


def test_periodic_cdc_slip_durations_agree_to_1e6(periodic_cdc):
    slips = [s for s in periodic_cdc.slips if s.complete][1:]  # after the first (transient)
    assert len(slips) >= 2
    durations = [s.t_end - s.t_start for s in slips]
    assert max(durations) - min(durations) < 1e-6
    assert durations[0] == pytest.approx(87.7704, abs=1e-4)


def test_periodic_cdc_slips_start_every_three_wells_over_v(periodic_cdc):
    starts = [s.t_start for s in periodic_cdc.slips][1:]
    gaps = [b - a for a, b in zip(starts, starts[1:])]
    assert all(abs(g - 300.0) < 1e-6 for g in gaps)
    assert all(s.wells == 3 for s in periodic_cdc.slips[1:])


def test_slip_cut_by_the_end_of_the_run_is_marked_incomplete(periodic_cdc):
    last = periodic_cdc.slips[-1]
    assert not last.complete and last.t_end == 1300.0
    assert last.to_json()["complete"] is False


def test_event_time_is_a_threshold_crossing_of_the_dense_output(periodic_run, periodic_cdc):
    """Every slip's start (and a complete slip's end) is where |x'| of the dense output
    crosses the threshold, to 1e-9: on the module's run to t = 1300 (four slips, the last
    cut by the end), not a run of its own to t = 700 (the first two, the second cut)."""
    r, a = periodic_run, periodic_cdc
    vth = 0.05  # max(5 v, 0.02 Omega lam)
    for s in a.slips:
        assert abs(abs(r.sol.sol(s.t_start)[1]) - vth) < 1e-9
        if s.complete:
            assert abs(abs(r.sol.sol(s.t_end)[1]) - vth) < 1e-9


def test_run_longer_than_the_bound_is_refused_naming_the_limit():
    with pytest.raises(ParameterError, match=f"the limit is {MAX_PERIODS}"):
        slide("cdc", {"Delta": 3.0, "v": 0.01}, t_end=1e7)
