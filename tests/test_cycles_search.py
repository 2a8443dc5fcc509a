"""Every limit cycle, found from the predictions and checked against a brute-force search.

``numerics.limit_cycles`` shoots from every cycle the energy-balance averaging predicts
(stable and unstable, on every period annulus of the conservative oscillator).  The
independent reference is a brute-force scan that knows nothing of the predictions:
Newton's method on the return map started from a grid of ``(x_max, T)`` points on both
sides of the origin, plus transients from a grid of starts (they find the stable cycles).
Every cycle the scan finds must be in the list, and every listed cycle is a true periodic
orbit (residual, trivial Floquet multiplier 1, energy balance Gamma = 0 over one period,
paper eq. 10) whose stability agrees with the prediction's.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from numerics import ConvergenceError, IntegrationError, NoCycleError, limit_cycle, limit_cycles
from numerics.cli import main

#: (Delta, beta) at mu = 0.1, lam = 1, Omega = 1: the paper's Fig. 3 case; a case with
#: unstable side-well cycles on both sides of the origin; the paper's Fig. 4 potential
CASES = [(1.5, 1.0), (1.5, 1.3), (3.0, 0.5)]


def _scan(params) -> list:
    """Cycles found by Newton from a grid of starts and by transients (no predictions)."""
    found = []
    periods = (1.5, 2.5, 3.5, 5.0, 6.5, 8.0, 9.5)
    starts = [(s * x, T) for x in np.linspace(0.3, 3.3, 21) for T in periods for s in (1.0, -1.0)]
    for g in starts:
        try:
            c = limit_cycle("sedf", params, guess=g, max_iter=15)
        except (ConvergenceError, IntegrationError, NoCycleError):
            continue
        if c.success and not any(_same(c, d) for d in found):
            found.append(c)
    return found


def _same(a, b) -> bool:
    return (abs(a.period - b.period) < 1e-5 * b.period
            and abs(a.amplitude_max - b.amplitude_max) < 1e-5 * max(1, abs(b.amplitude_max)))


# the scan costs 15-20 s a case: one case in the default run, the others marked slow (the
# listed cycles of all three are checked below either way)
SCANNED = [CASES[0], *[pytest.param(*c, marks=pytest.mark.slow) for c in CASES[1:]]]


@pytest.mark.parametrize("Delta,beta", SCANNED)
def test_every_cycle_of_a_brute_force_scan_is_listed(Delta, beta):
    """No true cycle found by the brute-force scan is missing from ``limit_cycles``."""
    params = {"mu": 0.1, "Delta": Delta, "beta": beta, "lam": 1}
    listed = limit_cycles("sedf", params)
    assert listed and not listed.failures
    scan = _scan(params)
    assert len(scan) >= (3 if beta == 1.3 else 1)  # the scan itself finds the side wells
    for c in scan:
        assert any(_same(c, d) for d in listed), (c.amplitude_max, c.period, c.stable)


@pytest.mark.parametrize("Delta,beta", CASES)
def test_listed_cycles_are_true_cycles_with_the_predicted_stability(Delta, beta):
    """Each listed cycle closes (residual), has the trivial multiplier 1, balances its energy
    over one period (Gamma = 0, paper eq. 10), and is stable exactly when predicted."""
    params = {"mu": 0.1, "Delta": Delta, "beta": beta, "lam": 1}
    listed = limit_cycles("sedf", params)
    for c, p in zip(listed, listed.predicted):
        assert c.success and c.residual < 1e-9
        assert abs(c.floquet_multipliers[0] - 1) < 1e-7
        assert abs(c.dissipation.total) < 1e-9 * max(1.0, c.dissipation.gamma_minus)
        assert c.stable == p.stable
        assert c.amplitude_max == pytest.approx(p.amplitude_max, abs=2e-3)


def test_side_well_cycles_are_mirror_images():
    """SEDF is odd (x -> -x maps orbits to orbits): the two unstable side-well cycles at
    Delta = 1.5, beta = 1.3 have the same period and mirrored extremes."""
    listed = limit_cycles("sedf", {"mu": 0.1, "Delta": 1.5, "beta": 1.3, "lam": 1})
    wells = [c for c in listed if not c.stable]
    assert len(wells) == 2
    a, b = sorted(wells, key=lambda c: c.amplitude_max)
    assert a.period == pytest.approx(b.period, rel=1e-9)
    assert a.amplitude_max == pytest.approx(-np.min(b.x), abs=1e-6)
    assert abs(a.floquet_multipliers[1]) > 1 and abs(b.floquet_multipliers[1]) > 1


def test_default_search_finds_the_cycle_where_classical_kbm_fails():
    """Paper's Delta = 3, beta = 1, mu = 0.1 (delta = Delta/mu = 30): classical KBM's first
    order misses the cycle, the default search finds it from the energy balance."""
    c = limit_cycle("sedf", {"mu": 0.1, "Delta": 3, "beta": 1, "lam": 1})
    assert c.success and c.stable
    assert c.amplitude_max == pytest.approx(2.0906, abs=1e-4)
    assert c.period == pytest.approx(8.14206, abs=1e-4)


def test_cli_cycle_all_json(capsys):
    """``kbm cycle --all --json``: key ``cycles``, each a cycle's keys plus its annulus."""
    assert main(["cycle", "sedf", "-p", "mu=0.1", "-p", "Delta=1.5", "-p", "beta=1.3",
                 "-p", "lam=1", "--all", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert [c["stable"] for c in out["cycles"]] == [False, False, True]
    assert {c["annulus"] for c in out["cycles"]} == {"side well at x=-0.898",
                                                      "side well at x=+0.898", "outer"}
    for c in out["cycles"]:
        assert math.isfinite(c["period"]) and c["success"]


def test_no_cycle_is_an_empty_list_with_the_reason():
    """Linear damping loses energy on every orbit: no prediction, nothing to shoot; the
    reason says what was searched (issue 26), not more than was checked."""
    listed = limit_cycles("linear_damping", {"mu": 0.1, "zeta": 1})
    reason = listed.predictions.reason
    assert list(listed) == [] and "lose energy" in reason and "searched" in reason


def test_two_turns_of_a_cycle_are_reported_with_the_minimal_period():
    """Newton from a start with twice the period converges to two turns of the cycle
    (x(T) = x0 holds for T = 2 T_min too); the result is the cycle with its minimal period,
    the same as from the default start."""
    params = {"mu": 0.1, "Delta": 1.5, "beta": 1, "lam": 1}
    c = limit_cycle("sedf", params)
    d = limit_cycle("sedf", params, guess=(2.05, 13.9))
    assert d.period == pytest.approx(c.period, rel=1e-10)
    assert d.amplitude_max == pytest.approx(c.amplitude_max, abs=1e-10)
