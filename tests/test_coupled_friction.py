"""Friction laws of pulled chains of sliders (numerics.sliding.chain_friction, issue 23).

References: with kappa = 0 the chain is N independent stage-attached SEDF sliders, whose
friction law numerics.sliding.friction.friction_point computes by another route (its own
driven system, stick-slip detection and window); the same points in the same order on
this process, a local pool and a Dask LocalCluster (seeds spawned per velocity and slider).
"""

from __future__ import annotations

import json

import pytest

from numerics.sliding.chain_friction import chain_friction_law, chain_friction_point
from numerics.sliding.friction import friction_point

P = {"mu": 0.1, "Delta": 3, "lam": 1, "beta": 1}


@pytest.mark.parametrize("v", [0.01, 0.05])
def test_uncoupled_chain_is_independent_sliders(v):
    """Stick-slip velocities (periodic steady states): the dimer's force per slider at
    kappa = 0 equals the single sedf_comoving slider's to 1e-6."""
    chain = chain_friction_point("sedf-dimer", {**P, "kappa": 0}, v)
    one = friction_point("sedf_comoving", {**P, "v": v})
    assert chain.steady and one.steady and one.regime == "stick-slip"
    assert chain.mean_force == pytest.approx(one.mean_force, rel=1e-6)
    assert chain.spread < 1e-9  # both sliders on the same cycle, whatever their start


def test_runaway_is_reported():
    pt = chain_friction_point("sedf-dimer", {**P, "kappa": 0}, 2.0)
    assert pt.error and pt.error.startswith("runaway") and "slider" in pt.error
    assert friction_point("sedf_comoving", {**P, "v": 2.0}).regime == "runaway"


def _dump(points):
    return json.dumps([p.to_json() for p in points], sort_keys=True)


def test_same_bytes_on_any_executor():
    """This process and a local pool of two: the same bytes (seeds per velocity and
    slider; the Dask cluster in the slow test below).  Another seed is tried at v = 0.1,
    whose point costs an eighth of v = 0.02's and moves as much with the seed."""
    vs = [0.02, 0.05, 0.1]
    params = {**P, "kappa": 1}
    serial = chain_friction_law("sedf-chain-4", params, vs, workers=1)
    pool = chain_friction_law("sedf-chain-4", params, vs, workers=2)
    assert _dump(serial) == _dump(pool)
    assert [p.v for p in serial] == vs and not any(p.error for p in serial)
    # another seed moves the start, not the rules: a different run
    other = chain_friction_law("sedf-chain-4", params, vs[2:], workers=1, seed=1)
    assert other[0].per_slider != serial[2].per_slider


def _same_bytes_on_dask(model: str, vs: list, **local) -> None:
    """The law of ``model`` at ``vs`` on the local executor (``local``) and on a Dask
    LocalCluster of two processes: the same bytes."""
    distributed = pytest.importorskip("distributed")
    params = {**P, "kappa": 1}
    here = chain_friction_law(model, params, vs, **local)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        dask = chain_friction_law(model, params, vs, executor=client)
    assert _dump(here) == _dump(dask)


@pytest.mark.slow
def test_same_bytes_on_dask():
    _same_bytes_on_dask("sedf-chain-4", [0.02, 0.05, 0.1], workers=1)


def test_cli_chain_and_bad_input():
    import contextlib
    import io
    from types import SimpleNamespace

    from numerics.cli import main

    def kbm(*args):
        out, err = io.StringIO(), io.StringIO()
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            status = main(list(args))
        return SimpleNamespace(returncode=status, stdout=out.getvalue(), stderr=err.getvalue())

    out = kbm("friction", "sedf-dimer", "-p", "Delta=3", "-p", "kappa=0", "--vary", "v=0.01",
              "--json")
    assert out.returncode == 0, out.stderr
    d = json.loads(out.stdout)
    assert d["points"][0]["mean_force"] == pytest.approx(
        friction_point("sedf_comoving", {**P, "v": 0.01}).mean_force, rel=1e-6)
    bad = kbm("friction", "sedf-dimer", "-p", "Delta=3", "--vary", "v=0.01", "--vary",
              "Delta=1,2")
    assert bad.returncode == 2 and "stage velocity only" in bad.stderr
    bad = kbm("friction", "sedf-chain-1", "-p", "Delta=3", "--vary", "v=0.01")
    assert bad.returncode == 2 and "2 to 256" in bad.stderr


@pytest.mark.slow
def test_chain_of_64_at_20_velocities_on_dask_equals_local():
    """The issue's run: 64 sliders, 20 stage velocities, on a Dask LocalCluster and on the
    local pool: the same bytes."""
    import numpy as np

    _same_bytes_on_dask("sedf-chain-64", [float(v) for v in np.geomspace(0.01, 0.3, 20)],
                        workers=2)
