"""``kbm noise``, ``kbm escape`` with simulation and ``kbm friction -p D=`` (issue 22, part 4).

References: the Boltzmann density ``exp(-G/kT)`` by quadrature for the CDC at rest (paper
eq. 12 with ``kT = D/mu``; exact, independent of averaging and of the integrator), the
athermal friction law of :func:`numerics.sliding.friction.friction_point` (DOP853, a
second integrator) as ``D -> 0``.
"""

from __future__ import annotations

import json
import math
import subprocess
import sys

import pytest

from numerics.cli import main
from numerics.sliding.friction import friction_point
from numerics.thermal.friction import thermal_friction_map

CDC = ["-p", "mu=0.1", "-p", "Delta=3"]


def kbm(*args: str, check: bool = True) -> subprocess.CompletedProcess:
    proc = subprocess.run([sys.executable, "-m", "numerics.cli", *args], capture_output=True,
                          text=True, timeout=300)
    if check:
        assert proc.returncode == 0, proc.stderr
    return proc


def kbm_in_process(capsys, *args: str) -> tuple[int, str, str]:
    """``kbm args`` run by the command line's ``main`` in this process: ``(status, standard
    output, standard error)``, argparse's own exits included.  For the checks of what a
    command prints and returns; the tests above that compare processes (worker counts,
    bytes) start them."""
    try:
        code = main(list(args))
    except SystemExit as exc:  # argparse's own errors
        code = exc.code
    out = capsys.readouterr()
    return code, out.out, out.err


def test_noise_json_contract_and_boltzmann():
    """The JSON keys of issue 22 section 4; the CDC at rest at kT = 1 (several wells
    visited): simulated <x^2> = Boltzmann within 3 standard errors, and the energy-envelope
    average = Boltzmann (linear damping: the averaged density is exp(-E/kT) exactly)."""
    out = kbm("noise", "cdc", *CDC, "-p", "D=0.1", "--trajectories", "32", "--t-end", "1000",
              "--json").stdout
    rep = json.loads(out)
    for key in ("model", "params", "trajectories", "t_end", "seed", "moments", "density"):
        assert key in rep
    for m in ("a2", "x2"):
        assert set(rep["moments"][m]) >= {"averaged", "simulated", "stderr"}
    x2 = rep["moments"]["x2"]
    assert abs(x2["simulated"] - x2["boltzmann"]) < 3 * x2["stderr"], x2
    assert abs(x2["averaged"] - x2["boltzmann"]) < 1e-3 * x2["boltzmann"], x2
    d = rep["density"]
    assert d["variable"] == "E"
    assert len(d["grid"]) == len(d["averaged"]) == len(d["simulated"]) == len(d["stderr"])
    # the averaged density of E (Boltzmann over the graph of annuli) against the histogram,
    # bin by bin within 4 standard errors (40 bins: a bin beyond 4 has probability 2.5e-3),
    # over the bins holding 1 % of the peak or more (in the far tail a bin is visited by
    # one or two trajectories and its standard error means little)
    top = max(d["averaged"])
    z = [abs(a - s) / e for a, s, e in zip(d["averaged"], d["simulated"], d["stderr"])
         if a > 0.01 * top]
    assert len(z) > 20 and max(z) < 4, z


def test_noise_same_bytes_for_a_seed_on_any_worker_count():
    args = ["noise", "cdc", *CDC, "-p", "D=0.05", "--trajectories", "8", "--t-end", "50",
            "--seed", "5", "--json"]
    one = kbm(*args, "--workers", "1").stdout
    two = kbm(*args, "--workers", "2").stdout
    assert one == two
    other = kbm(*args[:-3], "--seed", "6", "--json").stdout
    assert other != one


def test_noise_extrapolate_same_bytes_on_any_worker_count():
    """The two-level estimator's streams are spawned per trajectory: --workers 1 and 2 give
    the same bytes with --extrapolate too."""
    args = ["noise", "linear_damping", "-p", "mu=1", "-p", "zeta=1", "-p", "D=1",
            "--trajectories", "16", "--t-end", "20", "--dt", "0.05", "--seed", "3",
            "--extrapolate", "--no-fokker-planck", "--json"]
    one = kbm(*args, "--workers", "1").stdout
    two = kbm(*args, "--workers", "2").stdout
    assert one == two
    ext = json.loads(one)["extrapolation"]
    assert ext["method"] == "two-level Richardson"
    assert ext["coupling"] == "antithetic"


def test_noise_driven_slider_has_no_averaged_state(capsys):
    code, out, err = kbm_in_process(capsys, "noise", "cdc", *CDC, "-p", "v=0.05", "-p",
                                    "D=0.01", "--trajectories", "8", "--t-end", "40", "--json")
    assert code == 0, err
    rep = json.loads(out)
    assert rep["moments"]["x2"]["averaged"] is None
    assert "not autonomous" in rep["message"]
    assert rep["density"]["variable"] == "x"
    assert rep["moments"]["x2"]["simulated"] > 0


def test_noise_figure(tmp_path):
    # the figure alone: a given step and no Fokker-Planck solve (both tested elsewhere)
    kbm("noise", "cdc", *CDC, "-p", "D=0.05", "--trajectories", "8", "--t-end", "40",
        "--dt", "0.02", "--no-fokker-planck", "--out", str(tmp_path))
    assert (tmp_path / "noise-cdc.png").stat().st_size > 10_000
    assert json.loads((tmp_path / "noise-cdc.json").read_text())["trajectories"] == 8


@pytest.mark.parametrize("args, message", [
    (["-p", "D=-0.1"], "D = -0.1: give the noise intensity"),
    (["-p", "D=nan"], "finite"),
    (["-p", "D=0.1", "--trajectories", "2"], "at least 8"),
    ([], "give the noise intensity"),
    (["-p", "D=0.1", "--seed", "-3"], "seed"),
])
def test_noise_bad_input_one_line(args, message, capsys):
    code, _, err = kbm_in_process(capsys, "noise", "cdc", *CDC, *args)
    assert code != 0
    assert message in err
    assert len(err.strip().splitlines()) == 1, err
    assert "Traceback" not in err


def test_noise_rare_event_guard():
    """Beyond the step budget the simulation is refused with the estimate; the averaged
    answer stays."""
    rep = json.loads(kbm("noise", "cdc", *CDC, "-p", "D=0.1", "--budget", "1e5",
                         "--json").stdout)
    assert rep["moments"]["x2"]["simulated"] is None
    assert rep["moments"]["x2"]["averaged"] is not None
    assert "simulation refused" in rep["message"] and "budget" in rep["message"]


@pytest.mark.slow  # 4-8 s; kept out of the default run (five-minute rule)
def test_noise_fp_budget_bounds_the_fokker_planck_solve(capsys):
    """``--fp-budget`` is the Kramers solve's ``max_cost``: van der Pol's first solve (32
    Hermite functions on at least 96 Chebyshev intervals, folded by parity: a cost of at
    least 32 x 48^2 = 7.4e4) is refused at a budget of 1e4 with that cost in the message,
    and solved at the default, where ``<a^2>`` agrees with first-order stochastic averaging
    (an independent method) within 1 % (its error is O(mu), 0.21 % here, issue 36)."""
    args = ("noise", "vdp", "-p", "mu=0.1", "-p", "D=0.05", "--budget", "0", "--json")
    code, out, _ = kbm_in_process(capsys, *args, "--fp-budget", "1e4")
    rep = json.loads(out)
    assert code == 0 and rep["moments"]["a2"]["fokker_planck"] is None
    msg = rep["fokker_planck_message"]
    assert "not affordable" in msg and "> 1e+04" in msg
    assert msg.endswith("(raise --fp-budget above that cost)")  # the option that affords it
    assert float(msg.split("(cost ")[1].split()[0]) >= 0.995 * 32 * 48**2  # printed .3g
    code, out, _ = kbm_in_process(capsys, *args)
    a2 = json.loads(out)["moments"]["a2"]
    assert a2["fokker_planck"] == pytest.approx(a2["averaged"], rel=0.01)


@pytest.mark.slow  # 4-8 s; kept out of the default run (five-minute rule)
def test_noise_text_skips_p_of_e_and_prints_the_same_moments(capsys):
    """``P(E)`` is reported in JSON only (the text prints none, and its grid step beyond
    the moments' is 18 s of 50 at the SEDF's mu = 0.01): the text run computes none and
    prints the JSON's Fokker-Planck moments to the digits its stated error supports."""
    args = ("noise", "vdp", "-p", "mu=0.1", "-p", "D=0.05", "--budget", "0", "--method",
            "fokker-planck")
    code, out, _ = kbm_in_process(capsys, *args, "--json")
    rep = json.loads(out)
    assert code == 0 and rep["fokker_planck"]["energy_density"]["P"]
    code, text, _ = kbm_in_process(capsys, *args)
    assert code == 0
    for key in ("a2", "x2"):
        line = next(row for row in text.splitlines() if row.strip().startswith(f"<{key[0]}^2>"))
        printed = float(line.split()[-1])
        assert printed == pytest.approx(rep["moments"][key]["fokker_planck"], rel=1e-6)
    from numerics.thermal.stationary import noise_report

    api = noise_report("vdp", {"mu": 0.1, "D": 0.05}, budget=0, method="fokker-planck",
                       energy_density=False)
    assert api["fokker_planck"]["energy_density"] is None
    assert api["moments"]["x2"]["fokker_planck"] == rep["moments"]["x2"]["fokker_planck"]


def test_escape_json_simulated():
    """kbm escape's contract with a simulation (the CDC, E_b/kT = 3)."""
    D = 0.1 * 1.0869519157903051 / 3
    rep = json.loads(kbm("escape", "cdc", *CDC, "-p", f"D={D}", "--trajectories", "40",
                         "--json").stdout)
    for key in ("rate_averaged", "rate_simulated", "stderr", "barrier"):
        assert rep[key] is not None and rep[key] > 0
    assert rep["escaped"] + rep["censored"] == 40


def test_thermal_friction_joins_the_athermal_law():
    """As D -> 0 the Langevin friction law joins the athermal one (DOP853, FrictionPoint):
    the mean spring force over 200 stage periods at v = 0.01 (stick-slip) within the bias of
    a window that cuts a stick-slip cycle, peak force x wells per cycle / wells."""
    params = {"mu": 0.1, "Delta": 3.0, "lam": 1.0, "Omega": 1.0}
    det = friction_point("cdc", {**params, "v": 0.01})
    m = thermal_friction_map("cdc", {**params, "D": 1e-12}, {"v": [0.01]}, trajectories=4,
                             wells=200, workers=1)
    p = m.points[0]
    bound = det.peak_force * det.wells_per_slip / 200
    assert abs(p.mean_force.value - det.mean_force) < bound, (p, det.mean_force, bound)
    assert abs(p.slip_force.value - det.static_force) < 1e-2 * det.static_force


def test_thermal_friction_falls_with_temperature_and_is_executor_independent():
    """Thermally activated slips come earlier: at v = 0.01 the mean and slip forces at
    kT = 0.1 lie below the kT = 0.01 ones by many standard errors (Sang et al. 2001).
    One and two workers give the same numbers."""
    params = {"mu": 0.1, "Delta": 3.0}
    kw = dict(trajectories=8, wells=20, seed=3)
    a = thermal_friction_map("cdc", params, {"T": [0.01, 0.1], "v": [0.01]}, workers=1, **kw)
    b = thermal_friction_map("cdc", params, {"T": [0.01, 0.1], "v": [0.01]}, workers=2, **kw)
    assert a.to_json() == b.to_json()
    cold, hot = a.points
    for f in ("mean_force", "slip_force"):
        c, h = getattr(cold, f), getattr(hot, f)
        assert c.value - h.value > 3 * math.hypot(c.stderr, h.stderr), (f, c, h)


def test_friction_with_noise_cli():
    rep = json.loads(kbm("friction", "cdc", "-p", "Delta=3", "-p", "D=0.002", "--vary",
                         "v=0.05,0.1", "--trajectories", "4", "--wells", "5", "--json").stdout)
    assert rep["axes"] == {"v": [0.05, 0.1]}
    assert [p["v"] for p in rep["points"]] == [0.05, 0.1]
    assert all(p["mean_force"] > 0 and p["mean_force_stderr"] >= 0 for p in rep["points"])
    assert rep["points"][0]["kT"] == pytest.approx(0.02)
    bad = kbm("friction", "cdc", "-p", "Delta=3", "-p", "D=0.1", "-p", "T=1", "--vary",
              "v=0.1", check=False)
    assert bad.returncode == 2 and "not both" in bad.stderr


def test_friction_with_noise_prints_no_nan(capsys):
    """A point without slips (the CDC pulled at v = 0.01 for one stage period, kT = 1e-3 far
    below its barrier) has no slip force or position: the JSON says null, and the text
    "--" with the reason, not Python's "nan"."""
    args = ("friction", "cdc", "-p", "Delta=3", "-p", "D=0.0001", "--vary", "v=0.01:3:2",
            "--trajectories", "4", "--wells", "1", "--no-progress")
    code, out, _ = kbm_in_process(capsys, *args, "--json")
    slow = json.loads(out)["points"][0]
    assert code == 0 and slow["slips"] == 0 and slow["slip_force"] is None
    code, text, _ = kbm_in_process(capsys, *args)
    assert code == 0 and "nan" not in text and "--: no slip in the run" in text
    row = next(line.split() for line in text.splitlines() if line.split()[:1] == ["0.01"])
    assert row[5:9] == ["--"] * 4 and row[9] == "0"


def test_noise_driven_slider_says_its_moments_are_not_stationary(capsys):
    """A pulled CDC's x follows the stage, x ~ v t: its simulated <x^2> grows with --t-end
    (the stage's mean (v t)^2 over [10, 210] is v^2 (210^3 - 10^3)/600 = 38.6 at v = 0.05;
    over [10, 50] 2.6), so the report must not present it as a stationary moment; before,
    the message said only "no averaged stationary state"."""
    x2 = {}
    for t_end in ("40", "200"):
        code, out, err = kbm_in_process(capsys, "noise", "cdc", *CDC, "-p", "v=0.05", "-p",
                                        "D=0.01", "--trajectories", "8", "--t-end", t_end,
                                        "--burn-in", "10", "--json")
        assert code == 0, err
        rep = json.loads(out)
        x2[t_end] = rep["moments"]["x2"]["simulated"]
        assert "grow with --t-end" in rep["message"] and "kbm friction" in rep["message"]
    stage = 0.05**2 * (210**3 - 10**3) / 600
    assert x2["200"] > 10 * x2["40"] and stage / 2 < x2["200"] < 2 * stage


@pytest.mark.slow  # 4-8 s; kept out of the default run (five-minute rule)
def test_noise_budget_refusal_keeps_the_reason_and_says_what_is_given(capsys):
    """--budget 0 replaced the message: a pulled slider (no averaged state) then said "the
    averaged answer is given alone" beside an empty averaged column, and --order 2 on the
    SEDF lost "first order given".  The refusal now follows the reason and says what is
    given."""
    code, out, _ = kbm_in_process(capsys, "noise", "cdc", *CDC, "-p", "v=0.05", "-p",
                                  "D=0.01", "--budget", "0", "--json")
    rep = json.loads(out)
    assert code == 0 and rep["moments"]["x2"]["averaged"] is None
    assert "not autonomous" in rep["message"] and "simulation refused" in rep["message"]
    assert "the averaged answer is given alone" not in rep["message"]
    code, out, _ = kbm_in_process(capsys, "noise", "sedf", "-p", "mu=0.1", "-p", "Delta=3",
                                  "-p", "beta=1", "-p", "D=0.05", "--order", "2", "--budget",
                                  "0", "--no-fokker-planck", "--json")
    rep = json.loads(out)
    assert code == 0 and rep["averaged_order"] == 1
    assert "first order given" in rep["message"] and "simulation refused" in rep["message"]


def test_friction_with_noise_states_no_default_for_an_axis(capsys):
    """``--vary mu=0.1,1`` with ``-p T=0.05``: the header said "mu = 0.1" (the library's
    default) and the JSON ``params.mu`` 0.1.  Now the header names no mu, the JSON keeps the
    key with ``null`` (the values are in ``axes``), and each point's ``D = mu T`` (the
    temperature of the damping mu x', paper eq. 12) uses its own mu.  Without ``v`` the
    refusal says what to give, not "got None"."""
    args = ("friction", "cdc", "-p", "Delta=3", "-p", "T=0.05", "-p", "v=0.5", "--vary",
            "mu=0.1,1", "--trajectories", "4", "--wells", "2", "--no-progress")
    code, text, _ = kbm_in_process(capsys, *args)
    head = text.splitlines()[0]
    assert code == 0 and "mu =" not in head and "T = 0.05" in head, head
    code, out, _ = kbm_in_process(capsys, *args, "--json")
    rep = json.loads(out)
    assert code == 0 and "mu" in rep["params"] and rep["params"]["mu"] is None
    assert rep["params"]["lam"] == 1.0 and rep["axes"]["mu"] == [0.1, 1.0]
    assert [p["D"] for p in rep["points"]] == pytest.approx([0.1 * 0.05, 1.0 * 0.05])
    code, _, err = kbm_in_process(capsys, *args[:6], *args[8:])
    assert code == 2 and "got None" not in err and "give -p v=VALUE" in err, err
