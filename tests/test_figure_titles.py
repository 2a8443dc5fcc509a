"""The figures say what they show (issue 40 item 10): the noise figures name every parameter
and the CDC's temperature, the thermal friction figure its fixed parameters and its noise
in the variable given (kT when T was the axis), and the error maps draw the 1 % contour
solid and the 1e-3 contour dashed in every figure."""

from __future__ import annotations

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")

from numerics.cli._thermal_friction import _noise_label, _title  # noqa: E402
from numerics.paper.figures.comparison import error_contours  # noqa: E402
from numerics.thermal.friction import thermal_friction_map  # noqa: E402
from numerics.thermal.stationary import _title as noise_title  # noqa: E402


def test_noise_title_names_every_parameter_and_the_temperature():
    """kT = D/mu for the CDC (numerics.thermal's convention); vdp has no temperature."""
    rep = {"params": {"mu": "0.1", "Delta": "3", "Omega": "1", "lam": "1"}}
    title = noise_title(rep, "cdc", 0.1)
    for part in ("mu = 0.1", "Delta = 3", "Omega = 1", "lam = 1", "D = 0.1",
                 "kT = D/mu = 1"):
        assert part in title, part
    assert len(title.splitlines()) == 2
    vdp = noise_title({"params": {"mu": "0.05"}}, "vdp", 0.01)
    assert "mu = 0.05" in vdp and "D = 0.01" in vdp and "kT" not in vdp


@pytest.fixture(scope="module")
def t_map():
    """A small map over T (the CDC at mu = 1: D = mu kT)."""
    return thermal_friction_map("cdc", {"mu": 1.0, "Delta": 3.0}, {"T": [0.01, 0.04],
                                                                   "v": [0.01]},
                                trajectories=4, wells=1, workers=1)


def test_thermal_friction_legend_in_kT_when_T_was_the_axis(t_map):
    Ds = sorted({p.params["D"] for p in t_map.points})
    assert [_noise_label(t_map, d) for d in Ds] == ["cdc, kT = 0.01", "cdc, kT = 0.04"]
    title = _title(t_map, None)
    assert "mu = 1" in title and "Delta = 3" in title and "4 trajectories" in title
    assert "T =" not in title.split("\n")[0].split(":", 1)[1]  # the axis is in the legend


def test_thermal_friction_title_names_a_fixed_temperature():
    """-p T=0.05 with mu an axis: the legend names D = mu kT (0.025, 0.05), so the fixed
    T is said in the title (it was left out, as if it were an axis)."""
    m = thermal_friction_map("cdc", {"Delta": 3.0, "T": 0.05}, {"mu": [0.5, 1.0], "v": [0.01]},
                             trajectories=4, wells=1, workers=1)
    assert sorted(_noise_label(m, d) for d in {p.params["D"] for p in m.points}) == [
        "cdc, D = 0.025", "cdc, D = 0.05"]
    fixed = _title(m, None).split("\n")[0].split(":", 1)[1]
    assert "T = 0.05" in fixed and "Delta = 3" in fixed and "mu =" not in fixed


def test_error_contours_one_convention():
    """Level -2 (1 %) solid, level -3 (1e-3) dashed.  matplotlib draws a one-colour negative
    level dashed by default, which made kbm_validity.png's 1 % contour dashed."""
    import matplotlib.pyplot as plt

    x, y = np.geomspace(0.01, 1, 5), np.geomspace(1e-3, 3, 6)
    X, Y = np.meshgrid(x, y)
    fig, ax = plt.subplots()
    cs = error_contours(ax, x, y, np.log10(Y / X * 1e-2))
    styles = dict(zip(cs.levels, cs.get_linestyles()))
    assert styles[-2][1] is None  # solid
    assert styles[-3][1] is not None  # dashed
    plt.close(fig)
