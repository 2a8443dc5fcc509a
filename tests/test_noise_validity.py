"""Validity flags and bad input of ``kbm noise`` and ``kbm escape`` (issue 36, findings 4
and 5).

A gap |averaged - simulated|/stderr > 4 is flagged in the JSON and the text with what to
do; mu <= 0, infinite D and models with no stationary state (no damping: A_1 = 0; an
anti-damping: the averaged drift does not confine) are refused before any simulation with
the reason; escape below E_b/kT = 2 warns.
"""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from kbm.errors import ModelError, ParameterError
from numerics.thermal.advice import validity
from numerics.thermal.stationary import noise_report
from numerics.noise.validity import Z_FLAG


def kbm(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "numerics.cli", *args], capture_output=True,
                          text=True, timeout=300)


def test_validity_flags_a_large_gap():
    """z = (avg - sim)/stderr per moment; |z| > 4 flagged with the two remedies."""
    moments = {"a2": {"averaged": 4.0, "simulated": 4.02, "stderr": 0.013},
               "x2": {"averaged": 2.11486, "simulated": 2.32239, "stderr": 0.0087}}
    v = validity(moments)
    assert v["z"]["x2"] == pytest.approx((2.11486 - 2.32239) / 0.0087)
    assert v["flagged"] and v["threshold"] == Z_FLAG
    assert "--order 2" in v["advice"] and "--method fokker-planck" in v["advice"]
    # the energy envelope (a slider) has no second order: only the Fokker-Planck route;
    # at order 2 the advice no longer names --order 2 either
    for w in (validity(moments, 1, can_raise_order=False), validity(moments, 2)):
        assert w["flagged"] and "--order 2" not in w["advice"]
        assert "--method fokker-planck" in w["advice"]
    assert "second-order averaging does not hold" in validity(moments, 2)["advice"]
    fine = validity({"a2": {"averaged": 1.0, "simulated": 1.01, "stderr": 0.01},
                     "x2": {"averaged": None, "simulated": 0.5, "stderr": 0.01}})
    assert not fine["flagged"] and fine["advice"] == "" and fine["z"]["x2"] is None


@pytest.mark.parametrize("params, match", [
    ({"mu": -0.1, "D": 0.01}, "mu = -0.1"),
    ({"mu": 0, "D": 0.01}, "mu = 0"),
    ({"mu": 0.1, "D": "inf"}, "finite"),
])
def test_bad_numbers_refused(params, match):
    with pytest.raises(ParameterError, match=match):
        noise_report("vdp", params, trajectories=8)


@pytest.mark.parametrize("model, params, match", [
    ("duffing", {"mu": 0.1, "D": 0.01}, "A_1 is 0"),
    ("linear_stiffness", {"mu": 0.1, "kappa": 1, "D": 0.01}, "A_1 is 0"),
    ("linear_damping", {"mu": 0.1, "zeta": -1, "D": 0.01}, "does not confine"),
    ("sedf", {"mu": 0.1, "Delta": 2, "beta": -1, "D": 0.01}, "no stationary state"),
])
def test_no_stationary_state_refused_before_simulation(model, params, match):
    """The budget 1 would refuse any simulation with a message: the error comes first."""
    with pytest.raises(ModelError, match=match):
        noise_report(model, params, trajectories=8, budget=1, fokker_planck=False)


def test_anti_damping_message_says_infinity_in_words():
    """linear_damping with zeta = -1: A_1 = a grows without bound (A_1 -> +infinity as
    a -> infinity), and the message says so in words, not in sympy's ``oo``."""
    with pytest.raises(ModelError) as err:
        noise_report("linear_damping", {"mu": 0.1, "zeta": -1, "D": 0.01}, trajectories=8,
                     budget=1, fokker_planck=False)
    assert "tends to +infinity at large amplitude" in str(err.value)
    assert " oo " not in str(err.value)


def test_cli_one_line_errors():
    for args, text in ((("noise", "vdp", "-p", "mu=-0.1", "-p", "D=0.01"), "mu > 0"),
                       (("noise", "vdp", "-p", "mu=0.1", "-p", "D=inf"), "finite"),
                       (("escape", "cdc", "-p", "mu=-0.1", "-p", "Delta=2", "-p", "D=0.01"),
                        "mu > 0")):
        proc = kbm(*args)
        assert proc.returncode == 2, proc.stderr
        assert text in proc.stderr and "not a number" not in proc.stderr
        assert len(proc.stderr.strip().splitlines()) == 1


def test_escape_warns_below_two_kT(capsys):
    """CDC at kT = 2 (E_b/kT = 0.39): the warning in the JSON and the text (in-process: the
    command's own code, without three interpreter start-ups)."""
    from numerics.cli import main

    def run(*args):
        assert main(list(args)) == 0
        return capsys.readouterr().out

    args = ("escape", "cdc", "-p", "mu=0.1", "-p", "Delta=2", "-p", "D=0.2",
            "--no-simulation")
    rep = json.loads(run(*args, "--json"))
    assert rep["barrier_over_kT"] < 2 and rep["warnings"]
    assert "E_b/kT" in rep["warnings"][0]
    assert "WARNING" in run(*args)
    ok = json.loads(run("escape", "cdc", "-p", "mu=0.1", "-p", "Delta=2", "-p", "D=0.02",
                        "--no-simulation", "--json"))
    assert ok["barrier_over_kT"] > 2 and ok["warnings"] == []


def test_a_density_wider_than_the_quadrature_is_not_called_unnormalisable():
    """The first-order amplitude density of noisy van der Pol (x'' + x = mu (1 - x^2) x' +
    sqrt(2 D) xi), P(a) ~ a exp((mu/D)(a^2/2 - a^4/16)) (Stratonovich's stochastic
    averaging), is normalisable at every D > 0; at large D/mu its peak is at
    a^4 = 4 D/mu.  At D = 1e20, mu = 0.1 that is a = 2.51e5, and the density is still above
    exp(-80) of its peak at a = 1e6, the quadrature's end: the message names the peak and
    what to change, not 'not normalisable'."""
    import re

    from numerics.thermal.averaged import averaged_stationary

    with pytest.raises(ModelError) as err:
        averaged_stationary("vdp", {"mu": 0.1}, 1e20, 1.0)
    msg = str(err.value)
    peak = float(re.search(r"peaks at a = ([0-9.e+]+)", msg).group(1))
    assert abs(peak / (4 * 1e20 / 0.1) ** 0.25 - 1) < 0.01, msg
    assert "lower the noise D" in msg and "not normalisable" not in msg


def test_advice_points_at_the_fokker_planck_column_when_it_is_shown():
    """With Fokker-Planck moments beside the simulated ones, a flagged gap names them as the
    reference with z_FP = (FP - simulated)/stderr (computed here by hand), and does not
    advise --method fokker-planck (already in use or its column already printed); --order 2
    only where it applies."""
    moments = {"a2": {"averaged": 4.0, "simulated": 4.02, "stderr": 0.013,
                      "fokker_planck": 4.040466},
               "x2": {"averaged": 2.11486, "simulated": 2.32239, "stderr": 0.0087,
                      "fokker_planck": 2.328522}}
    for raise_order in (False, True):
        v = validity(moments, 1, raise_order, None)
        assert v["flagged"] and "--method fokker-planck" not in v["advice"]
        assert "Fokker-Planck column" in v["advice"] and "reference" in v["advice"]
        assert ("--order 2" in v["advice"]) is raise_order
        zf = ((4.040466 - 4.02) / 0.013, (2.328522 - 2.32239) / 0.0087)
        assert v["z_fokker_planck"]["a2"] == pytest.approx(zf[0])
        assert v["z_fokker_planck"]["x2"] == pytest.approx(zf[1])
        assert f"{zf[0]:+.1f} and {zf[1]:+.1f} standard errors" in v["advice"]
        assert "beyond" not in v["advice"]  # the simulation agrees with the reference
    far = {k: dict(m, fokker_planck=m["fokker_planck"] + 10 * m["stderr"])
           for k, m in moments.items()}
    assert "a smaller --dt" in validity(far, 1, False, None)["advice"]


def test_advice_names_only_fokker_planck_routes_that_run(capsys):
    """--no-fokker-planck: the route is to drop it (--method fokker-planck with it is an
    error of kbm noise); a solve refused for its cost: --fp-budget (--method fokker-planck
    has the same budget); a damping not polynomial in x' (tanh(x')): no Fokker-Planck route,
    and without --order 2 the advice says that the simulation is the answer."""
    import sympy as sp

    from kbm.model.builtins import Oscillator
    from kbm.symbols import x, xdot
    from numerics.cli import main
    from numerics.thermal.advice import fokker_planck_route

    route = fokker_planck_route("sedf", {"mu": 0.1, "Delta": 3, "beta": 1, "lam": 1},
                                "not requested")
    assert "without --no-fokker-planck" in route and "--method" not in route
    assert "--fp-budget" in fokker_planck_route(
        "vdp", {"mu": 0.1}, "no Fokker-Planck solution: the Kramers solve needs 32 Hermite "
        "functions x 97 Chebyshev points (cost 7.4e+04 > 1e+04): not affordable here")
    tanh = Oscillator("tanh_damping", -sp.tanh(xdot) - x**3)
    assert fokker_planck_route(tanh, {"mu": 0.1}, "not requested") is None
    gap = {"a2": {"averaged": 4.0, "simulated": 4.5, "stderr": 0.01},
           "x2": {"averaged": 2.0, "simulated": 2.25, "stderr": 0.01}}
    advice = validity(gap, 1, False, None)["advice"]
    assert "--" not in advice and "the simulated values are the answer" in advice
    assert main(["noise", "vdp", "-p", "mu=0.1", "-p", "D=0.05", "--no-fokker-planck",
                 "--method", "fokker-planck"]) == 2  # the command the old advice named
    assert "contradicts" in capsys.readouterr().err


@pytest.mark.slow
def test_noise_cli_flag_with_fokker_planck_shown(capsys, tmp_path):
    """The known defect: ``kbm noise ... --method fokker-planck`` with |z| > 4 advised "use
    --method fokker-planck".  Van der Pol at mu = D = 0.5 (first-order averaging off by 8 %
    in <a^2>, 32 trajectories: z = -9) with the Fokker-Planck column: the JSON's and the
    text's advice (one run, ``--out``) name that column as the reference, --order 2 (a
    polynomial F), and not --method fokker-planck; the Fokker-Planck values are within 4
    standard errors of the simulated ones (an independent method agreeing)."""
    from numerics.cli import main

    assert main(["noise", "vdp", "-p", "mu=0.5", "-p", "D=0.5", "--trajectories", "32",
                 "--t-end", "400", "--method", "fokker-planck", "--out", str(tmp_path)]) == 0
    text = capsys.readouterr().out
    rep = json.loads((tmp_path / "noise-vdp.json").read_text())
    v = rep["validity"]
    assert v["flagged"] and "--method fokker-planck" not in v["advice"]
    assert "--order 2" in v["advice"] and "Fokker-Planck column" in v["advice"]
    for k in ("a2", "x2"):
        m = rep["moments"][k]
        assert abs(m["fokker_planck"] - m["simulated"]) < 4 * m["stderr"]
    assert f"WARNING: {v['advice']}" in text and text.count("WARNING") == 1


def test_noise_text_states_the_fokker_planck_error(capsys, tmp_path):
    """The text states the Fokker-Planck values' error (before: the JSON alone had it, as
    the relative ``fokker_planck.hermite_change``): ``+-`` that change times each moment
    (van der Pol mu = 0.1, D = 0.05, the Kramers solve alone: --budget 0, whose refused
    simulation the text no longer calls "simulated")."""
    from numerics.cli import main

    assert main(["noise", "vdp", "-p", "mu=0.1", "-p", "D=0.05", "--budget", "0",
                 "--out", str(tmp_path)]) == 0
    text = capsys.readouterr().out
    assert "  not simulated (refused, below): 100 trajectories" in text  # not "simulated:"
    rep = json.loads((tmp_path / "noise-vdp.json").read_text())
    stated = next(row for row in text.splitlines() if "stated error of the Fokker-Planck" in row)
    change = rep["fokker_planck"]["hermite_change"]
    assert 0 < change < 1e-6
    for k in ("a2", "x2"):
        pm = float(stated.split(f"<{k[0]}^2> +- ")[1].split(",")[0].split()[0])
        assert pm == pytest.approx(change * rep["moments"][k]["fokker_planck"], rel=0.05)


def test_escape_low_barrier_advice_runs_on_the_command_line(capsys):
    """CDC at E_b/kT = 0.39: the warning's "use the simulated first-passage rate" says how
    where the run has none: drop --no-simulation, or raise --budget when the simulation is
    refused for its cost; with a simulation, neither.  The --fp-budget help names no Python
    parameter (it named kramers_escape's max_cost)."""
    from numerics.cli import main

    args = ["escape", "cdc", "-p", "mu=0.1", "-p", "Delta=2", "-p", "D=0.2", "--json"]
    warned = {}
    for extra in (["--no-simulation"], ["--budget", "0"], ["--trajectories", "20",
                                                          "--t-end", "20"]):
        assert main(args + extra) == 0
        warned[extra[0]] = json.loads(capsys.readouterr().out)["warnings"][0]
    assert warned["--no-simulation"].endswith("(drop --no-simulation)")
    assert warned["--budget"].endswith("(raise --budget)")
    assert warned["--trajectories"].endswith("simulated first-passage rate")
    with pytest.raises(SystemExit):
        main(["escape", "--help"])
    assert "max_cost" not in capsys.readouterr().out


def test_escape_names_the_missing_values_as_noise_does(capsys):
    """kbm escape sedf without beta and Delta said "give values for beta, delta" (the scaled
    delta = Delta/mu, which -p does not take for a slider's example): it now names the
    values as kbm noise does, Delta with --param Delta=1."""
    from numerics.cli import main

    for command in ("escape", "noise"):
        assert main([command, "sedf", "-p", "mu=0.1", "-p", "D=0.05"]) == 2
        err = capsys.readouterr().err
        assert "beta, Delta (delta = Delta/mu" in err and "--param Delta=1" in err, err
        assert len(err.strip().splitlines()) == 1


def test_missing_noise_and_bad_times_in_the_command_line_words(capsys):
    """A missing D said "D >= 0" although kbm noise, escape and spectrum refuse D = 0; a
    bad --dt/--t-end/--burn-in echoed Python's float (-1.0 for -1)."""
    from numerics.cli import main

    for command in ("noise", "spectrum"):
        assert main([command, "vdp", "-p", "mu=0.1"]) == 2
        missing = capsys.readouterr().err
        assert "-p D=VALUE" in missing and ">= 0" not in missing
        assert main([command, "vdp", "-p", "mu=0.1", "-p", "D=0"]) == 2  # D = 0 refused
        capsys.readouterr()
    for command, flag in (("noise", "--dt"), ("noise", "--t-end"), ("noise", "--burn-in"),
                          ("escape", "--dt"), ("escape", "--t-end")):
        model = ["vdp", "-p", "mu=0.1"] if command == "noise" else ["cdc", "-p", "mu=0.1",
                                                                    "-p", "Delta=3"]
        assert main([command, *model, "-p", "D=0.1", flag, "-1", "--no-simulation"
                     if command == "escape" else "--budget=0"]) == 2
        assert capsys.readouterr().err.strip().endswith(f"{flag} must be a positive number, "
                                                        "got -1")


def test_escape_fp_budget_is_a_bound_and_the_help_says_so(capsys):
    """kbm escape --fp-budget said "larger solves are skipped", yet at a budget of 10 the
    CDC's Kramers escape solved 90 Hermite functions x 129 Chebyshev points (the first two
    rungs and the grid and sink checks ran whatever they cost); it now bounds every solve:
    the run is refused before solving, with the costs (folded orthonormal functions:
    ``2 n (nc/2 + 1)^2 / 3``, 90 x 129 points: 2.54e5), and the help says so."""
    from numerics.cli import main

    assert main(["escape", "cdc", "-p", "mu=0.1", "-p", "Delta=3", "-p", "D=0.1", "--method",
                 "fokker-planck", "--fp-budget", "10", "--no-simulation", "--json"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"90 x 129 ({2 * 90 * 65**2 / 3:.3g})" in err[0], err
    assert "above --fp-budget 10; raise --fp-budget to" in err[0]
    with pytest.raises(SystemExit):
        main(["escape", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "larger solves are skipped" not in text and "whatever they cost" not in text
    assert "a bound on every solve: refused before solving" in text


@pytest.mark.parametrize("command", ["noise", "escape", "spectrum", "friction"])
def test_noisy_commands_help_names_no_python_module(command, capsys):
    """The help spoke Python: kbm noise --order named kbm.noise.stochastic_order2 and kbm
    escape --dt numerics.noise.langevin.natural_step; the help names the documentation."""
    import re

    from numerics.cli import main

    with pytest.raises(SystemExit):
        main([command, "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert not re.search(r"\b(?:kbm|numerics)\.[a-z_]+\.", text), text


def test_an_unconverged_fokker_planck_column_is_not_called_the_reference():
    """A Fokker-Planck column whose stated error (SEDF at --fp-budget 1e6: relative 0.3,
    <a^2> +- 0.95) exceeds the simulation's standard error, or is not measured, is no
    sharper than the simulation: the advice asks for --fp-budget instead of naming it the
    reference; within the standard error it stays the reference."""
    moments = {"a2": {"averaged": 4.0, "simulated": 4.02, "stderr": 0.013,
                      "fokker_planck": 3.2},
               "x2": {"averaged": 2.11486, "simulated": 2.32239, "stderr": 0.0087,
                      "fokker_planck": 2.1}}
    for error in ({"a2": 0.95, "x2": 0.61}, {"a2": None, "x2": None}):
        advice = validity(moments, 1, False, None, error)["advice"]
        assert "reference" not in advice and "raise --fp-budget" in advice
        assert "--method fokker-planck" not in advice
    sharp = validity(moments, 1, False, None, {"a2": 1e-8, "x2": 1e-8})["advice"]
    assert "is the reference" in sharp and "--fp-budget" not in sharp
