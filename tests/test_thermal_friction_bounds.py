"""``kbm friction`` with noise is bounded and interruptible; its noise options are refused
without noise (the standard: bad input gets a clear one-line error, never a hang).

* A run beyond ``--budget`` integration steps is refused before any step, with the count
  ``trajectories x (burn-in + wells lam/v)/dt`` (checked here against
  :func:`numerics.noise.langevin.natural_step`, the step rule).
* The trajectories of a point are cut into blocks (tasks): a one-point law runs on the
  pool, so SIGTERM stops it within 2 s like every other ensemble; the numbers do not depend
  on the blocks (each trajectory draws from ``SeedSequence(seed, spawn_key=(j, i))``).
* ``--wells``, ``--trajectories``, ``--seed``, ``--budget`` without ``D`` or ``T``: exit 2.
"""

from __future__ import annotations

import math
import signal
import sys
import time

import pytest
from _proc import alive as _alive, signal_and_wait, start_with_workers

from kbm.errors import ParameterError
from numerics.noise.langevin import langevin_system, natural_step
from numerics.thermal.friction import STEPS_PER_PERIOD, thermal_friction_map

CDC = {"mu": 0.1, "Delta": 3.0, "lam": 1.0, "Omega": 1.0}


def _run(capsys, *argv):
    from numerics.cli import main

    t0 = time.monotonic()
    status = main(list(argv))
    out = capsys.readouterr()
    return status, out.out, out.err, time.monotonic() - t0


def test_a_run_over_the_budget_is_refused_at_once_with_the_step_count(capsys):
    """--wells 1e9 (the review's case, which ran unbounded): refused in seconds, exit 2, one
    line; the count is N (wells lam/v + max(5 lam/v, 20/mu))/h0 with h0 the natural step."""
    status, out, err, took = _run(capsys, "friction", "cdc", "-p", "Delta=3", "-p", "D=0.01",
                                  "--vary", "v=0.1", "--wells", "1e9")
    assert status == 2 and out == "" and took < 30
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "--budget" in lines[0] and "--wells" in lines[0]
    h0 = natural_step(langevin_system("cdc", {**CDC, "v": 0.1}, 0.01),
                      per_period=STEPS_PER_PERIOD)
    steps = 16 * (1e9 / 0.1 + max(5 / 0.1, 20 / 0.1)) / h0
    assert f"{steps:.3g} integration steps > budget 2e+09" in lines[0]
    assert f"dt = {h0:.3g}" in lines[0]


def test_the_library_checks_the_budget_summed_over_the_points():
    h0 = natural_step(langevin_system("cdc", {**CDC, "v": 1.0}, 0.01),
                      per_period=STEPS_PER_PERIOD)
    per = 4 * (2 / 1.0 + max(5 / 1.0, 20 / 0.1)) / h0  # one point at v = 1
    kw = dict(trajectories=4, wells=2, workers=1)
    with pytest.raises(ParameterError, match="budget"):
        thermal_friction_map("cdc", {**CDC, "D": 0.01}, {"v": [1.0, 1.0]}, budget=1.5 * per,
                             **kw)
    m = thermal_friction_map("cdc", {**CDC, "D": 0.01}, {"v": [1.0]}, budget=1.5 * per, **kw)
    assert math.isfinite(m.points[0].mean_force.value)
    with pytest.raises(ParameterError, match="positive"):
        thermal_friction_map("cdc", {**CDC, "D": 0.01}, {"v": [1.0]}, budget=-1, **kw)


def test_the_numbers_do_not_depend_on_the_blocks_of_trajectories():
    """One point alone (blocks of 1 trajectory) and the first of 8 (blocks of 2, so point
    j = 0 draws the same streams): the same bytes."""
    kw = dict(trajectories=4, wells=2, seed=3, workers=1)
    alone = thermal_friction_map("cdc", {**CDC, "D": 0.02}, {"v": [0.7]}, **kw).points[0]
    grid = thermal_friction_map("cdc", {**CDC, "D": 0.02},
                                {"v": [0.7, 0.3, 0.4, 0.5, 0.6, 0.8, 0.9, 1.0]}, **kw)
    assert alone.to_json() == grid.points[0].to_json()


@pytest.mark.parametrize("flags", [["--wells", "100"], ["--trajectories", "8"],
                                   ["--seed", "3"], ["--budget", "1e3"],
                                   ["--seed", "0", "--wells", "50"]])
def test_noise_options_without_noise_are_refused(capsys, flags):
    status, out, err, _ = _run(capsys, "friction", "cdc", "-p", "Delta=3", "--vary", "v=0.1",
                               *flags)
    assert status == 2 and out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "-p D=" in lines[0] and "-p T=" in lines[0]
    for flag in flags[::2]:
        assert flag in lines[0]


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="uses /proc")
def test_sigterm_stops_a_one_point_law_within_2_s():
    """The review's one-point law (minutes of work) ran in the parent's compiled loop, deaf
    to SIGTERM; its trajectories now run on the pool and the parent stops at once."""
    argv = ["friction", "cdc", "-p", "Delta=3", "-p", "D=0.01", "--vary", "v=0.1",
            "--wells", "2e4", "--workers", "2", "--no-progress"]
    proc, kids = start_with_workers(argv, 1.5, "the law's")
    if not kids:
        proc.kill()
        pytest.fail("the law's worker processes did not start within 60 s")
    elapsed, err = signal_and_wait(proc, signal.SIGTERM, "SIGTERM")
    assert proc.returncode == 143, err
    assert elapsed < 2.0
    last = err.strip().splitlines()[-1]
    assert last.startswith("kbm friction: interrupted (SIGTERM): ")
    assert "of 16 trajectories were finished" in last
    assert [k for k in kids if _alive(k)] == []
