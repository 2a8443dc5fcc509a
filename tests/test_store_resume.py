"""A crash-safe store of finished points: a run killed midway and resumed gives the
uninterrupted run's bytes (issue 21)."""

from __future__ import annotations

import signal
import sqlite3
import subprocess
import sys
import time

import pytest

from numerics.executor import chunk, map_chunks
from numerics.store import PointStore, StoreError

MAP = ["friction", "cdc", "--vary", "v=0.004:3:log48", "--vary",
       "Delta=2.5:3:2", "--workers", "2", "--json"]


def _kbm(*argv, **kw):
    return subprocess.Popen([sys.executable, "-m", "numerics.cli", *argv],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, **kw)


def _stored_chunks(path) -> int:
    try:
        with sqlite3.connect(path) as db:
            return db.execute("SELECT COUNT(*) FROM chunks").fetchone()[0]
    except sqlite3.Error:
        return 0


def test_a_map_killed_midway_and_resumed_equals_the_uninterrupted_run(tmp_path):
    """SIGTERM once a few chunks are committed, then ``--resume``: the JSON is byte-identical
    to an uninterrupted run's, and the resumed run computed only the missing chunks."""
    store = tmp_path / "map.sqlite"
    proc = _kbm(*MAP, "--store", str(store))
    deadline = time.monotonic() + 120
    while _stored_chunks(store) < 2 and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.05)
    assert proc.poll() is None, "the map ended before it could be interrupted"
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=10)
    assert proc.returncode == 143
    kept = _stored_chunks(store)
    assert 2 <= kept < 16
    assert f"they are kept in {store}" in err.decode()
    resumed = _kbm(*MAP, "--store", str(store), "--resume")
    out_resumed, err2 = resumed.communicate(timeout=300)
    assert resumed.returncode == 0, err2
    plain = _kbm(*MAP)
    out_plain, _ = plain.communicate(timeout=300)
    assert out_resumed == out_plain
    assert _stored_chunks(store) == 16


def _square(c):
    return [x * x for x in c]


def test_map_chunks_skips_stored_chunks_and_refuses_a_reused_store(tmp_path):
    parts = chunk(list(range(20)), size=3)
    with PointStore(tmp_path / "s.sqlite") as st:
        first = map_chunks(_square, parts, workers=1, store=st, definition="squares")
        with pytest.raises(StoreError, match="--resume"):
            map_chunks(_square, parts, workers=1, store=st, definition="squares")
    with PointStore(tmp_path / "s.sqlite", resume=True) as st:
        # nothing is computed again: a function that would fail shows it
        again = map_chunks(_fails, parts, workers=1, store=st, definition="squares")
        other = map_chunks(_square, parts[:2], workers=1, store=st, definition="other run")
    assert again == first == [i * i for i in range(20)] and other == first[:6]


def _fails(c):
    raise AssertionError("a stored chunk was computed again")


def test_a_file_that_is_not_a_store_is_refused(tmp_path):
    bad = tmp_path / "text.txt"
    bad.write_text("not a database " * 100)
    with pytest.raises(StoreError, match="cannot be used as a store"):
        PointStore(bad)


def test_a_map_saved_as_netcdf_reads_back_in_one_line(tmp_path):
    """``--netcdf FILE``: xarray.open_dataset(FILE) holds the JSON's numbers on the axes."""
    import json

    xr = pytest.importorskip("xarray")
    path = tmp_path / "map.nc"
    proc = _kbm("friction", "cdc", "--vary", "v=0.1:3:3", "--vary", "Delta=1:3:2",
                "--against", "sedf_comoving", "-p", "beta=1", "--workers", "1", "--json",
                "--netcdf", str(path))
    out, err = proc.communicate(timeout=300)
    assert proc.returncode == 0, err
    data = json.loads(out)
    ds = xr.open_dataset(path)
    assert list(ds.slider.values) == ["cdc", "sedf_comoving"]
    assert ds.v.values.tolist() == data["axes"]["v"]
    assert ds.Delta.values.tolist() == data["axes"]["Delta"]
    first = ds.sel(slider="cdc")

    def nan_for_none(rows):  # JSON has null where netCDF has NaN (no measure: a runaway)
        return [[float("nan") if v is None else v for v in row] for row in rows]

    import numpy as np
    np.testing.assert_array_equal(first.mean_force.values, nan_for_none(data["mean_force"]))
    assert first.regime.values.tolist() == data["regime"]
    np.testing.assert_array_equal(ds.sel(slider="sedf_comoving").mean_force.values,
                                  nan_for_none(data["against"]["mean_force"]))
