"""numerics.cycles.sweep: input order kept, failed points reported (not raised), results equal to
one-by-one limit_cycle calls."""

from __future__ import annotations

import pytest

from numerics import grid, limit_cycle, sweep


def test_sweep_matches_single_cycles_and_reports_failures():
    """A grid over beta for the SEDF with beta = 0 (no cycle: the amplitude grows) in the
    middle: that point carries the NoCycleError message, the others equal limit_cycle,
    in input order, on two processes and with continuation between neighbours."""
    pts = grid(beta=[1.0, 0.0, 0.5, 0.25])
    out = sweep("sedf", pts, fixed={"mu": 0.2, "Delta": 0.05, "lam": 1}, workers=2,
                chunksize=2, progress=False)
    assert [p.params for p in out] == pts
    assert out[1].cycle is None and "grows without bound" in out[1].error
    for p in (out[0], out[2], out[3]):
        ref = limit_cycle("sedf", {"mu": 0.2, "Delta": 0.05, "lam": 1, **p.params})
        assert p.cycle.period == pytest.approx(ref.period, rel=1e-9)
        assert p.cycle.amplitude_first_harmonic == pytest.approx(ref.amplitude_first_harmonic,
                                                                 rel=1e-9)
