"""The small things of issue 40 item 11: what the text of ``kbm friction``, ``kbm noise`` and
``kbm cycle --all`` looks like to a new user (no leading blank line, no spurious digits,
numbers with their digits, a quantity named for what it is)."""

from __future__ import annotations

import json
import re

import pytest

from numerics.cli import main


def _out(argv, capsys):
    code = main(argv)
    return code, capsys.readouterr().out


def test_friction_table_starts_with_its_header(capsys):
    """The table begins with the model's line, not a blank one; two tables (``--against``)
    are separated by exactly one blank line."""
    code, out = _out(["friction", "cdc", "-p", "Delta=3", "--vary", "v=2,4",
                      "--workers", "1", "--against", "cdc", "--no-progress"], capsys)
    assert code == 0
    lines = out.splitlines()
    assert lines[0].startswith("cdc: mu = 0.1")
    assert lines.count("") == 1 and lines[lines.index("") + 1].startswith("cdc: ")


def test_noise_prints_the_boltzmann_moment_with_its_digits_and_the_burn_in_in_steps(capsys):
    """Linear damping x'' + x = -2 mu zeta x' + sqrt(2 D) xi: equipartition (the Boltzmann
    density exp(-E/kT), kT = D/(2 mu zeta)) gives <x^2> = kT = 1 exactly here, printed
    with six digits like the other moments; the burn-in, a whole number of steps
    (numerics.thermal.stationary.default_times), is printed as asked with its step count,
    not as 400.003."""
    code, out = _out(["noise", "linear_damping", "-p", "mu=0.05", "-p", "D=0.01", "-p",
                      "zeta=0.1", "--trajectories", "8", "--t-end", "20"], capsys)
    assert code == 0
    line = next(ln for ln in out.splitlines() if "Boltzmann <x^2>" in ln)
    value = line.rsplit(":", 1)[1].strip()
    assert value == "1.00000" and float(value) == pytest.approx(0.01 / (2 * 0.05 * 0.1))
    m = re.search(r"burn-in of (\S+) \((\d+) steps\), dt = (\S+),", out)
    assert m and m.group(1) == "400"
    steps, dt = int(m.group(2)), float(m.group(3))
    assert 0 <= steps * dt - 400 < 2 * dt  # 20/|mu| rounded up to a whole step (dt to 4 digits)


def test_cycle_all_names_the_largest_x_and_gives_the_smallest(capsys):
    """A cycle in the left-hand side well of the SEDF (docs/energy.rst) has a negative
    largest x: the text calls it x_max (JSON key ``amplitude_max``, kept) and gives x_min
    beside it, the well's centre between them and both below 0; the outer cycle
    is symmetric (x -> -x of the paper's eq. 3 at v = 0), x_min = -x_max."""
    argv = ["cycle", "sedf", "-p", "mu=0.1", "-p", "Delta=1.5", "-p", "beta=1.3", "-p",
            "lam=1", "--all"]
    code, out = _out(argv, capsys)
    assert code == 0 and "amplitude_max" not in out
    x_max = [float(v) for v in re.findall(r"x_max \(largest x\)\s+(\S+)", out)]
    x_min = [float(v) for v in re.findall(r"x_min \(smallest x\)\s+(\S+)", out)]
    assert main([*argv, "--json"]) == 0
    cycles = json.loads(capsys.readouterr().out)["cycles"]
    assert x_max == pytest.approx([c["amplitude_max"] for c in cycles], rel=1e-10)
    left = next(i for i, c in enumerate(cycles) if c["annulus"] == "side well at x=-0.898")
    assert x_min[left] < -0.898 < x_max[left] < 0
    outer = next(i for i, c in enumerate(cycles) if c["annulus"] == "outer")
    assert abs(x_min[outer] + x_max[outer]) < 1e-5
