"""Library messages name API arguments; the command line names its flags (issue 15, item 4).

The same missing parameter is reported by the library as ``params={'beta': ...}`` and by
``kbm`` as ``--param beta=...``, in one line with exit status 2.
"""

from __future__ import annotations

import math
import re

import pytest

from kbm.cli import cli_message
from kbm.errors import ParameterError
from numerics import limit_cycle
from numerics.cli import main


def test_library_names_arguments_and_cli_names_flags(capsys):
    with pytest.raises(ParameterError, match=r"params=\{'beta'"):
        limit_cycle("sedf", {"mu": 0.1, "Delta": 1, "lam": 1})
    assert main(["cycle", "sedf", "-p", "mu=0.1", "-p", "Delta=1", "-p", "lam=1"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--param beta=" in err[0] and "params=" not in err[0]


@pytest.mark.parametrize("library,cli", [
    ("needs values for mu (e.g. params={'mu': 0.1})", "(e.g. --param mu=0.1)"),
    ("or give your own F with custom_model", "or give your own F with --rhs EXPR"),
    ("start elsewhere (x_start) to look for a cycle", "start elsewhere (--x-start) to look"),
])
def test_translation_table(library, cli):
    assert cli in cli_message(library)


#: words of the Python API that no command-line message may hold (issue 35, item 6)
API_WORDS = ("params=", "axes=", "resume=True", "max_wells", "max_periods", "np.float64",
             "potential=", "`potential`", "root=", "t_end", "rtol", "in params", "averaged_cycles",
             "D = '", "internal=", "trajectories = ", "resonance='", "a_min", "a-range",
             "order must", "order <=", "nu must", "tol must", "friction setting")


@pytest.mark.parametrize("argv, says", [
    # the conservative part's potential (kbm.model.conservative): the option, not the argument
    (["predict", "--rhs", "(1-x**2)*xdot - x**3", "--potential", "x**2", "-p", "mu=0.1"],
     "change --potential so that V'(x) = g(x), or leave out --potential"),
    (["predict", "--rhs", "(1-x**2)*xdot - x**3", "-p", "mu=0.1", "--method", "kbm",
      "--potential", "x**4/4"], "--potential belongs to the energy method"),
    (["predict", "vdp"], "(e.g. --param mu=0.1)"),
    # a series whose A_1 has no positive root said "has 0 positive roots []; choose one"
    (["series", "--rhs", "(1-x**2)*(4-x**2)*xdot", "--order", "1"],
     "has no positive root: the first-order amplitude equation has no limit cycle"),
    (["series", "sedf", "--order", "2"], "use kbm predict --method kbm"),
    (["slide", "cdc", "-p", "mu=0.1", "-p", "Delta=3", "-p", "v=0.1", "--t-end", "1e9"],
     "--t-end 1e+09 is"),
    (["slide", "cdc", "-p", "mu=0.1", "-p", "Delta=3", "-p", "v=0.1", "--t-end", "5",
      "--rtol", "1"], "--rtol must be between"),
    (["friction", "cdc", "-p", "Delta=3", "-p", "D=0.01", "--vary", "v=0.1", "--wells", "0",
      "--no-progress"], "--wells 0:"),
    (["friction", "cdc", "-p", "Delta=3", "-p", "D=0.01", "--vary", "v=0.1", "--seed", "-3",
      "--no-progress"], "--seed must be"),
    (["friction", "cdc", "--vary", "Delta=1,2", "--no-progress"], "give --vary v=..."),
    # a negative D is a plain number, not a Python string ("D = '-1'")
    (["noise", "vdp", "-p", "mu=0.1", "-p", "D=-1"], "D = -1: give the noise intensity"),
    (["noise", "vdp", "-p", "mu=0.1", "-p", "D=inf"], "D = inf: give"),
    (["escape", "cdc", "-p", "mu=0.02", "-p", "Delta=3", "-p", "D=-1"], "D = -1: give"),
    # no noise, no stationary density: refused, not 100 trajectories resting at the origin
    # with <a^2> = 0 +- 0 reported (van der Pol's attractor is the cycle a = 2)
    (["noise", "vdp", "-p", "mu=0.1", "-p", "D=0"],
     "D > 0 and finite (without noise there is no stationary density"),
    (["derive", "vdp", "--order", "2", "--numeric", "--a-range", "2:1"],
     "--a-range needs AMIN < AMAX, got 2:1"),
    # the library's words on the command line (issue 35): "the a-range must lie in a > 0
    # ..., got a_min = -1", "the order must be", "nu must be", "tol must be", "friction
    # setting slips must be", "ask for order <= 20"
    (["derive", "vdp", "--order", "2", "--numeric", "--a-range", "-1:2"],
     "--a-range must lie in a > 0"),
    (["derive", "vdp", "--order", "2", "--numeric", "--a-range", "1:2:3"],
     "--a-range must be 'AMIN:AMAX'"),
    (["derive", "vdp", "--order", "0"], "--order must be an integer >= 1, got 0"),
    (["series", "vdp", "--order", "-1"], "--order must be an integer >= 0, got -1"),
    (["predict", "vdp", "-p", "mu=0.1", "--order", "0"], "--order must be an integer >= 1"),
    (["derive", "vdp", "--order", "40", "--numeric", "--a-range", "1:2"],
     "--order 40 is above the limit 20 of the numeric backend; ask for --order <= 20"),
    (["derive", "vdp", "--order", "2", "--numeric", "--a-range", "1:2", "--tol", "2"],
     "--tol must be between 1e-15 and 1"),
    (["response", "duffing", "--forcing", "h*cos(theta)", "-p", "mu=0.05", "-p", "h=0.5",
      "--nu", "0"], "--nu must be a positive number"),
    (["friction", "cdc", "-p", "Delta=3", "-p", "D=0.01", "--vary", "v=0.1", "--slips", "0",
      "--no-progress"], "--slips must be an integer >= 1, got 0"),
    (["response", "duffing-forced", "--resonance", "0/1", "--vary", "sigma=-1:1", "--order",
      "1"], "--resonance p/q must be positive, got '0/1'"),
    (["noise", "cdc", "-p", "mu=0.1", "-p", "Delta=3", "-p", "T=0"],
     "T = 0 is the deterministic model, without noise: give a temperature T > 0 (-p T=VALUE"),
    (["noise", "cdc", "-p", "mu=0.1", "-p", "Delta=3", "-p", "D=0"],
     "D > 0 and finite (without noise there is no stationary density; or the temperature -p "
     "T=VALUE > 0"),
    (["derive", "coupled-vdp", "--order", "1", "--numeric", "--a-range", "1:2"],
     "--a-range is not for the coupled numeric backend"),
    # kbm spectrum: a ZeroDivisionError traceback, an OOM kill after 40 s, a MemoryError
    # traceback, options the forced and coupled runs dropped without a word
    (["spectrum", "vdp", "-p", "mu=0.1", "-p", "D=0.01", "--resolution", "0"],
     "--resolution must be a positive number, got 0"),
    (["spectrum", "vdp", "-p", "mu=0.1", "-p", "D=0.01", "--duration", "-1"],
     "--duration must be a positive number"),
    (["spectrum", "vdp", "-p", "mu=0.1", "-p", "D=0.01", "--trajectories", "1000000000"],
     "integration steps, above the limit 2e+09: give fewer --trajectories"),
    (["spectrum", "vdp", "-p", "mu=0.1", "-p", "D=0.01", "--duration", "1e12"],
     "integration steps, above the limit"),
    (["spectrum", "vdp", "-p", "mu=0.1", "--vary", "D=0.005:0.02:100000"],
     "shared by 100000 runs of the sweep"),
    (["spectrum", "coupled-vdp", "-p", "mu=0.1", "-p", "c=0.3", "-p", "D=0.02", "--vary",
      "sigma=0.2,0.3", "--trajectories", "1000000000"], "integration steps, above the limit"),
    (["spectrum", "coupled-vdp", "-p", "mu=0.1", "-p", "c=0.3", "-p", "D=0.02", "--vary",
      "sigma=0.2,0.3", "--no-simulation"], "would ignore it: leave out --no-simulation"),
    (["spectrum", "duffing-forced", "-p", "mu=0.05", "-p", "zeta=0.5", "-p", "alpha=1", "-p",
      "h=2", "-p", "D=0.001", "--vary", "sigma=0.8,1.1", "--floquet"],
     "would ignore it: leave out --floquet"),
    (["spectrum", "duffing-forced", "-p", "mu=0.05", "-p", "zeta=0.5", "-p", "alpha=1", "-p",
      "h=2", "-p", "D=0.001", "--vary", "sigma=0.8:1.1:5000"], "the limit is 200"),
    # a TypeError traceback ('Mul' object is not iterable)
    (["lock", "vdp", "-p", "mu=0.05", "--vary", "sigma=-1:1"], "vdp has one degree of freedom"),
    # the last --vary silently replaced the first (then "needs values for Delta")
    (["branch", "sedf", "-p", "mu=0.1", "-p", "beta=1", "-p", "lam=1", "--vary", "Delta=0:4",
      "--vary", "beta=0:1"], "give one --vary (got Delta, beta)"),
    (["response", "duffing-forced", "-p", "mu=0.05", "-p", "zeta=0.1", "-p", "alpha=1", "-p",
      "h=0.5", "--vary", "h=0.1:1", "--vary", "sigma=-1:3"], "give one --vary (got h, sigma)"),
    # a ZeroDivisionError traceback (exact), a* = 0 printed as a cycle (--method kbm)
    (["series", "vdp", "--order", "4", "--root", "0"], "a0 = 0 is the rest state"),
    (["series", "vdp", "--order", "4", "--root", "0", "--method", "kbm"],
     "choose one with --root A0"),
    # RankWarnings and slopes fitted to one point
    (["compare", "vdp", "--convergence", "0.1,0.1,0.1"], "at least two distinct values of mu"),
    # a list that starts with a minus sign: argparse's "expected one argument" (it read
    # -0.1,0.05,0.1 as an option); then "needs at least two distinct values", given two
    (["compare", "vdp", "--convergence", "-0.1,0.05,0.1"],
     "--convergence needs values of mu > 0 (the slope of log|error| against log mu), got -0.1"),
    (["response", "duffing-forced", "-p", "mu=0.05", "-p", "zeta=0.1", "-p", "alpha=1", "-p",
      "h=0.5", "--vary", "sigma=-1:1", "--convergence", "-0.1,0.05,0.1"],
     "the values of mu must be positive and finite, got -0.1"),
    (["compare", "vdp", "--orders", "-1,2"], "--orders must list orders >= 1, got '-1,2'"),
    (["compare", "vdp", "--energy-orders", "-1,2"], "--energy-orders must list orders >= 1"),
    (["compare", "--fixed-delta", "-1,2"], "--fixed-delta takes values 0 < Delta < 100"),
    (["diagram", "sedf", "-p", "mu=0.1", "-p", "lam=1", "--vary", "Delta=0:6", "--vary",
      "beta=0.3:1.6", "--grid", "-3,4"], "--grid NA,NB must be 3 to 400 each, got '-3,4'"),
    (["noise", "vdp", "-p", "mu=0.1", "-p", "D=0.01", "--t-end", "-1e3"],
     "--t-end must be a positive number, got -1000"),
    # the method won silently over the contradicting flag
    (["noise", "vdp", "-p", "mu=0.1", "-p", "D=0.01", "--method", "fokker-planck",
      "--no-fokker-planck"], "--no-fokker-planck contradicts --method fokker-planck"),
    # the Fokker-Planck cost budget: a positive number, with a Fokker-Planck solve to bound
    (["noise", "sedf", "-p", "mu=0.01", "-p", "D=0.005", "--method", "fokker-planck",
      "--fp-budget", "-1e8"], "--fp-budget must be a positive number, got -1e+08"),
    (["noise", "sedf", "-p", "mu=0.01", "-p", "D=0.005", "--fp-budget", "nan"],
     "--fp-budget must be a positive number, got nan"),
    (["noise", "vdp", "-p", "mu=0.1", "-p", "D=0.01", "--fp-budget", "1e8",
      "--no-fokker-planck"], "--fp-budget contradicts --no-fokker-planck"),
    (["escape", "cdc", "-p", "mu=0.1", "-p", "D=0.05", "--fp-budget", "1e8"],
     "--fp-budget is the budget of the Fokker-Planck solve: give it with --method "
     "fokker-planck"),
    (["escape", "cdc", "-p", "mu=0.1", "-p", "D=0.05", "--method", "fokker-planck",
      "--fp-budget", "0"], "--fp-budget must be a positive number, got 0"),
    # "declare it: --internal 1:3 (internal=['1:3'])": the flag and the API argument
    (["derive", "--rhs", "-x1**2*x2", "--rhs", "-x1**3", "--omega0", "1,3", "--order", "1"],
     "declare it: --internal 1:3, with the frequencies"),
    (["response", "duffing", "--forcing", "h*cos(theta)", "-p", "mu=0.05", "-p", "h=0.5",
      "--nu", "1"], "declare it: --resonance 1/1 with the detuning"),
    (["spectrum", "vdp", "-p", "mu=0.1", "-p", "D=0.01", "--trajectories", "1"],
     "--trajectories 1: at least 8"),
    # ran without end: the largest step is a quarter of lam/v = 1e-9
    (["slide", "sedf", "-p", "Delta=3", "-p", "beta=1", "-p", "v=1e9", "--t-end", "15"],
     "--t-end 15 needs at least 6e+10 steps"),
    # a Pade value at mu = 1e300 printed without a word (0.1757, where the true omega* is
    # ~4e-300); the series' radius |mu^2| = 3.42 (Andersen & Geer), the reach 10 radii
    (["series", "vdp", "--order", "80", "--float", "--at", "1e300"],
     "times the series' radius of convergence 3.4"),
    (["series", "vdp", "--order", "80", "--float", "--at", "7"], "give --at with |MU| <= 5.8"),
    # a RuntimeWarning (overflow in square) and stderr = inf in the table, exit 0
    (["noise", "sedf", "-p", "mu=0.1", "-p", "Delta=3", "-p", "beta=1", "-p", "v=0.1", "-p",
      "D=1e300", "--trajectories", "8", "--t-end", "10", "--burn-in", "1", "--json"],
     "the ensemble's moments reach"),
    # --at on one degree of freedom was ignored silently (the table printed as without it)
    (["derive", "vdp", "--order", "2", "--at", "1.5"],
     "--at is the point of a coupled system's --numeric rates"),
    # an empty --only wrote nothing and exited 0
    (["figures", "--only"], "give at least one, or leave out --only"),
    # --budget nan ran with no budget at all
    (["noise", "vdp", "-p", "mu=0.1", "-p", "D=0.01", "--budget", "nan"], "--budget must be"),
    # E_b/kT = 2e7: two RuntimeWarnings and "came out as nan ... check mu > 0 and D > 0"
    (["escape", "cdc", "-p", "mu=0.02", "-p", "Delta=3", "-p", "D=1e-9", "--no-simulation"],
     "raise D to 3.11e-05 or more"),
    # a negative T was told "T >= 0", then T = 0 was refused: the range these commands
    # take is T > 0 (kbm friction keeps T >= 0, T = 0 its deterministic slider)
    (["noise", "vdp", "-p", "mu=0.05", "-p", "T=-0.01"], "give -p T=VALUE with T > 0"),
    (["escape", "sedf", "-p", "mu=0.05", "-p", "T=-0.01"], "give -p T=VALUE with T > 0"),
    (["friction", "sedf", "-p", "mu=0.1", "-p", "T=-1", "--vary", "v=0.1:1"],
     "must be >= 0 (T = 0 is the deterministic slider)"),
    # without -p v the stage stood still, v = 0 (not a documented default): zeros, 0 slips
    (["slide", "sedf", "-p", "Delta=3", "-p", "beta=1", "--t-end", "100"],
     "give the stage velocity -p v=VALUE"),
    # only "unknown parameter 'v'": the escape (and noise's stationary state) is at rest
    (["escape", "sedf", "-p", "v=0.1", "-p", "mu=0.1", "-p", "D=0.05", "-p", "beta=1", "-p",
      "Delta=3"], "at rest, v = 0 (the stage not pulling: the potential's barrier is fixed), "
     "so -p v is not taken"),
    (["noise", "sedf", "-p", "v=0.1", "-p", "mu=0.1", "-p", "D=0.05", "-p", "beta=1", "-p",
      "Delta=3", "--method", "fokker-planck"], "the stationary state is computed at rest, "
     "v = 0, and -p v is not taken"),
    # "--vary beta=-1:1" was offered as sedf-dimer's detuning: its sliders are identical
    # (no detuning), and beta <= 0 has no cycle; docs/coupled.rst follows beta=0.5:1.5
    (["lock", "sedf-dimer", "--vary", "kappa=0:0.5"], "sedf-dimer has no detuning (its "
     "oscillators are identical): give the interval of the parameter its locked state is "
     "followed in, e.g. --vary beta=0.5:1.5"),
    # duffing-1-3's detuning is sigma (nu = 3 + mu sigma), not its first parameter alpha1
    (["lock", "duffing-1-3", "--vary", "k=0:0.5"], "--vary sigma=FROM:TO (e.g. sigma=-1:1)"),
    # named "Delta = 3", the plane's centre, never typed: delta = Delta/mu at mu = 0
    (["diagram", "sedf", "-p", "mu=0", "--vary", "Delta=0:6", "--vary", "beta=0.5:2"],
     "delta = Delta/mu is undefined for mu = 0 at every Delta = 0:6 of --vary: give mu != 0"),
])
def test_messages_speak_the_command_line(argv, says, capsys):
    """Each message as the user meets it: one line, exit 2, the option named as typed and no
    word of the Python API."""
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    assert says in err[0], err[0]
    bare = re.sub(r"--[\w-]+", "", err[0])  # the options named as typed
    assert not [w for w in API_WORDS if w in bare], err[0]


def test_negative_values_reach_their_options(capsys):
    """A value that starts with a minus sign and is no plain decimal (``-1e-1``, a list
    ``-1,0,0,0``) was read by argparse as an unknown option ("expected one argument"); now
    it is the option's value.  van der Pol's cycle from x = -0.1 at mu = 0.1 has the
    Lindstedt period ``2 pi/omega``, ``omega = 1 - mu^2/16 + 17 mu^4/3072 + O(mu^6)``."""
    import json
    import math

    assert main(["cycle", "vdp", "-p", "mu=0.1", "--x-start", "-1e-1", "--json"]) == 0
    mu = 0.1
    omega = 1 - mu**2 / 16 + 17 * mu**4 / 3072
    assert json.loads(capsys.readouterr().out)["period"] == pytest.approx(2 * math.pi / omega,
                                                                         rel=1e-7)
    assert main(["cycle", "coupled-vdp", "-p", "mu=0.1", "-p", "c=0.3", "--start", "-1,0,0,0",
                 "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["success"] is True


@pytest.mark.slow  # 4-8 s; kept out of the default run (five-minute rule)
def test_series_warns_beyond_the_radius(capsys):
    """``kbm series vdp --float --at 5``: mu^2 = 25 is 7.3 times the radius |mu^2| = 3.42
    (Andersen & Geer), within the reach; the value is printed with the note that its +- (the
    approximants' agreement) understates the error there (order 80: 6.7e-4 off the true
    omega* = 0.541083 of numerics' cycle, 5.2e-8 stated).  Within the radius (mu = 1) no
    note; the JSON states ``radius_multiple`` = mu^2/R."""
    import json

    assert main(["series", "vdp", "--order", "80", "--float", "--at", "5", "--at", "1"]) == 0
    out = capsys.readouterr().out.splitlines()
    notes = [i for i, line in enumerate(out) if "beyond the radius of convergence" in line]
    assert len(notes) == 1 and out[notes[0] - 1].startswith("mu = 5:")
    assert "(mu**2 = 7.31 times 3.4" in out[notes[0]]
    assert main(["series", "vdp", "--order", "80", "--float", "--at", "5", "--at", "1",
                 "--json"]) == 0
    pade = json.loads(capsys.readouterr().out)["pade"]
    assert [p["radius_multiple"] for p in pade] == pytest.approx([25 / 3.42, 1 / 3.42],
                                                                 rel=2e-3)


@pytest.mark.parametrize("model", ["vdp", "rayleigh"])
def test_escape_says_a_model_without_a_barrier_has_none_at_any_parameters(model, capsys):
    """van der Pol and Rayleigh: F at x' = 0 is 0, so the potential is x^2/2 whatever mu;
    the message said "choose parameters of vdp whose potential has a barrier"."""
    assert main(["escape", model, "-p", "mu=0.1", "-p", "D=0.1", "--no-simulation"]) == 2
    err = capsys.readouterr().err.strip()
    assert f"{model} has no barrier to escape over at any parameter values" in err
    assert "choose parameters" not in err and "\n" not in err


def test_cycle_json_has_the_x_min_the_text_prints(capsys):
    """``kbm cycle --json`` holds ``x_min`` (the text's "x_min (smallest x)") next to every
    old key; van der Pol's cycle is odd-symmetric (x -> -x, t -> t + T/2), so
    x_min = -amplitude_max to the sampling's accuracy (1024 samples of the orbit, cos near
    its extremum: 1 - cos(pi/1024) ~ 5e-6 relative)."""
    import json

    assert main(["cycle", "vdp", "-p", "mu=1", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    for key in ("model", "params", "period", "amplitude_max", "floquet_multipliers",
                "params_given"):
        assert key in data
    assert data["x_min"] == pytest.approx(-data["amplitude_max"], rel=1e-5)
    assert main(["cycle", "vdp", "-p", "mu=1"]) == 0
    text = capsys.readouterr().out
    line = next(s for s in text.splitlines() if "x_min" in s)
    assert float(line.split()[3]) == pytest.approx(data["x_min"], rel=1e-5)


def test_series_says_when_its_error_is_unmeasured(capsys):
    """``kbm series vdp --order 4 --float --at 0.1`` forms one diagonal Pade approximant of
    the series in mu^2 (c_0, c_2, c_4), so there is no second one to agree with: it printed
    ``(+- +inf)``; now ``+- unmeasured`` and why.  At order 8 two degrees agree to 5.3e-10,
    the distance of the value from the series' own partial sum 1 - mu^2/16 + 17 mu^4/3072
    (van der Pol, Andersen & Geer) being of that size too (the next term, ~mu^6 c_6)."""
    assert main(["series", "vdp", "--order", "4", "--float", "--at", "0.1"]) == 0
    out = capsys.readouterr().out
    assert "+inf" not in out and out.count("+- unmeasured") == 2
    assert "one Pade degree is formed" in out and "raise --order" in out
    assert main(["series", "vdp", "--order", "8", "--float", "--at", "0.1"]) == 0
    line = capsys.readouterr().out.splitlines()[-1]
    assert "unmeasured" not in line
    omega = float(line.split("omega* = ")[1].split(" ")[0])
    assert abs(omega - (1 - 0.01 / 16 + 17e-4 / 3072)) < 1e-8


def test_an_option_the_command_does_not_take_gets_the_commands_usage(capsys):
    """``kbm slide ... --vary v=0.1:1`` printed the top-level usage (``usage: kbm [-h]
    [--version] COMMAND ...``) and ``kbm: error: unrecognized arguments``: neither the
    command nor the options it does take.  Now the command's usage and its name."""
    with pytest.raises(SystemExit) as exc:
        main(["slide", "cdc", "-p", "Delta=3", "--t-end", "10", "--vary", "v=0.1:1"])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert err.startswith("usage: kbm slide") and "--t-end" in err, err
    assert err.strip().splitlines()[-1] == ("kbm slide: error: unrecognized arguments: "
                                            "--vary v=0.1:1")


@pytest.mark.parametrize("argv, says", [
    # "give -p T=VALUE": the user typed --vary, not -p
    (["spectrum", "vdp", "-p", "mu=0.1", "--vary", "T=-0.01:0.01"],
     "--vary T=-0.01:0.01: T = -0.01 is negative; the temperature kT = D/mu must be > 0"),
    # a later value was told as D = mu T: "D = -0.001: ... -p D=VALUE"
    (["spectrum", "vdp", "-p", "mu=0.1", "--vary", "T=0.01,-0.01"],
     "--vary T=0.01,-0.01: T = -0.01 is negative"),
    (["spectrum", "vdp", "-p", "mu=0.1", "--vary", "D=0.01,0"],
     "--vary D=0.01,0: D = 0 is no noise; the noise intensity of sqrt(2 D) xi must be > 0"),
    # "D = -0.04: give ... as -p D=VALUE"
    (["friction", "cdc", "-p", "Delta=3", "--vary", "D=0.01,-0.04", "--vary", "v=0.1"],
     "--vary D=0.01,-0.04: D = -0.04 is negative"),
    (["friction", "cdc", "-p", "Delta=3", "--vary", "T=-0.01,0.04", "--vary", "v=0.1"],
     "--vary T=-0.01,0.04: T = -0.01 is negative; the temperature kT = D/mu must be >= 0"),
])
def test_a_noise_axis_is_refused_as_typed(argv, says, capsys):
    """A bad value of ``--vary D`` or ``--vary T`` is refused naming the ``--vary`` typed
    and its value as typed (``T``, not ``D = mu T``), never an option not given (``-p``)."""
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and says in err[0], err
    assert "-p " not in err[0], err[0]


def test_series_refuses_far_beyond_a_radius_it_cannot_estimate(capsys):
    """``kbm series vdp --order 5 --float --at 1e9`` printed omega* = 0.294 "+- unmeasured"
    (the true omega* ~ 2 pi/((3 - 2 ln 2) mu) = 3.9e-9): at an order too low to estimate
    the radius of convergence, the reach of 10 radii that --order 80 enforces was skipped.
    The radius is then taken from the ratio of the last two coefficients of van der Pol's
    omega* = 1 - mu^2/16 + 17 mu^4/3072 (Lindstedt; Andersen & Geer), |mu^2| = 3072/(16 17),
    so --at is taken to |mu| <= sqrt(10 x 3072/272) = 10.63.  Within it the value is the
    diagonal Pade [1/1] of those three terms, (1 + 5 t/192)/(1 + 17 t/192), t = mu^2.  At
    --order 3 (c_0, c_2 only) no [1/1] exists: an ArithmeticError traceback before."""
    top = math.sqrt(10 * 3072 / (16 * 17))
    assert main(["series", "vdp", "--order", "5", "--float", "--at", "1e9"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"give --at with |MU| <= {top:.3g}" in err[0], err
    assert "too few coefficients to estimate its radius of convergence" in err[0]
    assert main(["series", "vdp", "--order", "5", "--float", "--at", "10.6"]) == 0
    line = capsys.readouterr().out.splitlines()[-2]
    t = 10.6**2
    omega = float(line.split("omega* = ")[1].split(" ")[0])
    assert omega == pytest.approx((1 + 5 * t / 192) / (1 + 17 * t / 192), rel=1e-14)
    assert main(["series", "vdp", "--order", "3", "--float", "--at", "0.1"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "no Pade approximant" in err[0] and "raise --order" in err[0]


@pytest.mark.parametrize("argv, says", [
    # "T = D/mu needs mu: give -p mu=VALUE, or the noise as -p D=VALUE"
    (["spectrum", "vdp", "--vary", "T=0.01,0.02"],
     "--vary T=0.01,0.02: T = D/mu needs mu: give -p mu=VALUE, or the noise as --vary D="),
    # "... got mu = -0.1; give -p D=VALUE"
    (["spectrum", "vdp", "-p", "mu=-0.1", "--vary", "T=0.01,0.02"],
     "needs mu > 0, got mu = -0.1; give -p mu=VALUE > 0, or the noise as --vary D="),
    # "parameter 'D' is given twice", though typed once as -p and once as --vary
    (["spectrum", "vdp", "-p", "mu=0.1", "-p", "D=0.01", "--vary", "D=0.01,0.02"],
     "D is both varied (--vary) and given (-p); give it once"),
])
def test_a_noise_axis_without_its_mu_is_refused_as_typed(argv, says, capsys):
    """``--vary T`` (``T = D/mu``, the temperature of the damping ``mu x'``) without ``mu >
    0``, and the noise given both as ``-p`` and as ``--vary``: the message names the
    ``--vary`` and offers ``--vary D``, not ``-p D=VALUE``."""
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and says in err[0], err
    assert "-p D=" not in err[0], err[0]
