"""Where the methods meet (numerics.paper.methods): classical KBM and the energy method
against one sweep of true SEDF cycles, on a small grid."""

from __future__ import annotations

import json

import numpy as np
import pytest

from numerics.paper.figures import FIGURES
from numerics.paper.figures.methods import methods_figure
from numerics.paper.methods import METHODS, methods_map

from _maps import point_at

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def mmap():
    return methods_map([0.02, 0.2], [0.01, 1.5, 3.0], [1.0], workers=2, progress=False)


def test_small_delta_both_methods_within_1e3(mmap):
    """Delta = 0.01, mu = 0.02 (beta = 1): KBM order 2 and energy order 2 are both
    within 1e-3 of the true cycle (largest relative error of a, max x, frequency)."""
    p = point_at(mmap, 0.02, 0.01)
    assert p.errors["KBM order 2"] < 1e-3 and p.errors["energy order 2"] < 1e-3


def test_large_delta_small_mu_energy_only(mmap):
    """Delta = 1.5 and 3 at mu = 0.02: the energy method's order 2 is within 1e-6 and
    order 1 within 1e-3, while neither classical KBM order is within 1 %."""
    for D in (1.5, 3.0):
        p = point_at(mmap, 0.02, D)
        assert p.errors["energy order 2"] < 1e-6 and p.errors["energy order 1"] < 1e-3
        assert min(p.errors["KBM order 1"], p.errors["KBM order 2"]) > 1e-2
    assert {(q.params["mu"], q.params["Delta"]) for q in mmap.within(1e-2, "KBM order 2")} \
        == {(0.02, 0.01), (0.2, 0.01)}


def test_missing_true_cycle_and_strict_json(mmap):
    """Delta = 3, mu = 0.2, beta = 1 has no true cycle (the motion settles on the
    equilibrium x = 1.89): the point says so with nan errors, null in the strict JSON;
    the summary counts the points within 1 % per method."""
    p = point_at(mmap, 0.2, 3.0)
    assert not p.success and "equilibrium" in p.message
    assert all(np.isnan(p.errors[m]) for m in METHODS)
    doc = json.loads(json.dumps(mmap.to_json(), allow_nan=False))
    assert doc["summary"]["1"]["true cycles"] == 5
    assert doc["summary"]["1"]["energy order 2 within 0.01"] == 5
    assert "no true cycle" in mmap.table()
    assert "nan" not in mmap.table()  # issue 24 item 8: a missing value says why
    assert mmap.array("energy order 2", 1.0).shape == (3, 2)


def test_friction_table_says_runaway_instead_of_nan():
    """Issue 24 item 8: the summary's friction table prints why a slider has no mean force."""
    from numerics.paper.friction import _force_text

    assert _force_text(float("nan")) == "none (runaway)" and _force_text(1.2345) == "1.23"


def test_methods_figure_registered_and_written(mmap, tmp_path):
    """'methods_map' (the headline map, next to the kept 'validity_map') is in the figure
    registry; drawn from a computed map (as ``kbm reproduce`` draws it: the module's map,
    its point without a true cycle included) it is a PNG of more than 10 kB in the folder
    asked for.  (It was drawn from a second, smaller map in
    tests/test_paper_methods_figures.py.)"""
    assert {"methods_map", "validity_map"} <= set(FIGURES)
    paths = methods_figure(tmp_path, mmap=mmap)
    assert [p.name for p in paths] == ["methods_map.png"]
    for p in paths:
        assert p.parent == tmp_path
        data = p.read_bytes()
        assert data[:8] == PNG_MAGIC and len(data) > 10_000, p
