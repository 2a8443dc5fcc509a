"""The one parameter and option layer (issue 35, items 1, 2, 3, 5, 6; issue 40, items 1, 2, 5,
6, 7, 8): every command reads ``-p`` and ``--vary`` through :mod:`numerics.cli.params.values` and
:mod:`kbm.parameters.names`, refuses unknown names with the valid ones listed, converts the paper's
physical parameters to the scaled ones and back (eqs. 3 and 12: ``delta = Delta/mu``,
``k = 2 pi/lam``), takes ``D`` or ``T = D/mu`` wherever noise applies, and speaks in
command-line terms.  Each test is the command as a user types it."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from kbm.errors import ParameterError
from kbm.parameters.names import names_of, noise_from, to_physical
from numerics.cli import main
from numerics.cli.params.values import parse_vary

VALID = ("mu", "Delta", "lam", "delta", "k", "Omega", "D", "T")


def _err(capsys) -> str:
    out = capsys.readouterr()
    lines = out.err.strip().splitlines()
    assert len(lines) == 1, out.err
    return lines[0]


# -- issue 35, item 1: kbm friction refuses unknown names, with the valid ones listed -----

@pytest.mark.parametrize("bad, near", [("Mu=1", "mu"), ("omega=2", "Omega"), ("Beta=1", None),
                                       ("d=0.01", "D"), ("t=0.01", "T")])
def test_friction_refuses_unknown_names(bad, near, capsys):
    assert main(["friction", "cdc", "-p", "Delta=3", "-p", bad, "--vary", "v=0.01,0.1",
                 "--no-progress"]) == 2
    err = _err(capsys)
    name = bad.split("=")[0]
    assert f"unknown parameter '{name}' for cdc" in err
    assert all(v in err for v in VALID), err
    assert (f"did you mean {near}?" in err) if near else "did you mean" not in err


def test_friction_refuses_unknown_axis(capsys):
    assert main(["friction", "cdc", "-p", "Delta=3", "--vary", "v=0.01",
                 "--vary", "gamma=1,2", "--no-progress"]) == 2
    assert "cannot vary 'gamma': it is not a parameter of cdc" in _err(capsys)


# -- item 2: physical and scaled names ---------------------------------------------------

def test_missing_delta_is_asked_for_in_physical_terms(capsys):
    assert main(["friction", "cdc", "--vary", "v=1e-3:1:log8", "--no-progress"]) == 2
    err = _err(capsys)
    assert "--param Delta=" in err and "delta = Delta/mu" in err
    assert "--param delta=" not in err and "params=" not in err


def test_scaled_delta_gives_the_prandtl_tomlinson_eta(capsys):
    """``-p delta=30`` at the default mu = 0.1 is Delta = 3: eta = 2 pi Delta/(Omega^2 lam)
    = 6 pi = 18.85 (not 0), and the same forces as ``-p Delta=3``."""
    argv = ["friction", "cdc", "--vary", "v=0.01", "--json", "--no-progress"]
    assert main([*argv, "-p", "delta=30"]) == 0
    scaled = json.loads(capsys.readouterr().out)
    assert main([*argv, "-p", "Delta=3"]) == 0
    physical = json.loads(capsys.readouterr().out)
    assert scaled["eta"][0] == pytest.approx(6 * math.pi, rel=1e-12)
    assert scaled["params"]["Delta"] == 3.0 and "delta" not in scaled["params"]
    assert scaled["mean_force"] == physical["mean_force"]


def test_slide_takes_the_scaled_names(capsys):
    """kbm slide with -p delta=30 (a KeyError traceback before) is the run with Delta = 3 at
    mu = 0.1, byte for byte; without mu the conversion asks for it."""
    base = ["slide", "cdc", "-p", "mu=0.1", "-p", "v=0.1", "--t-end", "10", "--json"]
    assert main([*base, "-p", "delta=30"]) == 0
    scaled = capsys.readouterr().out
    assert main([*base, "-p", "Delta=3"]) == 0
    assert scaled == capsys.readouterr().out
    assert main(["slide", "cdc", "-p", "delta=30", "-p", "v=0.1", "--t-end", "10"]) == 2
    assert "-p mu=VALUE" in _err(capsys)


@given(st.fractions(min_value=1, max_value=100), st.fractions(min_value=1, max_value=50),
       st.fractions(min_value="1/100", max_value=1))
@settings(max_examples=15, deadline=None)
def test_physical_and_scaled_round_trip(Delta, lam, mu):
    """resolve (physical -> scaled) and to_physical (scaled -> physical) are inverse, exactly
    (delta = Delta/mu, k = 2 pi/lam)."""
    from kbm.model.builtins import get_model

    model = get_model("cdc")
    names = names_of(model)
    scaled = model.resolve({"mu": str(mu), "Delta": str(Delta), "lam": str(lam)},
                           use_defaults=False)
    back = to_physical(names, {"mu": scaled["mu"], "delta": scaled["delta"],
                               "k": scaled["k"]})
    assert sp.simplify(back["Delta"] - sp.Rational(Delta)) == 0
    assert sp.simplify(back["lam"] - sp.Rational(lam)) == 0


# -- item 3: T = D/mu wherever noise applies ---------------------------------------------

def test_noise_takes_T_as_D_over_mu(capsys):
    """``-p T=1`` at mu = 0.1 is D = 0.1: the same report, byte for byte, as ``-p D=0.1``."""
    base = ["noise", "linear_damping", "-p", "mu=0.1", "-p", "zeta=0.5", "--trajectories", "8",
            "--t-end", "20",
            "--burn-in", "2", "--json"]
    assert main([*base, "-p", "T=1"]) == 0
    by_T = json.loads(capsys.readouterr().out)
    assert main([*base, "-p", "D=0.1"]) == 0
    by_D = json.loads(capsys.readouterr().out)
    assert by_T["D"] == pytest.approx(0.1, rel=1e-15)
    assert by_T["moments"] == by_D["moments"]


def test_escape_takes_T(capsys):
    base = ["escape", "cdc", "-p", "mu=0.1", "-p", "Delta=3", "--no-simulation", "--json"]
    assert main([*base, "-p", "T=1"]) == 0
    by_T = json.loads(capsys.readouterr().out)
    assert main([*base, "-p", "D=0.1"]) == 0
    assert by_T == json.loads(capsys.readouterr().out)
    assert by_T["kT"] == pytest.approx(1.0, rel=1e-12)


def test_noise_lists_D_and_T(capsys):
    assert main(["noise", "cdc", "-p", "mu=0.1", "-p", "Delta=3", "-p", "Tx=1"]) == 2
    err = _err(capsys)
    assert "D or T = D/mu" in err
    assert main(["noise", "cdc", "-p", "mu=0.1", "-p", "Delta=3", "-p", "D=0.1",
                 "-p", "T=1"]) == 2
    assert "D or as T = D/mu, not both" in _err(capsys)
    assert main(["noise", "cdc", "-p", "mu=0.1", "-p", "Delta=3"]) == 2
    err = _err(capsys)
    assert "-p D=VALUE" in err and "-p T=VALUE" in err


def test_negative_temperature_is_named_T(capsys):
    assert main(["friction", "cdc", "-p", "Delta=3", "--vary", "v=0.01",
                 "--vary", "T=-0.01,0.04", "--no-progress"]) == 2
    err = _err(capsys)
    assert "T = -0.01 is negative" in err and "D =" not in err


def test_noise_from_converts_T_exactly():
    rest, D, name = noise_from({"mu": "1/10", "T": "3"})
    assert (D, name, rest) == (sp.Rational(3, 10), "T", {"mu": "1/10"})
    with pytest.raises(ParameterError, match="needs mu > 0"):
        noise_from({"mu": "-1", "T": "1"})


# -- item 5: kbm derive --nu0 --------------------------------------------------------------

def test_derive_forced_coupled_system_from_the_command_line(capsys):
    """A forced coupled system with theta in --rhs derives with --nu0: the JSON equals the
    Python API's (kbm.expansion.coupled.derive_coupled of coupled_custom(..., nu0=1))."""
    from kbm.model.coupled_builtins import coupled_custom
    from kbm.expansion.coupled import derive_coupled

    rhs = ["-x1**3 + h*cos(theta) - 2*zeta*xdot1", "-2*zeta*xdot2 - x2**3 + c*x1**3"]
    internal = ["1:3", "1:1@1,F"]
    argv = ["derive", "--rhs", rhs[0], "--rhs", rhs[1], "--omega0", "1,3",
            "--internal", internal[0], "--internal", internal[1], "--order", "2", "--json"]
    assert main(argv) == 2
    assert "give --nu0 NU0" in _err(capsys)
    assert main([*argv, "--nu0", "1"]) == 0
    cli = json.loads(capsys.readouterr().out)
    api = derive_coupled(coupled_custom(rhs, "1,3", nu0=1), 2, internal=internal).to_json()
    assert cli == json.loads(json.dumps(api))


# -- item 6 and issue 40, item 8: command-line terms ------------------------------------

def test_no_api_words_in_messages():
    from kbm.cli import cli_message

    for api in ("the stage velocity v is missing: make it an axis (axes={'v': [...]}) or fix "
                "it", "pass --resume (resume=True) to continue it",
                "no steady state within 10 stage periods; raise max_wells or max_periods",
                "no locked state near [np.float64(2.0), np.float64(2.0)] at c = 0",
                "needs values for Delta, beta (e.g. params={'Delta': 1, 'beta': 1})"):
        msg = cli_message(api)
        for word in ("axes=", "resume=True", "max_wells", "np.float64", "params="):
            assert word not in msg, msg
    assert "--param Delta=1 --param beta=1" in cli_message(
        "(e.g. params={'Delta': 1, 'beta': 1})")


def test_unknown_model_lists_every_kind_and_rhs_only_where_taken(capsys):
    assert main(["branch", "sedf-dimmer", "--vary", "mu=0.1:1"]) == 2
    err = _err(capsys)
    assert "did you mean sedf-dimer?" in err and "coupled-vdp" in err and "--rhs" in err
    assert main(["noise", "vdpp", "-p", "D=0.1"]) == 2
    err = _err(capsys)
    assert "did you mean vdp?" in err and "--rhs" not in err


def test_misspelt_parameter_is_named(capsys):
    assert main(["branch", "sedf", "-p", "mu=0.1", "-p", "beta=1", "-p", "lamda=1",
                 "--vary", "Delta=0.5:1"]) == 2
    err = _err(capsys)
    assert "unknown parameter 'lamda'" in err and "did you mean lam?" in err
    assert "cannot vary" not in err


def test_escape_hint_fits_the_model(capsys):
    assert main(["escape", "vdp", "-p", "mu=0.1", "-p", "D=0.1", "--no-simulation"]) == 2
    assert "larger Delta" not in _err(capsys)


def test_noise_help_says_what_dt_is(capsys):
    with pytest.raises(SystemExit):
        main(["noise", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "1e-3 of kT" in text and "whole number of steps" in text


# -- issue 40, item 1: an option the mode ignores is an error ---------------------------

@pytest.mark.parametrize("argv", [
    ["branch", "vdp", "--vary", "mu=0.1:1", "--follow-period", "20"],
    ["branch", "coupled-vdp", "-p", "mu=0.1", "-p", "sigma=0", "--vary", "c=0.05:1",
     "--follow-period", "5"],
])
def test_follow_period_without_a_homoclinic_end_is_refused(argv, capsys):
    assert main(argv) == 2
    assert "--follow-period" in _err(capsys)


# -- issue 40, item 2: kbm lock ------------------------------------------------------------

def test_lock_with_only_the_coupling_names_the_detuning(capsys):
    assert main(["lock", "coupled-vdp", "-p", "mu=0.1", "--vary", "c=0.1:0.5"]) == 2
    err = _err(capsys)
    assert "--vary sigma=FROM:TO" in err and "at c = 0" not in err and "np." not in err


def test_lock_tongue_header_has_the_coupling_range(capsys):
    assert main(["lock", "coupled-vdp", "-p", "mu=0.1", "--vary", "sigma=-2:2",
                 "--vary", "c=0.05:0.6", "--points", "2", "--order", "1"]) == 0
    head = capsys.readouterr().out.splitlines()[0]
    assert "c=0.3" not in head and "c from 0.05 to 0.6, 2 values" in head


# -- issue 40, item 7: one --vary grammar ------------------------------------------------

def test_one_vary_grammar():
    v = parse_vary("v=1e-3:3:log4")
    assert np.allclose(v.values(), [1e-3, 0.0144225, 0.208008, 3], rtol=1e-5)
    assert list(parse_vary("Delta=1:2").values()) == list(np.linspace(1, 2, 8))
    assert parse_vary("beta=2,0.5,1").values().tolist() == [2, 0.5, 1]
    assert parse_vary("sigma=-1:1").interval("a branch") == (-1, 1)
    for bad in ("v=1:1", "v=2:1", "v=0:1:log3", "v", "v=a:b", "v=1:2:3:4", "v=1:2:0"):
        with pytest.raises(ParameterError, match="--vary"):
            parse_vary(bad)
    with pytest.raises(ParameterError, match="runs over an interval"):
        parse_vary("sigma=-1,1").interval("a branch")


@pytest.mark.parametrize("argv", [
    ["friction", "cdc", "-p", "Delta=3", "--vary", "v=3:1e-3:log8", "--no-progress"],
    ["lock", "coupled-vdp", "-p", "mu=0.1", "--vary", "sigma=1:-1"],
    ["branch", "vdp", "--vary", "mu=2:1"],
    ["response", "duffing-forced", "-p", "mu=0.1", "--vary", "sigma=1:-1"],
])
def test_a_range_typed_downwards_is_refused_everywhere(argv, capsys):
    """The one rule (issue 40, item 7): a range is an interval, FROM < TO, in every command
    (kbm friction accepted v=3:1e-3 and ran its table downwards; kbm lock refused); the
    message turns the range round."""
    assert main(argv) == 2
    err = _err(capsys)
    name, spec = argv[argv.index("--vary") + 1].split("=")
    a, b, *rest = spec.split(":")
    assert "FROM < TO in every command" in err
    assert f"--vary {name}={b}:{a}" in err


# -- issue 40, item 6: --resume with a store of another run -------------------------------

def test_resume_with_another_run_says_so(tmp_path, capsys):
    store = str(tmp_path / "map.sqlite")
    base = ["friction", "cdc", "-p", "Delta=3", "--no-progress", "--json", "--store", store]
    assert main([*base, "--vary", "v=0.5"]) == 0
    capsys.readouterr()
    assert main([*base, "--vary", "v=0.6", "--resume"]) == 2
    err = _err(capsys)
    assert "another map" in err and "nothing can be resumed" in err
    assert main([*base, "--vary", "v=0.5", "--resume"]) == 0


def test_resume_of_a_command_of_several_runs_continues_its_later_runs(tmp_path):
    """A command of several runs (kbm spectrum coupled-vdp over detunings, one run each)
    interrupted in its first run has nothing of its later ones: resumed, the first run is
    tested against the file and the later ones start from scratch (they were refused as
    "another run", and the resumed command failed; a file of another command is still
    refused at its first run)."""
    from numerics.cli.params.values import open_store
    from numerics.store import StoreError

    path = str(tmp_path / "runs.sqlite")
    with open_store(path, False) as store:
        store.run("detuning 0.2", 2).save(0, [1.0])  # interrupted in the first run
    with open_store(path, True) as store:
        first = store.run("detuning 0.2", 2)
        assert first.load() == {0: [1.0]}
        assert store.run("detuning 0.45", 2).load() == {}  # the second, from scratch
    with open_store(path, True) as store, pytest.raises(StoreError, match="another run"):
        store.run("another command", 2)


def test_against_the_same_model_names_it_once(capsys):
    """``--against cdc`` on cdc: the valid names are cdc's, said once ("for cdc", not "for
    cdc or cdc"); against another model, a name of either is valid."""
    assert main(["friction", "cdc", "-p", "Delta=3", "-p", "Bet=1", "--vary", "v=2,4",
                 "--against", "cdc"]) == 2
    err = _err(capsys)
    assert "for cdc (" in err and "cdc or cdc" not in err
    assert main(["friction", "sedf", "-p", "Delta=3", "-p", "Bet=1", "--vary", "v=2,4",
                 "--against", "cdc"]) == 2
    assert "for sedf or cdc" in _err(capsys)


# -- issue 35, "one parameter and option layer": every command, the same three refusals ------

#: each command that takes -p, as a user types it, cut short by the option under test
COMMANDS = {
    "predict": ["predict", "vdp"],
    "cycle": ["cycle", "vdp", "-p", "mu=1"],
    "cycle coupled": ["cycle", "coupled-vdp", "-p", "mu=0.1", "-p", "c=0.2"],
    "compare": ["compare", "vdp", "-p", "mu=1"],
    "compare --convergence": ["compare", "vdp", "--convergence", "0.1,0.2"],
    "slide": ["slide", "cdc", "-p", "mu=0.1", "-p", "Delta=3", "-p", "v=0.1", "--t-end", "5"],
    "derive": ["derive", "vdp", "--order", "1"],
    "derive coupled": ["derive", "coupled-vdp", "--order", "1"],
    "series": ["series", "vdp", "--order", "1"],
    "branch": ["branch", "vdp", "--vary", "mu=0.1:1"],
    "branch coupled": ["branch", "coupled-vdp", "-p", "mu=0.1", "-p", "sigma=0",
                       "--vary", "c=0.1:0.5"],
    "lock": ["lock", "coupled-vdp", "-p", "mu=0.1", "--vary", "sigma=-1:1"],
    "response": ["response", "duffing-forced", "-p", "mu=0.1", "--vary", "sigma=0:1",
                 "--no-numeric"],
    "response --detuning": ["response", "duffing-forced", "-p", "mu=0.1", "--detuning", "0",
                            "--no-numeric"],
    "response --nu": ["response", "duffing-forced", "-p", "mu=0.1", "--nu", "0.5"],
    "response --convergence": ["response", "duffing-forced", "--convergence", "0.1,0.2,0.3",
                               "--detuning", "0"],
    "response coupled": ["response", "duffing-1-3", "-p", "mu=0.1", "--vary", "sigma=0:1"],
    "friction": ["friction", "cdc", "-p", "Delta=3", "--vary", "v=0.1", "--no-progress"],
    "noise": ["noise", "cdc", "-p", "mu=0.1", "-p", "Delta=3", "-p", "D=0.1"],
    "escape": ["escape", "cdc", "-p", "mu=0.1", "-p", "Delta=3", "-p", "D=0.1",
               "--no-simulation"],
    "spectrum": ["spectrum", "vdp", "-p", "mu=0.1", "-p", "D=0.01", "--no-simulation"],
    "spectrum forced": ["spectrum", "duffing-forced", "-p", "mu=0.1", "-p", "D=0.01",
                        "--vary", "sigma=0:1"],
    "diagram": ["diagram", "sedf", "-p", "mu=0.1", "--vary", "Delta=0:6",
                "--vary", "beta=0.3:1.6"],
}
NOISY = ("friction", "noise", "escape", "spectrum", "spectrum forced")


@pytest.mark.parametrize("command", list(COMMANDS))
def test_every_command_refuses_an_unknown_name_with_the_valid_ones(command, capsys):
    """``-p Mu=1``: one line, exit 2, the close name and the list of valid names (``mu``
    first), in ``-p`` terms; before, ``kbm response`` answered in the library's words
    ("for model 'duffing-forced'; its parameters are alpha, h, zeta (and mu, sigma)")."""
    assert main([*COMMANDS[command], "-p", "Mu=1"]) == 2
    err = _err(capsys)
    assert "unknown parameter 'Mu'" in err and "(did you mean mu?)" in err, err
    assert "(in -p Mu=...); its parameters are mu" in err, err
    assert "for model '" not in err, err


@pytest.mark.parametrize("command", list(COMMANDS))
def test_every_command_takes_D_or_T_where_noise_applies_and_refuses_it_elsewhere(command,
                                                                                 capsys):
    """Where noise applies, ``D`` and ``T = D/mu`` are both names of it and together are
    refused; elsewhere ``T`` is refused as a name the command has not, saying why."""
    extra = ["-p", "T=1"] + (["-p", "D=0.1"] if command == "friction" else [])
    assert main([*COMMANDS[command], *extra]) == 2
    err = _err(capsys)
    if command in NOISY:
        assert err.endswith("give the noise as D or as T = D/mu, not both"), err
    else:
        assert "unknown parameter 'T'" in err and "(this command has no noise)" in err, err


VARIED = [c for c in COMMANDS if "--vary" in COMMANDS[c]]


@pytest.mark.parametrize("bad, words", [
    ("=1:2:3:4", "--vary takes NAME=FROM:TO[:N]"),
    ("=2:1", "FROM < TO in every command"),
    ("=a:b", "--vary takes NAME=FROM:TO[:N]"),
])
@pytest.mark.parametrize("command", VARIED)
def test_every_vary_has_one_grammar(command, bad, words, capsys):
    """A malformed or downward ``--vary`` of the name each command varies: the same message
    from every command (one grammar, :func:`numerics.cli.params.values.parse_vary`)."""
    argv = list(COMMANDS[command])
    i = argv.index("--vary") + 1
    name = argv[i].split("=")[0]
    argv[i] = name + bad
    assert main(argv) == 2
    err = _err(capsys)
    assert words in err and f"{name}{bad}" in err, err


@pytest.mark.parametrize("command", VARIED)
def test_every_vary_refuses_a_name_the_model_has_not(command, capsys):
    argv = list(COMMANDS[command])
    i = argv.index("--vary") + 1
    argv[i] = "omega=0:1"
    assert main(argv) == 2
    err = _err(capsys)
    assert "omega" in err and ("cannot vary 'omega'" in err
                               or "--vary sigma=FROM:TO" in err), err


def test_response_refuses_sigma_as_a_parameter(capsys):
    """The detuning is ``--detuning`` or ``--vary sigma``; ``-p sigma`` was silently
    dropped by the library's reading of the values (``sigma`` among "mu, sigma")."""
    assert main([*COMMANDS["response --detuning"], "-p", "sigma=1"]) == 2
    assert "sigma is the detuning: give it as --detuning 1" in _err(capsys)
    assert main([*COMMANDS["response"], "-p", "sigma=1"]) == 2
    assert "sigma is both varied (--vary) and given (-p)" in _err(capsys)


# -- issue 35, "one parameter and option layer": the shared options defined once ------------

#: the commands that run an ensemble of Langevin trajectories, as a user types them
ENSEMBLES = {
    "spectrum": ["spectrum", "vdp", "-p", "mu=0.1", "-p", "D=0.01"],
    "noise": ["noise", "cdc", "-p", "mu=0.1", "-p", "Delta=3", "-p", "D=0.1"],
    "escape": ["escape", "cdc", "-p", "mu=0.1", "-p", "Delta=3", "-p", "D=0.1"],
    "friction": ["friction", "cdc", "-p", "Delta=3", "-p", "T=0.05", "--vary", "v=1",
                 "--no-progress"],
}


def _options(command: str) -> dict:
    """``{flag: argparse action}`` of ``kbm COMMAND``."""
    import argparse

    from numerics.cli import build_parser

    sub = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    return {flag: a for a in sub.choices[command]._actions for flag in a.option_strings}


def test_shared_options_have_one_definition_in_every_command():
    """Every ensemble option (``--trajectories``, ``--seed``, ``--workers``, ``--store``,
    ``--resume``, ``--budget``) and every shared one (``-p``, ``--json``, ...) has the same
    flags, type and metavar in each command that takes it, and the same help wherever the
    command does not say what it does there (issue 35: "the same names everywhere")."""
    from kbm.cli._common import OPTIONS
    from numerics.cli import COMMANDS as NUMERIC
    from numerics.cli.params.options import ENSEMBLE

    seen = 0
    for command in ("derive", "series", *NUMERIC):
        actions = _options(command)
        for table in (OPTIONS, ENSEMBLE):
            for flags, kw in table.values():
                action = actions.get(flags[0])
                if action is None or action.option_strings != list(flags):
                    continue  # not taken, or the command's own (response: --order N)
                seen += 1
                assert action.type == kw.get("type"), (command, flags)
                if "metavar" in kw and action.metavar != kw["metavar"]:
                    assert flags[0] in ("--vary", "--store", "--out"), (command, flags)
    assert seen >= 60
    assert _options("noise")["--seed"].help == _options("spectrum")["--seed"].help == \
        _options("escape")["--seed"].help == ENSEMBLE["seed"][1]["help"]
    assert _options("noise")["--store"].help == _options("spectrum")["--store"].help
    assert all(_options(c)["--json"].help == "print JSON"
               for c in NUMERIC if "--json" in _options(c))


@pytest.mark.parametrize("command", list(ENSEMBLES))
def test_every_ensemble_refuses_a_negative_seed_alike(command, capsys):
    """``--seed -1``: the same one-line refusal from each command that spawns the
    trajectories' seeds (before, ``kbm escape`` left it to the library)."""
    assert main([*ENSEMBLES[command], "--seed", "-1"]) == 2
    assert _err(capsys) == f"kbm {command}: error: --seed must be >= 0, got -1"


@pytest.mark.parametrize("command", [c for c in ENSEMBLES if c != "escape"])
def test_every_store_refuses_resume_without_a_file_alike(command, capsys):
    assert main([*ENSEMBLES[command], "--resume"]) == 2
    what = "map" if command == "friction" else "run"
    assert _err(capsys) == (f"kbm {command}: error: --resume continues a {what} kept by "
                            "--store FILE: give the file")


def test_out_json_file_is_the_printed_json(tmp_path, capsys):
    """``--out DIR --json``: the file ``spectrum-vdp.json`` holds the bytes ``--json``
    prints (one writer, :func:`kbm.cli._common.write_json`, beside
    :func:`kbm.cli._common.emit_json`)."""
    assert main([*ENSEMBLES["spectrum"], "--no-simulation", "--json", "--out",
                 str(tmp_path)]) == 0
    printed = capsys.readouterr().out
    assert (tmp_path / "spectrum-vdp.json").read_text() == printed
    assert json.loads(printed)["figures"]


@pytest.mark.parametrize("argv", [
    COMMANDS["branch"] + ["--max-points", "1"],
    COMMANDS["diagram"] + ["--max-points", "1"],
    COMMANDS["branch coupled"] + ["--max-points", "1"],
])
def test_a_bounded_option_is_refused_in_one_wording(argv, capsys):
    """``--max-points`` out of range: the same words from every command (before, ``kbm
    diagram`` said "must be 2 to 100000" and ``kbm branch`` "must be between 2 and
    100000"; :func:`numerics.cli.params.values.within`)."""
    assert main(argv) == 2
    assert _err(capsys).endswith("error: --max-points must be between 2 and 100000, got 1")


def test_within_names_the_bounds_as_typed():
    from numerics.cli.params.values import within

    for value, flag, lo, hi, words in ((0.0, "--rtol", 1e-15, 1e-3, "between 1e-15 and 1e-3"),
                                       (2e6, "--transient", 0, 1e6, "between 0 and 1e6"),
                                       (math.nan, "--x-start", None, None, "a finite number")):
        with pytest.raises(ParameterError, match=f"^{flag} must be {words}, got {value}$"):
            within(value, flag, lo, hi)
    within(None, "--digits", 1, 200)  # the option not given
    within(1e-3, "--rtol", 1e-15, 1e-3)  # a bound is inside


@pytest.mark.parametrize("text, words", [
    ("-1:3", "cannot read --internal -1:3: write P:Q"),
    ("1:0", "--internal 1:0 has a zero in its ratio"),
    ("1:1@2,F", "--internal 1:1@2,F names the forcing (F), but the system has no forcing"),
    ("1:1@1,5", "--internal 1:1@1,5 needs two different modes among 1..2"),
])
def test_a_bad_internal_resonance_names_the_option(text, words, capsys):
    """``--internal`` that cannot be read is refused in the option's name (before: "cannot
    read the internal resonance '-1:3'", the library's words)."""
    assert main(["lock", "coupled-vdp", "--internal", text, "-p", "mu=0.1", "-p", "c=0.2",
                 "--vary", "sigma=-1:1"]) == 2
    assert words in _err(capsys)
