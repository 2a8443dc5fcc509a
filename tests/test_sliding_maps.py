"""Friction maps on any executor (issue 12, item 4): the same numbers in the same order on the
local process pool, in this process and on a Dask cluster; failures stay with their point;
bad input is refused with a message, an unreachable scheduler within a bounded time."""

from __future__ import annotations

import json
import time
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

from kbm.output.strict_json import finite
from numerics.cli import main
from numerics.errors import NumericsError
from numerics.executor import SchedulerError, chunk, connect, map_chunks
from numerics.sliding.friction_records import FrictionSettings
from numerics.sliding.maps import compare_sliders, friction_map

FAST = FrictionSettings(slips=4, sliding_wells=10)
FIXED = {"mu": 0.1, "lam": 1.0, "beta": 1.0}
AXES = {"v": np.geomspace(0.05, 3.0, 10), "Delta": np.linspace(0.5, 3.0, 10)}


def _dump(m) -> str:
    return json.dumps(finite(m.to_json()), sort_keys=True)


def _square(c):
    return [i * i for i in c]


def _fails_on_three(c):
    if 3 in c:
        raise RuntimeError("chunk with 3 lost")
    return list(c)


def test_chunks_keep_order_and_cover_everything():
    items = list(range(23))
    parts = chunk(items)
    assert [i for c in parts for i in c] == items and max(map(len, parts)) <= 64
    assert chunk(items, size=5)[-1] == [20, 21, 22]


def test_chunks_are_cut_by_the_data_alone():
    """Issue 21: the cut depends on the number of points only (no worker count to pass)."""
    assert [len(c) for c in chunk(list(range(100)))] == [7] * 14 + [2]
    assert [len(c) for c in chunk(list(range(5000)))] == [64] * 78 + [8]
    with pytest.raises(NumericsError, match="integer >= 1"):
        chunk([1, 2], size=0)


@pytest.mark.parametrize("make", [None, lambda: ThreadPoolExecutor(3)])
def test_map_chunks_in_input_order_and_failures_per_chunk(make):
    ex = make() if make else None
    try:
        parts = chunk(list(range(40)), size=3)
        assert map_chunks(_square, parts, executor=ex, workers=2) == [i * i for i in range(40)]
        out = map_chunks(_fails_on_three, parts, executor=ex, workers=2,
                         on_error=lambda c, exc: [f"lost: {exc}"] * len(c))
        assert out[:3] == [0, 1, 2] and out[3:6] == ["lost: chunk with 3 lost"] * 3
        assert out[6:] == list(range(6, 40))
        with pytest.raises(RuntimeError, match="chunk with 3 lost"):
            map_chunks(_fails_on_three, parts, executor=ex, workers=2)
    finally:
        if ex is not None:
            ex.shutdown()


def test_dask_and_the_local_pool_give_identical_maps():
    """A 10 x 10 (v, Delta) map of the stage-attached SEDF: this process, the local pool and
    a Dask LocalCluster give the same bytes, in grid order."""
    distributed = pytest.importorskip("distributed")
    serial = friction_map("sedf_comoving", FIXED, AXES, settings=FAST, workers=1, progress=False)
    pool = friction_map("sedf_comoving", FIXED, AXES, settings=FAST, workers=2, progress=False)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        dask = friction_map("sedf_comoving", FIXED, AXES, settings=FAST, executor=client,
                            progress=False)
    assert serial.shape == (10, 10) and not serial.failures
    assert _dump(serial) == _dump(pool) == _dump(dask)
    v = [p.params["v"] for p in dask.points]
    assert v == [float(a) for a in np.repeat(AXES["v"], 10)]


@pytest.mark.slow  # 4-8 s; kept out of the default run (five-minute rule)
def test_a_scheduler_address_runs_the_map_as_the_command_line_does():
    """``--scheduler ADDRESS``: :func:`connect` makes a client that is not the default one
    (as on the command line); the map runs on it and equals the local result."""
    distributed = pytest.importorskip("distributed")
    axes = {"v": [0.5, 3.0]}
    local = friction_map("cdc", {"mu": 0.1, "lam": 1.0, "Delta": 3.0}, axes, settings=FAST,
                         workers=1, progress=False)
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        client = connect(cluster.scheduler_address, timeout=10)
        try:
            remote = friction_map("cdc", {"mu": 0.1, "lam": 1.0, "Delta": 3.0}, axes,
                                  settings=FAST, executor=client, progress=False)
        finally:
            client.close()
    assert _dump(remote) == _dump(local)


def test_a_failing_point_keeps_its_error_and_the_rest_stand():
    """mu = 1e-9 needs a transient of 1e10 time units (10/mu): that point reports it; the
    other point is measured."""
    m = friction_map("cdc", {"Delta": 3.0, "lam": 1.0}, {"v": [3.0], "mu": [0.1, 1e-9]},
                     settings=FAST, workers=1, progress=False)
    ok, bad = m.points
    assert ok.ok and ok.regime == "smooth sliding"
    assert not bad.ok and "transient" in bad.error and np.isnan(bad.mean_force)
    assert len(m.failures) == 1


def test_the_cdc_ignores_the_sedf_beta_axis_and_computes_each_point_once():
    comp = compare_sliders({"mu": 0.1, "lam": 1.0, "Delta": 1.5},
                           {"v": [0.5, 2.0], "beta": [0.5, 1.0, 2.0]}, settings=FAST, workers=1,
                           progress=False)
    cdc = comp.second.field("mean_force")
    assert np.all(cdc[:, 0:1] == cdc)  # the same state whatever beta
    assert comp.force_ratio.shape == (2, 3)
    assert set(comp.summary()) >= {"compared", "first_better", "steady"}


def test_unreachable_scheduler_is_reported_within_the_timeout():
    pytest.importorskip("distributed")
    t0 = time.perf_counter()
    with pytest.raises(SchedulerError, match="no Dask scheduler answered at tcp://127.0.0.1:9"):
        connect("tcp://127.0.0.1:9", timeout=2)
    assert time.perf_counter() - t0 < 15


def test_cli_json_keys(capsys, tmp_path):
    """``kbm friction MODEL --vary ... --json --out DIR``: the keys of issue 12, per point;
    standard output is the JSON alone (the figure's path goes to standard error)."""
    assert main(["friction", "cdc", "-p", "Delta=3", "--vary", "v=2,4", "--workers", "1",
                 "--json", "--out", str(tmp_path)]) == 0
    data = json.loads(capsys.readouterr().out)
    for key in ("axes", "mean_force", "static_force", "dissipation_per_distance",
                "stuck_fraction", "regime"):
        assert key in data
    assert data["axes"] == {"v": [2.0, 4.0]} and data["regime"] == ["smooth sliding"] * 2
    assert data["static_force"] == [None, None]  # no stick: no static friction
    assert (tmp_path / "friction_law_cdc.png").exists()


@pytest.mark.parametrize("argv, words", [
    (["--vary", "v=0:1:log4"], "log range needs FROM, TO > 0"),
    (["--vary", "v=-1,2"], "must hold values > 0"),
    (["--vary", "v=1:nan"], "finite"),
    (["--vary", "v=1:2:0"], "between 1 and"),
    (["--vary", "v"], "--vary takes NAME=FROM:TO"),
    (["--vary", "v=0.1", "--vary", "v=0.2"], "given twice"),
    (["--vary", "v=0.1", "--scheduler", "tcp://127.0.0.1:9", "--scheduler-timeout", "1"],
     "no Dask scheduler answered"),
    (["--vary", "Delta=1:2", "-p", "v=0.1", "--out", "/nonexistent"], "--out draws"),
])
def test_cli_bad_input_one_line_and_status_2(argv, words, capsys):
    if "--scheduler" in argv:
        pytest.importorskip("distributed")
    assert main(["friction", "cdc", "-p", "Delta=3", *argv]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and words in err[0], err


def test_friction_figures_and_the_study_table(tmp_path):
    """The law and map figures are written, and the study's table counts what the maps hold."""
    from numerics.paper.figures.friction import law_figure, map_figure
    from numerics.paper.friction import FrictionStudy
    from numerics.sliding.maps import SliderComparison

    params = {"mu": 0.1, "lam": 1.0, "Delta": 3.0}
    laws = tuple(friction_map(m, {**params, **({"beta": 1.0} if m != "cdc" else {})},
                              {"v": [0.5, 3.0]}, settings=FAST, workers=1, progress=False)
                 for m in ("sedf_comoving", "cdc"))
    assert law_figure(laws, tmp_path / "law.png").stat().st_size > 10_000
    comp = compare_sliders({"mu": 0.1, "lam": 1.0, "beta": 1.0},
                           {"v": [0.5, 3.0], "Delta": [1.0, 3.0]}, settings=FAST, workers=1,
                           progress=False)
    assert isinstance(comp, SliderComparison)
    assert map_figure(comp, tmp_path / "map.png", [(0.5, 3.0, "P")]).stat().st_size > 10_000
    table = FrictionStudy(laws={3.0: laws}, v_delta=comp, v_beta=comp).table()
    assert "| 3 | sedf_comoving |" in table and "| 3 | cdc |" in table
    s = comp.summary()
    assert f"| {s['compared']}/4 |" in table
