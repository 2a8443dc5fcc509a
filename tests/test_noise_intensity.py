"""The one check of the noise intensity ``D`` of ``x'' + ... = sqrt(2 D) xi(t)`` (issue 36).

:func:`kbm.parameters.names.noise_intensity` is the only check of ``D``: every command that
takes the noise (``kbm noise``, ``escape``, ``friction`` with noise, ``spectrum`` of a
self-excited, forced or coupled model) refuses ``D <= 0`` (``D < 0`` where ``D = 0`` is the
deterministic model: ``kbm friction``), NaN, infinity and a non-number with the same one-line
message and exit status 2, before any work.
"""

from __future__ import annotations

import math

import pytest

from kbm.errors import ParameterError
from kbm.parameters.names import noise_intensity
from numerics.cli import main

#: the message, whatever the command: what to pass, in command-line terms
SAYS = "give the noise intensity of sqrt(2 D) xi as -p D=VALUE with"


@pytest.mark.parametrize("given", ["0.01", "1/100", 0.01, "1e-2"])
def test_values_read_exactly(given):
    """The decimal, the fraction and the float all read as the float nearest 1/100."""
    assert noise_intensity(given) == 0.01
    assert noise_intensity(given, "a linewidth needs noise") == 0.01


def test_zero_is_the_deterministic_model_unless_refused():
    assert noise_intensity("0") == 0.0
    with pytest.raises(ParameterError, match=r"^D = 0: .* D > 0 and finite \(nothing escapes"):
        noise_intensity(0.0, "nothing escapes")


@pytest.mark.parametrize("bad, shown", [(-1, "-1"), ("-0.5", "-0.5"), (math.nan, "nan"),
                                        ("inf", "inf"), ("abc", "abc"), (None, "None")])
def test_bad_values_name_what_to_pass(bad, shown):
    with pytest.raises(ParameterError) as err:
        noise_intensity(bad)
    assert str(err.value).startswith(f"D = {shown}: {SAYS} D >= 0 and finite")


#: each command with noise, at valid values but for D
COMMANDS = {
    "noise": ["noise", "cdc", "-p", "mu=0.1", "-p", "Delta=3"],
    "escape": ["escape", "cdc", "-p", "mu=0.1", "-p", "Delta=3"],
    "friction": ["friction", "cdc", "-p", "mu=0.1", "-p", "Delta=3", "--vary", "v=0.1",
                 "--no-progress"],
    "spectrum": ["spectrum", "vdp", "-p", "mu=0.1"],
    "spectrum-forced": ["spectrum", "duffing-forced", "-p", "mu=0.05", "-p", "zeta=0.5", "-p",
                        "alpha=1", "-p", "h=2", "--vary", "sigma=0.8"],
    "spectrum-coupled": ["spectrum", "coupled-vdp", "-p", "mu=0.1", "-p", "c=0.3", "-p",
                         "sigma=0.2"],
}
#: the commands that accept D = 0 (the deterministic slider of kbm friction)
ZERO_ACCEPTED = {"friction"}


CASES = [(command, value) for command in sorted(COMMANDS)
         for value in ("0", "-1", "nan", "inf", "abc")
         if not (value == "0" and command in ZERO_ACCEPTED)]


@pytest.mark.parametrize("command, value", CASES)
def test_every_command_refuses_a_bad_D_in_one_line(command, value, capsys):
    assert main([*COMMANDS[command], "-p", f"D={value}"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    bound = ">= 0" if command in ZERO_ACCEPTED else "> 0"
    assert f"D = {value}: {SAYS} D {bound} and finite" in err[0], err[0]
