"""The step pilot's budget (numerics/noise/_pilot.py, ``measured_step``; issue 36: "the
default step is set by a measured error (two steps compared)").

The pilot runs only when it can resolve its tolerance within its budget.  Checks:

- the criterion's statistics: the lower 95 % confidence bound of a spread from ``n``
  normal draws, ``s ((n - 1)/chi2_{0.975, n-1})^(1/2)`` (the chi-square interval of a
  variance, e.g. Hogg, McKean & Craig, *Introduction to Mathematical Statistics*, sec.
  4.2), lies below the true spread in 97.5 % of draws (a fixed-seed Monte Carlo of 4000
  draws: within four binomial standard errors);
- a probe whose spread resolves the tolerance runs the full pilot, whose trajectories it
  reuses: the same step and numbers as the pilot at a budget that affords the floor;
- at low friction (SEDF, mu = 0.01 and 0.03) the step is the heating rule's, as the
  32-trajectory pilot had accepted it, without the pilot's 20 times its budget;
- ``kbm noise --json`` states what the pilot did in ``step_pilot``.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from numerics.noise import langevin_system
from numerics.noise.langevin import natural_step
from numerics.noise._pilot import PILOT_FLOOR, measured_step, reachable_stderr

SEDF = {"Delta": 3, "beta": 1, "lam": 1, "v": 0}


@pytest.mark.parametrize("n", [2, 3, 6, 13])
def test_reachable_stderr_is_a_lower_95_percent_bound(n):
    """Rows whose bias ``(4/3)(coarse - fine)`` is normal with spread ``sigma`` and whose
    fine column is 1: the bound at ``count`` trajectories is below ``sigma/count^(1/2)``
    in 97.5 % of 4000 draws (binomial standard error 0.25 %: within 1 %)."""
    rng = np.random.default_rng(36)
    sigma, count, below = 0.3, 50, 0
    for _ in range(4000):
        rows = np.ones((n, 4))
        rows[:, 0] = 1 + 0.75 * sigma * rng.standard_normal(n)
        rows[:, 1] = rows[:, 0]
        below += reachable_stderr(rows, 0, 2, count) <= sigma / math.sqrt(count)
    assert abs(below / 4000 - 0.975) < 0.01


def test_a_probe_that_resolves_runs_the_floor_pilot():
    """van der Pol, mu = 0.3 (its pilot resolves a -0.6 % bias, tests/test_baoab.py) with a
    budget of 4 trajectories and a tolerance of 1 %: the probe resolves it, and the pilot
    on the floor's 32 trajectories (the probe's 4 among them) gives the step and the
    numbers of the pilot whose budget affords exactly the floor."""
    kp = langevin_system("vdp", {"mu": 0.3}, 0.15, "kp")
    h0 = natural_step(kp, per_period=50)
    per = 3 * 50 / 0.3 / h0
    h, info = measured_step(kp, h0, tolerance=1e-2, budget=4.5 * per)
    assert info["probe"] == 4 and info["trajectories"] == PILOT_FLOOR
    assert min(info["reachable_stderr_x2"], info["reachable_stderr_a2"]) <= 0.5e-2
    ref_h, ref = measured_step(kp, h0, tolerance=1e-2, budget=(PILOT_FLOOR + 0.5) * per)
    assert "probe" not in ref and ref["trajectories"] == PILOT_FLOOR
    assert h == ref_h
    for key in ("bias_x2", "stderr_x2", "bias_a2", "stderr_a2", "accepted", "outcome"):
        assert info[key] == ref[key]
    assert info["steps"] == ref["steps"]


@pytest.mark.slow  # 4-8 s; kept out of the default run (five-minute rule)
def test_low_friction_step_is_the_rule_s_without_the_pilot():
    """SEDF at rest, Delta = 3, D = mu/2.  At mu = 0.01 the budget affords one trajectory
    (no standard error): the step is the rule's (BAOAB: half the Kloeden-Platen step),
    unmeasured, no step spent (the 32-trajectory pilot had spent 2e8 steps, 13 s, and
    accepted it with a standard error of 3.3 %).  At mu = 0.03 the probe of 6 trajectories
    cannot reach half the tolerance 2e-4 within the budget (it reaches about 3 %), and its
    steps stay within 1.5 times the budget; the floor pilot accepts the same step."""
    s = langevin_system("sedf", {"mu": 0.01, **SEDF}, 0.005, "auto")
    h0 = natural_step(s, per_period=50)
    h, info = measured_step(s, h0)
    assert h == h0 / 2 and info["outcome"] == "unresolved" and info["steps"] == 0
    assert info["probe"] == 0 and not info["resolved"]
    s = langevin_system("sedf", {"mu": 0.03, **SEDF}, 0.015, "auto")
    h0 = natural_step(s, per_period=50)
    h, info = measured_step(s, h0)
    assert h == h0 / 2 and info["outcome"] == "unresolved" and info["probe"] == 6
    assert min(info["reachable_stderr_x2"], info["reachable_stderr_a2"]) > 1e-4
    assert info["steps"] <= 1.5 * info["budget"]
    per = 3 * 50 / 0.03 / (h0 / 2)
    ref_h, ref = measured_step(s, h0, budget=(PILOT_FLOOR + 0.5) * per)
    assert ref_h == h and ref["accepted"] and ref["trajectories"] == PILOT_FLOOR


@pytest.mark.slow  # 3-4 s; kept out of the default run (five-minute rule)
def test_noise_json_states_the_pilot(capsys):
    """``kbm noise --json``: ``step_pilot`` with the rule's step ``h0``, the pilot's
    ``outcome`` and its record (vdp at mu = 0.01: the probe's 11 trajectories cannot
    resolve 2e-4; ``--dt``: not run), the other keys as before; the text says so."""
    from numerics.cli import main

    base = ["noise", "vdp", "-p", "mu=0.01", "-p", "D=0.005", "--trajectories", "8",
            "--t-end", "40", "--no-fokker-planck", "--json"]
    assert main(base) == 0
    rep = json.loads(capsys.readouterr().out)
    pilot = rep["step_pilot"]
    assert pilot["outcome"] == "unresolved" and pilot["probe"] >= 2
    assert pilot["h"] == pytest.approx(rep["dt"], rel=1e-3)
    assert pilot["steps"] <= 1.5 * pilot["budget"]
    assert isinstance(rep["steps"], float)
    assert main(base + ["--dt", "0.01"]) == 0
    pilot = json.loads(capsys.readouterr().out)["step_pilot"]
    assert pilot == {"h0": 0.01, "outcome": "not run", "reason": "--dt given"}
    assert main(base[:-1]) == 0  # the text says the step is unmeasured
    assert "dt is the heating rule's, unmeasured" in capsys.readouterr().out
