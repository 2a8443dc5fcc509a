"""Issue 11: branches of limit cycles by pseudo-arclength continuation.

References are independent of the continuation: the exact first-order fold
``nu = 1/8`` of ``F = (-nu + x^2 - x^4) x'``, the third-order KBM fold (the engine's
averaged equations, solved separately), single-cycle shooting, and a transient in
reversed time integrated here by scipy on a right-hand side written in this file.
"""

from __future__ import annotations

import math
import re
import time

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from kbm import custom_model
from kbm.errors import ParameterError
from numerics import limit_cycle
from numerics.comparison.branches import kbm_branch
from numerics.cycles.continuation import continue_cycles
from numerics.shooting.acceptance import TRIVIAL_TOL
from numerics.errors import NoCycleError

FOLD = "(-nu + x**2 - x**4)*xdot"


@pytest.fixture(scope="module")
def fold_model():
    return custom_model(FOLD)


@pytest.fixture(scope="module")
def fold_branches(fold_model):
    return {mu: continue_cycles(fold_model, {"mu": mu, "nu": 0.05}, "nu", (0.0, 0.2),
                                rtol=1e-12)
            for mu in (0.05, 0.1, 0.2)}


def test_fold_found_near_one_eighth(fold_branches):
    for mu, br in fold_branches.items():
        folds = br.folds()
        assert len(folds) == 1, br.special
        assert abs(folds[0].parameter - 0.125) < 1e-5
        assert abs(folds[0].amplitude - 1.0) < 1e-3
        # stable before the fold, unstable after it
        stab = [p.stable for p in br.points]
        assert stab[0] and not stab[-1]


def test_fold_converges_at_the_kbm_rate(fold_model, fold_branches):
    """Orders 1-2 leave an error ~ mu^2 (A_2 = 0); order 3 removes it."""
    err2, err3 = {}, {}
    for mu, br in fold_branches.items():
        nu_c = br.folds()[0].parameter
        k2 = kbm_branch(fold_model, {"mu": mu}, "nu", (0.0, 0.2), order=2, n=41).folds
        k3 = kbm_branch(fold_model, {"mu": mu}, "nu", (0.0, 0.2), order=3, n=41).folds
        assert abs(k2[0].parameter - 0.125) < 1e-12
        err2[mu], err3[mu] = abs(nu_c - k2[0].parameter), abs(nu_c - k3[0].parameter)
    rate = math.log(err2[0.2] / err2[0.1]) / math.log(2)
    assert 1.8 < rate < 2.2, err2
    rate = math.log(err2[0.1] / err2[0.05]) / math.log(2)
    assert 1.8 < rate < 2.2, err2
    for mu in err3:
        assert err3[mu] < 2e-3 * err2[mu], (err2, err3)


def test_hopf_end_of_the_unstable_branch(fold_branches):
    br = fold_branches[0.1]
    hopf = [s for s in br.special if s.kind == "hopf"]
    assert len(hopf) == 1 and abs(hopf[0].parameter) < 1e-5 and abs(hopf[0].amplitude) < 1e-9
    assert abs(hopf[0].period - 2 * math.pi) < 1e-3


def _reverse_time_amplitude(mu: float, nu: float, x_start: float) -> float:
    """Largest x over the last turns of the flow in reversed time (t -> -t): the unstable
    cycle of the forward flow attracts."""
    def rhs(t, y):
        x, v = y
        return [v, -x - mu * (-nu + x * x - x ** 4) * v]
    sol = solve_ivp(rhs, (0.0, 4000.0), [x_start, 0.0], method="DOP853", rtol=1e-12,
                    atol=1e-12, dense_output=True)
    t = np.linspace(3990.0, 4000.0, 100001)
    return float(np.max(sol.sol(t)[0]))


def test_unstable_branch_matches_shooting_and_reversed_time(fold_model):
    mu, nu = 0.1, 0.05
    br = continue_cycles(fold_model, {"mu": mu, "nu": nu}, "nu", (nu, 0.2), directions=(1,),
                         rtol=1e-12)
    last = br.points[-1]  # back at nu = 0.05 on the unstable side of the fold
    assert last.parameter == pytest.approx(nu, abs=1e-14) and not last.stable
    a_guess = math.sqrt(1 - math.sqrt(1 - 8 * nu))
    c = limit_cycle(fold_model, {"mu": mu, "nu": nu}, guess=(a_guess, 2 * math.pi))
    assert not c.stable
    assert abs(c.amplitude_max - last.amplitude_max) < 1e-9
    assert abs(c.period - last.period) < 1e-9
    assert abs(c.floquet_multipliers[1].real - last.multipliers[1].real) < 1e-7
    assert abs(_reverse_time_amplitude(mu, nu, 0.5) - last.x0) < 1e-6


def test_vdp_into_relaxation_matches_single_cycles():
    t0 = time.perf_counter()
    br = continue_cycles("vdp", {"mu": 0.1}, "mu", (0.1, 10.0), rtol=1e-12)
    assert time.perf_counter() - t0 < 60
    assert br.reasons == ("reached mu = 10",) and not br.special
    mus = np.array([p.parameter for p in br.points])
    assert np.all(np.diff(mus) > 0) and mus[-1] == 10.0
    for k in np.linspace(0, len(br.points) - 1, 5).astype(int):
        p = br.points[k]
        c = limit_cycle("vdp", {"mu": p.parameter})
        assert abs(c.period - p.period) < 1e-10 * c.period
        assert abs(c.amplitude_max - p.amplitude_max) < 1e-10 * c.amplitude_max
        assert p.stable and 0 < p.multipliers[1].real < 1


def test_homoclinic_end_sedf():
    br = continue_cycles("sedf", {"mu": 0.1, "beta": 1, "lam": 1, "Delta": 3.0}, "Delta",
                         (3.0, 4.0), directions=(1,))
    kinds = [s.kind for s in br.special]
    assert kinds == ["homoclinic"]
    assert br.points[-1].period > 1.25 * br.points[0].period
    # issue 26: every printed point passes the convergence test; the others are counted.
    # The corrector iterates on until the trivial multiplier passes, so none is dropped here
    # (before it did, 15 of 63 points near the separatrix were)
    assert all(abs(p.multipliers[0] - 1) <= TRIVIAL_TOL for p in br.points)
    assert br.dropped == 0
    # the end from the period law with computed saddle eigenvalues, against AUTO-07p's
    # last point on this branch (3.2494301 at period 14.47, its start cycle at s = 1 exactly;
    # benchmarks/bench_branch.py), within its error bar
    msg = br.special[0].message
    m = re.search(r"period law agrees: ([0-9.]+) \+- ([0-9.]+)", msg)
    est, err = float(m.group(1)), float(m.group(2))
    assert abs(est - 3.2494301) < err < 1e-3
    # and the end itself from the saddles' manifolds (issue 25: a computation of the saddle
    # connection independent of the cycles), inside the period law's error bar
    m = re.search(r"Delta_h = ([0-9.]+) \+- (\S+) \(the saddle connection", msg)
    conn, cerr = float(m.group(1)), float(m.group(2))
    assert br.special[0].parameter == pytest.approx(conn, abs=1e-10)
    assert cerr < 1e-9 and abs(conn - est) < err
    # AUTO-07p followed the cycles up to 3.2494301: the end lies just beyond
    assert 0 < conn - 3.2494301 < 1e-5


@pytest.mark.slow  # 4-7 s; the default run keeps its siblings (five-minute rule)
def test_vdp_relaxation_has_no_homoclinic_end():
    """van der Pol has no saddle: its period grows like a power of mu, not like
    -log|mu - mu_h|, so its branch has no homoclinic end (it had one 'near mu = 50.92',
    Aitken's limit of the last three points, after the period passed 8 times its start).
    The relaxation period (Dorodnitsyn 1947; Grasman, *Asymptotic Methods for Relaxation
    Oscillations*, 1987): T = (3 - 2 ln 2) mu + 3 alpha mu^(-1/3) + O(log(mu)/mu), alpha =
    2.338107 the magnitude of the first zero of Ai; the leading term alone within 5 % at
    mu >= 50, the two terms within 1e-3."""
    br = continue_cycles("vdp", {"mu": 0.1}, "mu", (0.1, 1e6), directions=(1,),
                         max_points=30)
    assert "homoclinic" not in [s.kind for s in br.special]
    assert br.points[-1].parameter > 100  # on past the false end at 50.92
    lead = 3 - 2 * np.log(2)
    far = [p for p in br.points if p.parameter >= 50]
    assert len(far) >= 5
    for p in far:
        mu = p.parameter
        assert abs(p.period / (lead * mu) - 1) < 0.05
        assert abs(p.period / (lead * mu + 3 * 2.338107 * mu ** (-1 / 3)) - 1) < 1e-3


def test_bad_input(fold_model):
    with pytest.raises(ParameterError, match="cannot vary 'nope'"):
        continue_cycles("vdp", {"mu": 1}, "nope", (0, 1))
    with pytest.raises(ParameterError, match="empty range"):
        continue_cycles("vdp", {"mu": 1}, "mu", (1, 1))
    with pytest.raises(ParameterError, match="outside the range"):
        continue_cycles("vdp", {"mu": 3}, "mu", (0.1, 1))
    with pytest.raises(ParameterError, match="does not enter"):
        continue_cycles("sedf", {"mu": 0.1, "Delta": 1, "beta": 1}, "v", (0, 1))
    with pytest.raises(NoCycleError, match="to start the branch from"):
        continue_cycles("linear_damping", {"mu": 0.1, "zeta": 0.1}, "zeta", (0.1, 0.5))
    with pytest.raises(NoCycleError, match="to start the branch from"):
        continue_cycles(fold_model, {"mu": 0.1, "nu": 0.05}, "nu", (0, 0.2), start=(5.0, 6.3))


def test_bounded(fold_model):
    br = continue_cycles(fold_model, {"mu": 0.1, "nu": 0.05}, "nu", (0.0, 0.2), max_points=5,
                         directions=(1,))
    assert len(br.points) == 5 and "max_points" in br.reasons[0]
    js = br.to_json()
    assert set(js["points"][0]) >= {"parameter", "amplitude_max", "period", "stable",
                                    "multipliers"}
