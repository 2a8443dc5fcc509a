"""Accuracy of the double-precision cycles (issue 16, items 2 and 3).

- the first-harmonic amplitude of relaxation cycles (van der Pol, mu = 20 and 50)
  agrees with the independent mpmath Taylor integrator (its own quadrature of
  x cos(wt), x sin(wt) inside the Taylor steps) to 1e-10;
- the printed digits never exceed the accuracy estimate;
- a weakly attracting cycle (mu = 1e-6) is right to 1e-12 (high-precision path),
  and its message says what limits the double-precision shooting;
- mu = 0 is an error (no isolated cycle); mu < 0 gives the unstable cycle.
"""

from __future__ import annotations

import math

import pytest

from kbm.errors import KBMError
from numerics import limit_cycle
from numerics.cli import main
from numerics.cycles import limit_cycle_mp
from numerics.errors import NoCycleError
from numerics.flow import compile_model


@pytest.mark.parametrize("mu", [20, pytest.param(50, marks=pytest.mark.slow)])
def test_first_harmonic_of_relaxation_cycles_matches_taylor_reference(mu):
    c = limit_cycle("vdp", {"mu": mu})
    ref = limit_cycle_mp(compile_model("vdp", {"mu": mu}).acceleration_expr, 16,
                         c.amplitude_max, c.period)
    a_ref = float(ref["amplitude_first_harmonic"])
    assert abs(c.amplitude_first_harmonic - a_ref) <= 1e-10 * a_ref
    assert abs(2 * abs(c.harmonics[1]) - a_ref) <= 1e-10 * a_ref
    # the estimate is honest: at least as large as a tenth of the true error, and small
    assert c.accuracy["amplitude_first_harmonic"] < 1e-10


@pytest.mark.slow  # 3-4 s; kept out of the default run (five-minute rule)
def test_vdp_mu20_first_harmonic_value():
    # 2.14447449099 (30-digit Taylor path); the 1024-sample FFT gave 2.14447429638
    c = limit_cycle("vdp", {"mu": 20})
    assert c.amplitude_first_harmonic == pytest.approx(2.14447449098896, abs=1e-11)


def test_cycle_prints_no_more_digits_than_the_accuracy_supports(capsys):
    assert main(["cycle", "vdp", "-p", "mu=1", "--rtol", "1e-6"]) == 0
    out = capsys.readouterr().out
    line = next(ln for ln in out.splitlines() if "amplitude_first_harmonic" in ln)
    value = line.split()[1]
    digits = len(value.replace(".", "").lstrip("0"))
    assert digits < 12 and "relative accuracy" in line
    true = 2.0149064642027  # the same at rtol 1e-12
    assert abs(float(value) - true) <= 10 * 10.0 ** (1 - digits) * true


def test_weakly_attracting_cycle_is_right_to_1e12_and_says_why():
    c = limit_cycle("vdp", {"mu": 1e-6})
    ref = limit_cycle_mp(compile_model("vdp", {"mu": 1e-6}).acceleration_expr, 25, 2.0,
                         2 * math.pi)
    assert abs(c.amplitude_max - float(ref["amplitude_max"])) < 1e-12
    assert abs(c.period - float(ref["period"])) < 1e-12
    assert abs(c.amplitude_first_harmonic - float(ref["amplitude_first_harmonic"])) < 1e-12
    assert "weakly" in c.message and "1/|1 - multiplier|" in c.message


def test_conservative_mu_zero_is_an_error_not_a_fake_cycle():
    with pytest.raises(NoCycleError, match="no isolated limit cycle"):
        limit_cycle("vdp", {"mu": 0})


def test_cli_mu_zero_exits_2_with_one_line(capsys):
    assert main(["cycle", "vdp", "-p", "mu=0"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("kbm cycle: error:") and err.count("\n") == 1


def test_negative_mu_finds_the_unstable_cycle():
    c = limit_cycle("vdp", {"mu": -0.1})
    assert not c.stable
    assert abs(c.floquet_multipliers[1]) > 1
    # time reversal t -> -t maps mu -> -mu: the same orbit as mu = 0.1
    c_plus = limit_cycle("vdp", {"mu": 0.1})
    assert c.period == pytest.approx(c_plus.period, rel=1e-10)
    assert c.amplitude_max == pytest.approx(c_plus.amplitude_max, rel=1e-10)
    assert abs(c.floquet_multipliers[1] * c_plus.floquet_multipliers[1] - 1) < 1e-8


def test_non_isolated_orbit_of_a_conservative_custom_model_is_refused():
    from kbm.model.builtins import custom_model

    with pytest.raises(KBMError, match="not isolated|not a cycle|no isolated"):
        limit_cycle(custom_model("-x**3"), {"mu": 1})
