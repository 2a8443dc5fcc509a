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
from numerics.thermal.stationary import noise_report, validity
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
