"""The parameter layer in ``kbm cycle``, ``predict``, ``compare``, ``series`` and ``derive``
(issue 35, "one parameter and option layer for every command"): ``-p`` is read by
:func:`kbm.cli._common.checked_params` against :class:`kbm.parameters.values.ParameterNames`, as in
``kbm friction``, ``noise``, ``branch`` and ``lock``: an unknown name is refused with the
closest valid one and every valid one, in ``-p`` terms; the paper's physical names are
taken and converted to the scaled ones (eq. 3: ``delta = Delta/mu``, ``k = 2 pi/lam``).
Each test is the command as a user types it (exit 2 and one line for bad input)."""

from __future__ import annotations

import json

import pytest

from numerics.cli import main

SEDF = ("mu", "Delta", "lam", "delta", "k", "Omega", "beta")


def _err(capsys) -> str:
    out = capsys.readouterr()
    lines = out.err.strip().splitlines()
    assert len(lines) == 1, out.err
    return lines[0]


def _json(argv, capsys) -> dict:
    assert main([*argv, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


@pytest.mark.parametrize("argv, bad, near, model, valid", [
    (["cycle", "sedf", "-p", "Mu=0.1", "-p", "Delta=3", "-p", "beta=1", "-p", "lam=1"],
     "Mu", "mu", "sedf", SEDF),
    (["predict", "sedf", "-p", "lamda=1"], "lamda", "lam", "sedf", SEDF),
    (["compare", "vdp", "-p", "mu=0.1", "-p", "Beta=1"], "Beta", None, "vdp", ("mu",)),
    (["compare", "vdp", "--convergence", "0.1,0.05", "-p", "Mu=1"], "Mu", "mu", "vdp",
     ("mu",)),
    (["series", "vdp", "--order", "3", "-p", "Mu=1"], "Mu", "mu", "vdp", ("mu",)),
    (["derive", "sedf", "--order", "1", "-p", "lamda=1"], "lamda", "lam", "sedf", SEDF),
    (["derive", "--rhs", "-b*x**3", "--order", "1", "-p", "B=1"], "B", "b", "custom",
     ("mu", "b")),
    (["cycle", "coupled-vdp", "-p", "Mu=0.1"], "Mu", "mu", "coupled-vdp", ("mu", "c")),
    (["derive", "coupled-vdp", "--order", "1", "-p", "C=0.1"], "C", "c", "coupled-vdp",
     ("mu", "c")),
])
def test_unknown_name_is_refused_with_the_valid_ones(argv, bad, near, model, valid, capsys):
    assert main(argv) == 2
    err = _err(capsys)
    assert f"unknown parameter '{bad}' for {model}" in err and f"-p {bad}=" in err
    assert (f"did you mean {near}?" in err) if near else "did you mean" not in err
    listed = err.split("its parameters are ")[1]
    assert all(v in listed for v in valid), err


@pytest.mark.parametrize("command", [["cycle", "sedf"], ["predict", "sedf"],
                                     ["derive", "sedf", "--order", "1"]])
def test_scaled_and_physical_of_one_parameter_refused(command, capsys):
    assert main([*command, "-p", "mu=0.1", "-p", "delta=30", "-p", "Delta=3"]) == 2
    assert "give either delta or Delta (delta = Delta/mu), not both" in _err(capsys)


def test_stage_velocity_keeps_the_models_answer(capsys):
    """``v`` is the sliders' stage velocity (kbm slide, kbm friction); here the model says
    which take one, and that a limit cycle needs the autonomous model."""
    assert main(["cycle", "vdp", "-p", "mu=0.1", "-p", "v=1"]) == 2
    assert "only the sliders" in _err(capsys)
    assert main(["cycle", "sedf", "-p", "mu=0.1", "-p", "Delta=3", "-p", "beta=1",
                 "-p", "lam=1", "-p", "v=0.1"]) == 2
    assert "autonomous" in _err(capsys)


# -- the physical names are converted (paper eq. 3: delta = Delta/mu) ------------------------

def test_cycle_physical_delta_is_the_scaled_one(capsys):
    base = ["cycle", "sedf", "-p", "mu=0.1", "-p", "beta=1", "-p", "lam=1"]
    phys = _json([*base, "-p", "Delta=3"], capsys)
    scaled = _json([*base, "-p", "delta=30"], capsys)
    assert phys["params_given"]["Delta"] == "3" and scaled["params_given"]["delta"] == "30"
    for key in ("period", "amplitude_max", "amplitude_first_harmonic"):
        assert phys[key] == pytest.approx(scaled[key], rel=1e-10), key


def test_predict_physical_delta_is_the_scaled_one(capsys):
    base = ["predict", "sedf", "-p", "mu=0.1", "-p", "beta=1", "-p", "lam=1"]
    phys = _json([*base, "-p", "Delta=3"], capsys)["cycles"]
    scaled = _json([*base, "-p", "delta=30"], capsys)["cycles"]
    assert len(phys) == len(scaled) >= 1
    for p, s in zip(phys, scaled):
        assert p["amplitude_max"] == pytest.approx(s["amplitude_max"], rel=1e-12)
        assert p["period"] == pytest.approx(s["period"], rel=1e-12)


def test_derive_physical_delta_is_the_scaled_one(capsys):
    """The exact expansion is the same expression (``Delta = 3, mu = 1/10`` is
    ``delta = 30``)."""
    base = ["derive", "sedf", "--order", "1", "-p", "beta=1"]
    phys = _json([*base, "-p", "mu=0.1", "-p", "Delta=3"], capsys)
    scaled = _json([*base, "-p", "delta=30"], capsys)
    assert phys["A"] == scaled["A"] and phys["B"] == scaled["B"]


# -- kbm compare --convergence holds the scaled parameters fixed while mu varies ----------

def test_convergence_refuses_mu_and_physical_names(capsys):
    base = ["compare", "sedf", "--convergence", "0.1,0.05", "--orders", "1"]
    assert main([*base, "-p", "mu=0.1"]) == 2
    assert "--convergence gives the values of mu" in _err(capsys)
    assert main([*base, "-p", "Delta=3", "-p", "beta=1", "-p", "lam=1"]) == 2
    err = _err(capsys)
    assert "give -p delta=VALUE (delta = Delta/mu) instead of -p Delta" in err


# -- kbm derive and kbm series: the expansion is in powers of mu --------------------------

@pytest.mark.parametrize("argv, says", [
    (["series", "vdp", "--order", "3", "-p", "mu=1"], "--float --at MU"),
    (["derive", "vdp", "--order", "1", "-p", "mu=0.3"], "does not depend on it"),
    (["derive", "sedf", "--order", "1", "-p", "mu=0.3", "-p", "delta=3"],
     "only converts Delta, lam"),
])
def test_mu_that_sets_nothing_is_refused(argv, says, capsys):
    """``-p mu`` was silently dropped by these commands; it converts a physical name only."""
    assert main(argv) == 2
    err = _err(capsys)
    assert "-p mu sets nothing here" in err and says in err


@pytest.mark.parametrize("fraction, decimal", [
    # a ValueError traceback (could not convert string to float: '1/50'), exit 1
    (["escape", "cdc", "-p", "mu=1/50", "-p", "Delta=3", "-p", "D=7/1000", "--no-simulation"],
     ["escape", "cdc", "-p", "mu=0.02", "-p", "Delta=3", "-p", "D=0.007", "--no-simulation"]),
    (["spectrum", "vdp", "-p", "mu=1/10", "-p", "D=1/100", "--no-simulation"],
     ["spectrum", "vdp", "-p", "mu=0.1", "-p", "D=0.01", "--no-simulation"]),
])
def test_noisy_commands_read_fractions_as_every_command_does(fraction, decimal, capsys):
    """``-p mu=1/50`` is read as ``kbm cycle`` reads it: the double nearest 1/50 is
    ``float('0.02')``, so the JSON is the decimal input's, byte for byte."""
    assert main([*fraction, "--json"]) == 0
    got = capsys.readouterr().out
    assert main([*decimal, "--json"]) == 0
    assert got == capsys.readouterr().out


def test_noise_prints_a_temperature_given_as_a_fraction(capsys):
    """``kbm noise vdp -p mu=1/20 -p T=1/5`` ran its ensemble, then died on printing ``T``
    (a ValueError traceback, exit 1).  ``D = mu T = 1/100``."""
    assert main(["noise", "vdp", "-p", "mu=1/20", "-p", "T=1/5", "--trajectories", "8",
                 "--t-end", "200", "--no-fokker-planck"]) == 0
    head = capsys.readouterr().out.splitlines()[0]
    assert head.endswith("D = 0.01 (T = D/mu = 0.2)"), head


@pytest.mark.parametrize("command, key", [
    (["escape", "cdc", "-p", "mu=0.02", "-p", "Delta=3", "-p", "D=0.007", "--no-simulation"],
     ("rate_averaged",)),
    pytest.param(["noise", "cdc", "-p", "mu=0.1", "-p", "Delta=3", "-p", "D=0.05", "--budget",
                  "0", "--no-fokker-planck"], ("moments", "x2", "averaged"),
                 marks=pytest.mark.slow),  # 7 s (the CDC's envelope); escape's in the default run
])
def test_noisy_commands_take_the_scaled_wavenumber(command, key, capsys):
    """``-p k=...`` (the scaled name of ``lam``, one of each pair) was refused by ``kbm
    escape cdc`` and ``kbm noise cdc`` with "give either k or lam, not both": the command
    had put its default ``lam = 1`` beside it.  ``k = 2 pi/lam`` (paper eq. 3): ``k = 2 pi``
    gives the values of ``lam = 1``."""
    import math

    def value(extra):
        data = _json([*command, "-p", extra], capsys)
        for k in key:
            data = data[k]
        return data

    assert value(f"k={2 * math.pi!r}") == pytest.approx(value("lam=1"), rel=1e-9)


@pytest.mark.slow  # 4-8 s; kept out of the default run (five-minute rule)
def test_spectrum_of_a_slider_takes_the_stage_defaults_as_noise_and_escape(capsys):
    """``kbm spectrum sedf`` without ``lam`` and ``Omega`` asked for ``lam`` ("needs values for
    lam"), where ``kbm noise`` and ``kbm escape`` take the paper's ``Omega = 1``, ``lam = 1``
    (eq. 3, :data:`kbm.model.builtins.SLIDER_DEFAULTS`): now the same line as with them
    typed."""
    argv = ["spectrum", "sedf", "-p", "mu=0.1", "-p", "Delta=3", "-p", "beta=1", "-p", "D=0.01",
            "--trajectories", "8"]
    bare = _json(argv, capsys)
    typed = _json([*argv, "-p", "lam=1", "-p", "Omega=1"], capsys)
    assert bare.pop("params") == typed.pop("params")  # the same values (dicts: any order)
    assert bare == typed
