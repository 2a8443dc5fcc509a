"""Defects a new user met at the seams of ``kbm`` (session 20's user pass), each pinned.

The one-line messages are in :mod:`tests.test_cli_messages`; here the outputs and the
limits that are not a message of the command line alone.
"""

from __future__ import annotations

import pytest

from kbm.errors import ParameterError
from numerics.cli import main
from numerics.noise.budget import STEP_BUDGET
from numerics.spectrum._cost import MEMORY_LIMIT, check_cost


def test_friction_table_prints_no_nan_for_a_sliding_state(capsys):
    """A steady sliding state (SEDF at rest, Delta = 3, v = 0.2: self-oscillating sliding)
    never sticks, so it has no static (peak) friction and no wells per slip: the table
    printed ``nan`` in both columns; it prints ``--`` (the JSON has ``null``)."""
    assert main(["friction", "sedf_comoving", "-p", "Delta=3", "-p", "beta=1", "--vary",
                 "v=0.2"]) == 0
    row = capsys.readouterr().out.strip().splitlines()[-1]
    assert "sliding" in row and "nan" not in row
    assert row.split()[-5:-3] == ["--", "0.000"] and row.split()[-3] == "--"


def test_spectrum_cost_refuses_steps_and_memory_with_the_numbers():
    """:func:`check_cost`: the product trajectories x steps against the step limit (shared
    by the runs of a sweep), the bytes held against the memory limit."""
    check_cost(64, STEP_BUDGET / 64, MEMORY_LIMIT)  # exactly at both limits: runs
    with pytest.raises(ParameterError, match=r"64 trajectories x 3.12e\+07 steps = 2e\+09 "
                                             r"integration steps, above the limit 1e\+09"):
        check_cost(64, STEP_BUDGET / 64, 0.0, budget=STEP_BUDGET / 2, shared=2)
    with pytest.raises(ParameterError, match=r"hold 3 GB of recorded samples"):
        check_cost(8, 1e3, 3e9)


@pytest.mark.parametrize("option, says", [
    ("--out", "cannot write to --out = '{bad}'"),
    ("--netcdf", "cannot write to --netcdf's folder = '{bad}'"),
])
def test_friction_refuses_an_unwritable_output_before_the_map(option, says, tmp_path,
                                                               capsys, monkeypatch):
    """An unwritable ``--out`` or ``--netcdf`` failed only after the whole map was computed
    (hours for a large one): now before the first point (the map is never started)."""
    import numerics.sliding.maps as maps

    def never(*a, **k):
        raise AssertionError("the map ran before the output was checked")

    monkeypatch.setattr(maps, "friction_map", never)
    blocker = tmp_path / "a-file"
    blocker.write_text("")
    bad = blocker / "sub"  # a folder inside a regular file: cannot be created
    target = str(bad / "map.nc") if option == "--netcdf" else str(bad)
    assert main(["friction", "cdc", "-p", "Delta=3", "--vary", "v=0.1", option, target,
                 "--no-progress"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and says.format(bad=bad) in err[0], err


@pytest.mark.parametrize("argv", [
    ["diagram", "sedf", "-p", "mu=0.1", "-p", "lam=1", "--vary", "Delta=0:6", "--vary",
     "beta=0.3:1.6"],
    ["lock", "coupled-vdp", "-p", "mu=0.05", "-p", "c=0.3", "--vary", "sigma=-1:1"],
    ["spectrum", "vdp", "-p", "mu=0.1", "-p", "D=0.01"],
    ["response", "duffing-forced", "-p", "mu=0.05", "-p", "zeta=0.1", "-p", "alpha=1", "-p",
     "h=0.5", "--vary", "sigma=-1:3"],
])
def test_an_unwritable_out_is_refused_before_the_computation(argv, tmp_path, capsys):
    """``--out`` under a regular file: these commands computed first (a diagram for minutes,
    a spectrum's 64 trajectories) and failed when writing ("cannot access", "out = ...").
    Now refused at once (well under a second), in one line naming ``--out``, and nothing is
    created."""
    import time

    blocker = tmp_path / "a-file"
    blocker.write_text("")
    t0 = time.process_time()
    assert main([*argv, "--out", str(blocker / "sub")]) == 2
    assert time.process_time() - t0 < 1.0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"cannot write to --out = '{blocker / 'sub'}'" in err[0], err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a-file"]


def test_noise_refuses_before_the_step_pilot_without_a_warning(capsys):
    """vdp at D = 1e300: the averaged amplitude density ``P(a) ~ a exp((mu/D)(a^2/2 -
    a^4/16))`` peaks at ``a^4 = 4 D/mu``, far beyond the quadrature's a = 1e6, and the
    averaging refuses; the step pilot ran first and its variance of the squared moments
    overflowed (a numpy RuntimeWarning on stderr before the error).  With warnings as
    errors the refusal is the one line."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert main(["noise", "vdp", "-p", "mu=0.1", "-p", "D=1e300"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "no averaged stationary state" in err[0], err


def test_ill_conditioned_kramers_solve_warns_through_its_flag_only():
    """vdp at mu = D = 1e-6 (``kbm noise vdp -p mu=1e-6 -p D=1e-6``): the Schur complements
    of the order-by-order LU have rcond ~ 1e-26 and scipy printed a LinAlgWarning per
    order; the unconverged solve is reported by its refinements (``hermite_change``, the
    command's "not converged" line), not by raw warnings.  32 functions x 301 points (a
    size that met such a complement) with LinAlgWarning as an error."""
    import warnings

    from scipy.linalg import LinAlgWarning

    from numerics.fokker_planck import stationary_kramers

    with warnings.catch_warnings():
        warnings.simplefilter("error", LinAlgWarning)
        sol = stationary_kramers("vdp", {"mu": 1e-6}, 1e-6, n_hermite=32, n_cheb=301)
    assert sol.coef.shape == (32, 302)



def test_a_negative_energy_density_is_reported_not_silent():
    """``kbm noise --method fokker-planck --json``'s ``P(E)`` at low friction (SEDF at rest,
    Delta = 3, mu = 0.002, D = 0.001) held eleven negative values in the tail (-2.9e-6 of a
    0.41 peak at E = 8.26, each within its stated change) without a word.  The spectral
    solution is not positive by construction; where it is negative the report says so
    (``negative``: the energies and values, the mass ``int max(-P, 0) dE`` on the grid's
    equal bins, and whether zero lies within each value's stated change, ``change >= 1``).
    By hand: P = 0.5, -0.1, 0.2, -0.05 on bins of 0.5 has the negative mass 0.075, and the
    last value's change 0.5 does not reach zero.  A coarse SEDF solve (mu = 0.05, D = 0.025,
    cost 1e6: 32 x 267) has such a tail; where ``P`` is positive (the CDC at rest, Boltzmann
    times the period, eq. 12) the report keeps its keys (its bytes)."""
    import numpy as np

    from numerics.fokker_planck import stationary_kramers
    from numerics.fokker_planck._energy_density import energy_density_report, negative_part

    hand = negative_part(np.array([0.0, 0.5, 1.0, 1.5]), np.array([0.5, -0.1, 0.2, -0.05]),
                         np.array([0.1, 2.0, 0.1, 0.5]))
    assert hand["E"] == [0.5, 1.5] and hand["P"] == [-0.1, -0.05]
    assert hand["mass"] == pytest.approx(0.075) and hand["within_change"] is False
    params = {"mu": 0.05, "Delta": 3, "beta": 1, "lam": 1}
    rep = energy_density_report(stationary_kramers("sedf", params, 0.025, max_cost=1e6,
                                                   basis="orthonormal"))
    P, E, change = (np.array(rep[k]) for k in ("P", "E", "change"))
    neg = rep["negative"]
    assert neg["E"] == list(E[P < 0]) and len(neg["E"]) > 0
    assert neg["within_change"] is bool(np.all(change[P < 0] >= 1))
    cdc = energy_density_report(stationary_kramers("cdc", {"mu": 0.15, "Delta": 2, "lam": 1.3,
                                                           "Omega": 1}, 0.09))
    assert min(cdc["P"]) > 0
    assert set(cdc) == {"E", "P", "change", "change_peak", "separatrices"}


def test_series_progress_counts_every_power_of_mu():
    """``kbm series --float --order 1000`` ran for minutes without a sign of life; the
    recursion now reports each power of ``mu`` (the command's tqdm bar on a terminal): the
    recursion to ``mu**N`` fixes ``a_N`` at ``mu**(N+1)``, N + 1 steps, and the series it
    returns is the same (van der Pol: omega* = 1 - mu^2/16 + 17 mu^4/3072 - ...)."""
    from kbm.slowflow.numeric_series import numeric_cycle_series

    steps = []
    s = numeric_cycle_series("vdp", 10, progress=steps.append)
    assert sum(steps) == 11
    assert s.omega[:5] == pytest.approx((1, 0, -1 / 16, 0, 17 / 3072), abs=1e-15)
    assert s.omega == numeric_cycle_series("vdp", 10).omega


@pytest.mark.parametrize("axis, values", [("lam", (0.5, 1.0)), ("Omega", (1.0, 2.0))])
def test_friction_maps_over_a_parameter_with_a_default(axis, values, capsys):
    """``kbm friction cdc -p Delta=3 --vary v=0.1 --vary lam=0.5,1`` (or ``Omega``, ``mu``)
    was refused, "lam is both fixed and an axis: give it once", though typed once: the
    command's default ``lam = 1`` went to the map as a fixed value.  The map's ``eta`` is
    the paper's ratio ``2 pi Delta/(Omega^2 lam)`` at each value of the axis."""
    import json
    import math

    assert main(["friction", "cdc", "-p", "Delta=3", "--vary", "v=0.1", "--vary",
                 f"{axis}={values[0]},{values[1]}", "--json", "--no-progress"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["axes"][axis] == list(values) and axis not in data["params"]
    lam = dict(lam=values, Omega=(1.0, 1.0))[axis]
    omega = dict(lam=(1.0, 1.0), Omega=values)[axis]
    expected = [2 * math.pi * 3 / (w**2 * lm) for w, lm in zip(omega, lam)]
    assert data["eta"][0] == pytest.approx(expected, rel=1e-12)
    assert data["error"] == [[None, None]]
