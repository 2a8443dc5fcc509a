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


def test_sweep_gives_the_same_bytes_on_every_executor():
    """Issue 21: the chunking followed the worker count and each chunk continued its Newton
    guesses, so workers=1 and Dask differed in the last digits (6.318443203454227 against
    6.318443203454231 at mu = 0.3).  Chunks are now cut by the data: this process, the
    local pool (2 workers), a thread pool and a Dask LocalCluster give identical bytes."""
    from concurrent.futures import ThreadPoolExecutor

    distributed = pytest.importorskip("distributed")
    pts = grid(mu=[0.1, 0.3, 0.5, 1.0, 2.0])

    def run(**kw):
        out = sweep("vdp", pts, progress=False, **kw)
        return repr([(p.params, p.cycle.period, p.cycle.amplitude_max,
                      tuple(p.cycle.floquet_multipliers)) for p in out])

    serial = run(workers=1)
    assert run(workers=2) == serial
    with ThreadPoolExecutor(2) as pool:
        assert run(executor=pool) == serial
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        assert run(executor=client) == serial
