"""The ``kbm derive`` and ``kbm series`` commands: JSON contents, and errors as one line + exit 2."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest
import sympy as sp

from kbm import parse
from numerics.cli import main


def run_cli(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_derive_json_round_trip_vdp(capsys):
    """van der Pol (Bogoliubov & Mitropolsky ch. 1): the JSON strings parse back to
    A_1 = a/2 (1 - a^2/4), B_2 = -(1/8 - a^2/8 + 7a^4/256), u_1 = -a^3/32 sin 3psi."""
    code, out, _ = run_cli(capsys, "derive", "vdp", "--order", "2", "--json")
    assert code == 0
    data = json.loads(out)
    assert data["model"] == "vdp" and data["order"] == 2
    assert data["A"][0] is None and data["B"][0] is None and data["u"][0] is None
    a, psi = sp.symbols("a psi")
    assert sp.expand(parse(data["A"][1]) - a / 2 * (1 - a**2 / 4)) == 0
    assert sp.expand(parse(data["B"][2]) + (sp.Rational(1, 8) - a**2 / 8
                                            + sp.Rational(7, 256) * a**4)) == 0
    assert sp.expand(parse(data["u"][1]) + a**3 / 32 * sp.sin(3 * psi)) == 0


def test_derive_json_sedf_bessel(capsys):
    """sedf first order (paper eq. 3): B_1 = delta J_1(k a)/(Omega a) is in the phase
    equation, A_1 = a/2 (1 - beta a^2/4) has no Bessel term (against the paper's eq. 7)."""
    code, out, _ = run_cli(capsys, "derive", "sedf", "--order", "1", "--json")
    data = json.loads(out)
    a, k, delta, Omega, beta = sp.symbols("a k delta Omega beta")
    assert sp.simplify(parse(data["B"][1]) - delta * sp.besselj(1, k * a) / (Omega * a)) == 0
    assert sp.expand(parse(data["A"][1]) - a / 2 * (1 - beta * a**2 / 4)) == 0


def test_derive_user_rhs(capsys):
    """A user's F via --rhs: Duffing written by hand gives B_1 = 3a^2/8 (textbook)."""
    code, out, _ = run_cli(capsys, "derive", "--rhs=-x**3", "--order", "1", "--json")
    a = sp.Symbol("a")
    assert sp.expand(parse(json.loads(out)["B"][1]) - 3 * a**2 / 8) == 0


def test_series_json_andersen_geer(capsys):
    """van der Pol limit-cycle frequency 1 - e^2/16 + 17e^4/3072 + 35e^6/884736
    (Andersen & Geer 1982), as exact rationals in JSON."""
    code, out, _ = run_cli(capsys, "series", "vdp", "--order", "6", "--json")
    data = json.loads(out)
    assert [sp.Rational(c) for c in data["omega"]] == [
        1, 0, sp.Rational(-1, 16), 0, sp.Rational(17, 3072), 0, sp.Rational(35, 884736)]
    assert sp.Rational(data["amplitude"][0]) == 2


@pytest.mark.parametrize("argv, needle", [
    (["derive", "--rhs", "exp(x)", "--order", "1"], "exp(x)"),
    (["derive", "--rhs", "Abs(xdot)", "--order", "1"], "Abs(xdot)"),
    (["derive", "--rhs", "1/x", "--order", "1"], "1/x"),
    (["derive", "vdp", "--order", "0"], "order"),
    (["derive", "sedf", "--order", "3"], "order 3"),
    (["derive", "sedf", "--order", "1", "--param", "v=0.1"], "autonomous"),
    (["derive", "nosuchmodel", "--order", "1"], "unknown model"),
    (["derive", "vdp", "--order", "1", "--param", "beta"], "NAME=VALUE"),
    (["derive", "sedf", "--order", "1", "--param", "gamma=1"], "unknown parameter"),
    (["derive", "--rhs", "x +* 2", "--order", "1"], "cannot read"),
    (["series", "sedf", "--order", "2"], "polynomial"),
])
def test_errors_are_one_line_and_exit_2(capsys, argv, needle):
    """Bad input: a one-line message naming the problem and exit status 2, never a traceback."""
    code, out, err = run_cli(capsys, *argv)
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and needle in lines[0], err


def test_console_script_entry_point():
    """``python -m numerics.cli`` runs the same command line (exit status passed through)."""
    proc = subprocess.run([sys.executable, "-m", "numerics.cli", "derive", "vdp", "--order", "0"],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2 and "order" in proc.stderr and "Traceback" not in proc.stderr


def test_json_round_trip_is_exact_for_bessel_sums(capsys):
    """Every JSON string of the sedf order-2 expansion (nested Bessel sums included) reads
    back with kbm.parse to exactly the engine's expression."""
    from kbm import derive

    code, out, _ = run_cli(capsys, "derive", "sedf", "--order", "2", "--json")
    data = json.loads(out)
    res = derive("sedf", 2)
    for key, seq in (("A", res.A), ("B", res.B), ("u", res.u)):
        for n in (1, 2):
            assert parse(data[key][n]) == seq[n], (key, n)
