"""Reading user input runs no code (issue 16, item 1).

``kbm.parse`` (and so ``--rhs``, ``--potential``, ``--omega0``, ``--root``, parameter values
and reading JSON results back) checks the text with Python's own parser before sympy
sees it: only arithmetic, numbers, names and calls of mathematical functions are read.
Each attack string below would run code through ``sympy.sympify``; here it is a
``ModelError`` (one line and exit status 2 on the command line) and the marker file is
never written.
"""

from __future__ import annotations

import pytest
import sympy as sp

from kbm import ModelError, parse
from kbm.model.builtins import custom_model
from numerics.cli import main

ATTACKS = [
    '__import__("os").system("touch {marker}")',
    '__import__("os").system', "x.__class__.__base__",
    '(lambda: __import__("os").system("touch {marker}"))()',
    'exec("open(\'{marker}\', \'w\')")', 'eval("1+1")', 'open("{marker}", "w")',
    'getattr(x, "__class__")', "[c for c in ().__class__.__bases__]", "x[0]",
    '"touch {marker}"', "sin.__globals__", "Symbol('x').__init__",
    'Float("1").__class__', "().__class__", "{{1: 2}}", "x if 1 else 2", "x and 1",
    "lambda_: 1", "x := 1", "*x", "sin(x, key=lambda: 1)",
]


@pytest.mark.parametrize("attack", ATTACKS)
def test_attack_strings_run_nothing(attack, tmp_path):
    """Every attack string is refused with ModelError and writes nothing."""
    marker = tmp_path / "PWNED"
    text = attack.format(marker=marker)
    with pytest.raises(ModelError):
        parse(text)
    with pytest.raises(ModelError):
        custom_model(text)
    assert not marker.exists()


@pytest.mark.parametrize("flag", ["--rhs", "--omega0", "--param"])
def test_command_line_attacks_are_one_line_errors(flag, tmp_path, capsys):
    """On the command line the attack is one line on stderr and exit status 2."""
    marker = tmp_path / "PWNED"
    attack = f'__import__("os").system("touch {marker}")'
    argv = ["cycle", "--rhs", "(1 - x**2)*xdot", "-p", "mu=1"]
    if flag == "--rhs":
        argv[2] = attack
    elif flag == "--omega0":
        argv += ["--omega0", attack]
    else:
        argv[4] = f"mu={attack}"
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "error" in err[0]
    assert not marker.exists()


def test_expressions_still_read():
    """The expressions the toolkit writes (and users type) read as before: powers, ^,
    Bessel sums, the shadowed parameter names, rationals and floats."""
    x, xdot, a, k, n = sp.symbols("x xdot a k n")
    assert parse("(1 - x**2)*xdot") == (1 - x**2) * xdot
    assert parse("x^3") == x**3
    assert parse("Sum(besselj(2*n+1, k*a), (n, 0, oo))") == sp.Sum(
        sp.besselj(2 * n + 1, k * a), (n, 0, sp.oo))
    assert parse("beta + gamma + zeta + lambda").free_symbols == set(
        sp.symbols("beta gamma zeta lambda"))
    assert parse("3/2") == sp.Rational(3, 2)
    assert parse("-tanh(xdot/0.05)") == -sp.tanh(xdot / 0.05)


def test_rhs_starting_with_a_minus_sign(capsys):
    """``--rhs -x**3 ...`` is a value, not an option (issue 16, item 5)."""
    assert main(["derive", "--rhs", "-x**3", "--order", "1"]) == 0
    assert "A_1" in capsys.readouterr().out


def test_derivatives_are_refused():
    """``diff(x, t)`` in F used to become 0 silently; F is a function of x and xdot only."""
    with pytest.raises(ModelError, match="not a known function"):
        parse("diff(x, t)")
