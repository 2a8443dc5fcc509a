"""Branches of periodic orbits of coupled systems (numerics.shooting.coupled_branch, issues 23
and 25) against independent references.

- Two identical van der Pol oscillators with dissipative coupling (coupled-vdp, sigma = 0):
  on the in-phase orbit x1 = x2 the coupling c (x2' - x1') vanishes, so along the whole
  branch in c the period is the single van der Pol cycle's, computed by the
  one-degree-of-freedom shooting (numerics.limit_cycle, separate code).
- The strongly forced Duffing oscillator x'' + x = mu (-2 zeta x' - alpha x^3 + h cos nu t)
  (mu = 1, zeta = 0.05, alpha = 1, h = 20) as the case N = 1 of the coupled family: its
  period-1 responses form a closed branch (an isola) whose period doublings are located
  against a separate scipy shooting (tests/test_forced_special.py's reference: Newton on
  the period map with its own variational equations, Brent on lambda_min + 1), and whose
  folds against the one-degree-of-freedom continuation (numerics.shooting.forced_branch).
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from scipy.optimize import brentq

from numerics import limit_cycle
from numerics.shooting.coupled_branch import continue_coupled
from numerics.cli import main
from _references import duffing_lambda_min


def run_cli(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_in_phase_branch_is_the_single_van_der_pol_cycle():
    br = continue_coupled("coupled-vdp", {"mu": 0.1, "sigma": 0, "c": 0.3}, "c", (0.05, 1.0))
    ref = limit_cycle("vdp", {"mu": 0.1})
    assert br.points[0].parameter == pytest.approx(0.05, abs=1e-12)
    assert br.points[-1].parameter == pytest.approx(1.0, abs=1e-12)
    assert len(br.points) >= 10
    for p in br.points:
        assert p.period == pytest.approx(ref.period, rel=1e-8)
        assert p.amplitudes[0] == pytest.approx(p.amplitudes[1], rel=1e-8)
        assert abs(p.floquet_multipliers[0] - 1) < 1e-6  # the trivial multiplier first
        assert p.stable
    assert br.special == ()


@pytest.fixture(scope="module")
def duffing_isola():
    return continue_coupled("duffing-forced",
                            {"mu": 1, "zeta": 0.05, "alpha": 1, "h": 20, "sigma": 1.0},
                            "sigma", (-0.6, 1.2), max_points=300)


def test_forced_duffing_branch_is_closed(duffing_isola):
    br = duffing_isola
    assert br.dof == 1 and br.forced
    assert "closed on itself" in br.reasons[0]
    sig = [p.parameter for p in br.points]
    folds = sorted(s.parameter for s in br.special if s.kind == "fold")
    # the isola's ends are folds, and every point lies between them
    assert min(sig) >= folds[0] - 1e-6 and max(sig) <= folds[-1] + 1e-6
    # the folds inside, against the one-degree-of-freedom continuation's 0.77719323020 and
    # 0.87977159034 (numerics.shooting.forced_branch, located there by the same fold test
    # on its own branch)
    for ref in (0.7771932302, 0.8797715903):
        assert min(abs(f - ref) for f in folds) < 1e-8
    for s in br.special:
        if s.kind == "fold":
            assert min(abs(z - 1) for z in s.floquet_multipliers) < 1e-5


def test_forced_duffing_period_doublings_against_scipy_shooting(duffing_isola):
    pds = [s for s in duffing_isola.special if s.kind == "period-doubling"]
    # two pairs: the system is symmetric under (x, t) -> (-x, t + T/2), each orbit has a
    # partner with the same multipliers at the same sigma
    assert len(pds) == 4
    for s in pds:
        assert min(z.real for z in s.floquet_multipliers) == pytest.approx(-1, abs=1e-6)
        ref = brentq(lambda q: duffing_lambda_min(q, s.state) + 1, s.parameter - 0.01,
                     s.parameter + 0.01, xtol=1e-12)
        assert s.parameter == pytest.approx(ref, abs=1e-7)
    assert sorted({round(s.parameter, 6) for s in pds}) == [0.168726, 0.499328]


def test_kbm_branch_and_response_take_coupled_systems(capsys):
    code, out, err = run_cli(capsys, "branch", "coupled-vdp", "-p", "mu=0.1", "-p", "sigma=0", "-p",
                             "c=0.3", "--vary", "c=0.2:0.4", "--json")
    assert code == 0, err
    d = json.loads(out)
    assert d["dof"] == 2 and not d["forced"]
    assert len(d["points"][0]["floquet_multipliers"]) == 4
    code, out, err = run_cli(capsys, "response", "quadratic-1-2", "-p", "mu=0.02", "-p", "zeta1=0.5",
                             "-p", "zeta2=0.5", "-p", "alpha1=1", "-p", "alpha2=1", "-p",
                             "sigma1=0", "-p", "h=2", "--vary", "sigma2=0.8:1.2:40", "--json")
    assert code == 0, err
    d = json.loads(out)
    assert d["forced"] and d["parameter"] == "sigma2"
    # below the threshold mode 1 stays at rest and mode 2 is linear:
    # a2 = h/(2 omega2 sqrt(zeta2^2 + s^2)) to O(mu) (Nayfeh & Mook 6.5)
    for p in d["points"]:
        assert p["amplitudes"][0] < 1e-6
        lin = 2.0 / (4 * math.hypot(0.5, p["parameter"]))
        assert p["amplitudes"][1] == pytest.approx(lin, rel=0.05)


def test_mode_at_rest_is_printed_as_zero(capsys):
    """Below the saturation threshold x1 = 0 is an invariant solution (x1'' = -2 zeta1 x1' -
    alpha1 x1 x2 vanishes with x1; Nayfeh & Mook 6.5): the table prints max|x1| as 0, not
    the shooting's round-off (4.4e-19), with the bound it is under, the residual the
    acceptance standard takes, 100 rtol max(1, |state|); the JSON keeps the numbers."""
    argv = ["response", "quadratic-1-2", "-p", "mu=0.02", "-p", "zeta1=0.5", "-p", "zeta2=0.5",
            "-p", "sigma1=0", "-p", "h=2", "--vary", "sigma2=0.8:1.2:10"]
    code, out, err = run_cli(capsys, *argv)
    assert code == 0, err
    rows = [line.split() for line in out.splitlines() if line.split()[-1:] == ["stable"]]
    assert rows and all(r[2] == "0" and float(r[3]) > 0.3 for r in rows), out
    assert "(0: below the accuracy of the orbit" in out and "rtol = 1e-11" in out
    code, out, err = run_cli(capsys, *argv, "--json")
    amps = [p["amplitudes"] for p in json.loads(out)["points"]]
    assert all(0 <= a1 < 100 * 1e-11 and a2 > 0.3 for a1, a2 in amps)


@pytest.mark.parametrize("argv, words", [
    (["response", "quadratic-1-2", "-p", "mu=0.02", "--detuning", "1"], "--detuning"),
    (["response", "coupled-vdp", "-p", "mu=0.1", "--vary", "c=0:1"], "no forcing"),
    (["branch", "coupled-vdp", "-p", "mu=0.1", "-p", "sigma=0", "--vary", "q=0:1"],
     "not a parameter"),
    (["branch", "coupled-vdp", "-p", "mu=0.1", "-p", "sigma=0", "--vary", "c=0:1",
      "--start", "1,2"], "4 finite numbers"),
    (["branch", "vdp", "-p", "mu=0.1", "--vary", "mu=0.1:1", "--start", "1,0"], "coupled"),
    (["branch", "sedf", "-p", "mu=0.1", "--vary", "Delta=0:4", "--follow-period", "0.5"],
     "--follow-period"),
])
def test_coupled_branch_bad_input(capsys, argv, words):
    code, out, err = run_cli(capsys, *argv)
    assert code != 0 and words in err and len(err.strip().splitlines()) == 1, err


def test_kbm_response_takes_rhs_lists(capsys):
    """Two identical forced Duffing oscillators with a spring between them, forced alike: the
    in-phase responses (x1 = x2, the spring idle) are the single forced Duffing's, which the
    one-degree-of-freedom shooting (numerics.shooting.forced_orbit, separate code) gives at
    each sigma."""
    from numerics.flow.forced_system import ForcedSystem
    from numerics.shooting.forced_orbit import periodic_response

    argv = ["response", "--rhs", "-2*zeta*xdot1 - x1**3 + h*cos(theta) - k*(x1 - x2)",
            "--rhs", "-2*zeta*xdot2 - x2**3 + h*cos(theta) - k*(x2 - x1)", "--omega0", "1,1",
            "--nu0", "1", "-p", "mu=0.1", "-p", "zeta=0.1", "-p", "h=1", "-p", "k=0.5",
            "-p", "sigma=-1", "--vary", "sigma=-1:0.5:30", "--json"]
    code, out, err = run_cli(capsys, *argv)
    assert code == 0, err
    d = json.loads(out)
    assert d["forced"] and d["dof"] == 2
    system = ForcedSystem("duffing-forced", {"mu": 0.1, "zeta": 0.1, "alpha": 1, "h": 1})
    for p in d["points"][::6]:
        x1, x2, v1, v2 = p["state"]
        assert abs(x1 - x2) < 1e-8 and abs(v1 - v2) < 1e-8  # in phase
        one = periodic_response(system, p["parameter"], np.array([x1, v1]))
        assert one.amplitude_max == pytest.approx(p["amplitudes"][0], rel=1e-6)
    i = argv.index("--nu0")
    code, out, err = run_cli(capsys, *(argv[:i] + argv[i + 2:]))
    assert code == 2 and "--nu0" in err and len(err.strip().splitlines()) == 1


def test_a_branch_started_at_an_end_of_its_range_holds_its_start_once():
    """``kbm response quadratic-1-2 ... --vary sigma2=0.8:1.2`` (README) starts at FROM: the
    direction towards smaller sigma2 leaves the range at once, and its end placed on the
    bound is the start itself, which the table printed twice ("0.8 6.2333188 ..." in its
    first two rows, 30 points).  Now each point once: the parameters strictly increase from
    FROM, and the other direction's points are the same as before (the branch is one
    curve: the direction towards larger sigma2 alone gives them)."""
    params = {"mu": 0.02, "zeta1": 0.5, "zeta2": 0.5, "alpha1": 1, "alpha2": 1, "sigma1": 0,
              "h": 2, "sigma2": 0.8}
    both = continue_coupled("quadratic-1-2", params, "sigma2", (0.8, 1.2))
    up = continue_coupled("quadratic-1-2", params, "sigma2", (0.8, 1.2), directions=(1,))
    p = np.array([pt.parameter for pt in both.points])
    assert p[0] == 0.8 and np.all(np.diff(p) > 0), p[:3]
    assert [pt.parameter for pt in up.points] == p.tolist()
