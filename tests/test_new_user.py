"""What a new user meets on the command line (issue 24): series in ascending powers, a
version, help texts that list what exists, grammatical messages."""

from __future__ import annotations

import re

import pytest

from kbm.models import model_names
from numerics.cli import main


def _out(argv, capsys):
    try:
        code = main(argv)
    except SystemExit as exc:
        code = exc.code
    out = capsys.readouterr()
    return code, out.out, out.err


def test_series_prints_ascending_powers_of_mu(capsys):
    """van der Pol's frequency 1 - mu^2/16 + 17 mu^4/3072 + ... (Andersen & Geer 1982) is
    printed as a series is read, lowest power first."""
    code, out, _ = _out(["series", "vdp", "--order", "6"], capsys)
    assert code == 0
    line = out.splitlines()[0]
    assert line.startswith("omega* = 1 - mu**2/16 + 17*mu**4/3072")
    powers = [int(p) for p in re.findall(r"mu\*\*(\d+)", line)]
    assert powers == sorted(powers)


def test_float_series_header_names_the_powers_of_mu(capsys):
    code, out, _ = _out(["series", "vdp", "--order", "10", "--float"], capsys)
    assert code == 0
    assert "mu**2^k" not in out
    assert "c_0, c_2, c_4, ... (odd powers vanish) = 1.0, -6.25e-2" in out


def test_version(capsys):
    code, out, _ = _out(["--version"], capsys)
    assert code == 0 and re.fullmatch(r"kbm \S+\n", out)


def test_derive_help_lists_every_built_in_model(capsys):
    code, out, _ = _out(["derive", "--help"], capsys)
    text = " ".join(out.split())
    for name in model_names():
        assert name in text


def test_figures_help_has_a_description(capsys):
    _, out, _ = _out(["figures", "--help"], capsys)
    assert "Write the paper's Figs." in " ".join(out.split())


@pytest.mark.parametrize("argv", [["cycle", "vdp"]])
def test_missing_values_message_is_grammatical(argv, capsys):
    code, _, err = _out(argv, capsys)
    assert code == 2
    assert "model 'vdp' needs values for mu" in err and "functions needs" not in err
