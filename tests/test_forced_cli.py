"""``kbm response``: the JSON contract, the forcing syntax and one-line errors."""

from __future__ import annotations

import json

import pytest

from numerics.cli import main

DUFF = ["-p", "mu=0.05", "-p", "zeta=0.1", "-p", "alpha=1", "-p", "h=0.5"]


def _json(capsys, argv):
    assert main(argv) == 0
    return json.loads(capsys.readouterr().out)


def test_json_contract(capsys, tmp_path):
    d = _json(capsys, ["response", "duffing-forced", *DUFF, "--vary", "sigma=-1:3:120",
                       "--order", "2", "--amax", "3", "--json", "--out", str(tmp_path)])
    assert d["order"] == 2 and d["resonance"] == "1/1"
    assert {"sigma", "amplitude", "stable"} <= set(d["analytic"][0])
    assert {"sigma", "amplitude_max", "stable"} <= set(d["numeric"][0])
    assert len(d["folds"]) == 2 and {"sigma", "amplitude"} == set(d["folds"][0])
    assert {p["stable"] for p in d["analytic"]} == {True, False}
    assert {p["stable"] for p in d["numeric"]} == {True, False}
    # the analytic and the true lower jump agree to O(mu^2)
    assert abs(d["folds"][0]["sigma"] - d["numeric_folds"][0]["sigma"]) < 1e-3
    assert (tmp_path / "response.png").stat().st_size > 10_000


def test_forcing_added_to_an_autonomous_model(capsys):
    d = _json(capsys, ["response", "duffing", "--forcing", "h*cos(theta)", "-p", "mu=0.05",
                       "-p", "h=0.5", "--vary", "sigma=-1:1:40", "--no-numeric", "--json"])
    assert d["numeric"] == [] and d["analytic"]
    assert "sin(phi)" in d["slow_flow"]["da/dt"]


def test_rhs_with_theta_and_resonance(capsys):
    d = _json(capsys, ["response", "--rhs", "-2*zeta*xdot - x**3 - h*x*cos(theta)",
                       "--resonance", "2", "-p", "mu=0.05", "-p", "zeta=0.05", "-p", "h=1",
                       "--vary", "sigma=-1:1.5:60", "--amax", "3", "--json"])
    assert d["resonance"] == "2/1"
    assert any(p["amplitude"] == 0.0 for p in d["analytic"])  # the trivial state


@pytest.mark.parametrize("argv, words", [
    (["response", "duffing", "--forcing", "t*x", "--vary", "sigma=0:1"], "the time t itself"),
    (["response", "duffing", "--forcing", "cos(theta/2)", "--vary", "sigma=0:1"],
     "not 2*pi-periodic"),
    (["response", "duffing", "--vary", "sigma=0:1"], "has no forcing"),
    (["response", "duffing-forced", "--vary", "h=0:1"], "varies the detuning"),
    (["response", "duffing-forced", "--vary", "sigma=0"], "sigma=FROM:TO"),
    (["response", "duffing-forced", "--vary", "sigma=0:1", "--resonance", "x"], "p/q"),
    (["response", "duffing-forced", "--vary", "sigma=0:1", "-p", "zeta=1"], "mu"),
    (["response", "nope", "--forcing", "cos(theta)", "--vary", "sigma=0:1"], "unknown model"),
])
def test_one_line_errors(capsys, argv, words):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and words in err, err


def test_detuning_mode(capsys):
    d = _json(capsys, ["response", "duffing-forced", *DUFF, "--detuning", "1", "--order", "3",
                       "--json"])
    assert [p["stable"] for p in d["analytic"]] == [True, False, True]
    assert [p["stable"] for p in d["numeric"]] == [True, False, True]
    for p, q in zip(d["analytic"], d["numeric"]):
        assert abs(p["amplitude"] - q["amplitude"]) < 1e-3
    assert main(["response", "duffing-forced", *DUFF]) == 2
    assert "either --vary" in capsys.readouterr().err


def test_fixed_frequency_names_the_undeclared_resonance(capsys):
    assert main(["response", "duffing-forced", "--nu", "0.98", "-p", "h=1"]) == 2
    err = capsys.readouterr().err
    assert "resonance nu = 1 omega0" in err and "--resonance 1/1" in err
    d = _json(capsys, ["response", "duffing-forced", "--nu", "0.5", "--order", "2", "--json"])
    assert d["resonance"] is None and "phi" not in d["A"][1]


def test_hard_forcing_flag(capsys):
    d = _json(capsys, ["response", "duffing", "--hard", "K", "--resonance", "1/3", "-p",
                       "mu=0.02", "-p", "K=1", "--detuning", "0", "--order", "2", "--json"])
    assert d["resonance"] == "1/3" and len(d["analytic"]) == 1 and len(d["numeric"]) == 1
    assert abs(d["analytic"][0]["amplitude"] - d["numeric"][0]["amplitude"]) < 1e-3
