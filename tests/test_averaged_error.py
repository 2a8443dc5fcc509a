"""The expected error of each averaged moment of ``kbm noise`` (issue 36: "each averaged
number states its order and its expected error"; :mod:`numerics.thermal.averaged_error`).

The references are independent of the averaging: the stationary Kramers equation solved
numerically (:func:`numerics.thermal.stationary.fokker_planck_moments`, stated error
<= 2e-9 for van der Pol), the truth against which each stated error is judged.
"""

from __future__ import annotations

import functools

import pytest

from numerics.noise.validity import averaged_error
from numerics.thermal.stationary import noise_report
from numerics.thermal._kramers_outputs import fokker_planck_moments


@functools.lru_cache(maxsize=None)
def _truth(mu: float) -> dict:
    """The Kramers solution's moments at D = mu/2, solved once per mu in this module (the
    tests read them, never change them)."""
    fp, why = fokker_planck_moments("vdp", {"mu": mu}, mu / 2, 1.0)
    assert fp is not None, why
    return fp


@functools.lru_cache(maxsize=None)
def _first_order_without_fp(mu: float) -> dict:
    """``noise_report`` of vdp at D = mu/2, 8 trajectories to t = 20, without the
    Fokker-Planck solution: computed once per mu in this module (read, never changed)."""
    return noise_report("vdp", {"mu": mu, "D": mu / 2}, trajectories=8, t_end=20,
                        fokker_planck=False)


@pytest.mark.parametrize("mu", [0.05, 0.1, pytest.param(0.3, marks=pytest.mark.slow)])  # 0.3: 7 s
def test_next_order_estimates_the_first_order_error(mu):
    """Van der Pol, D/mu = 0.5, first order without the Fokker-Planck solution: the stated
    error is the second order's correction |A_2 - A_1| (the first omitted term of the
    series), and it is the true error |A_1 - FP| within 20 % at mu = 0.05, 0.1 and 0.3
    (measured: 1.00, 1.02, 1.16 times it for <a^2>)."""
    rep = _first_order_without_fp(mu)
    fp = _truth(mu)
    assert rep["averaged_order"] == 1
    for key in ("a2", "x2"):
        m = rep["moments"][key]
        assert m["averaged_error_source"] == "next order"
        true = abs(m["averaged"] - fp[key])
        assert 0.95 * true <= m["averaged_error"] <= 1.2 * true, (key, m, fp[key])


def test_fokker_planck_error_and_next_order_agree():
    """Two independent routes to the first order's error at vdp mu = 0.1: measured against
    the Fokker-Planck solution (the default where it is affordable) and estimated by the next
    order agree within 5 %; the measured one bounds |averaged - FP|."""
    with_fp = noise_report("vdp", {"mu": 0.1, "D": 0.05}, trajectories=8, t_end=20)
    without = _first_order_without_fp(0.1)
    for key in ("a2", "x2"):
        m, n = with_fp["moments"][key], without["moments"][key]
        assert m["averaged_error_source"] == "fokker-planck"
        assert m["averaged_error"] >= abs(m["averaged"] - m["fokker_planck"])
        assert n["averaged_error"] == pytest.approx(m["averaged_error"], rel=0.05)


def test_simulation_bound_holds_at_second_order():
    """At second order (no next order) and without the Fokker-Planck solution the stated
    error is |averaged - simulated| + 2 stderr; at vdp mu = 0.3 (seed 3, 64 trajectories)
    it bounds the true error of A_2 against the independent Kramers solution."""
    rep = noise_report("vdp", {"mu": 0.3, "D": 0.15}, trajectories=64, t_end=100, seed=3,
                       fokker_planck=False, order=2)
    fp = _truth(0.3)
    assert rep["averaged_order"] == 2
    for key in ("a2", "x2"):
        m = rep["moments"][key]
        assert m["averaged_error_source"] == "simulation"
        assert m["averaged_error"] == pytest.approx(
            abs(m["averaged"] - m["simulated"]) + 2 * m["stderr"])
        assert abs(m["averaged"] - fp[key]) <= m["averaged_error"]


def test_no_reference_is_said():
    """Without an averaged value, or with no reference at all, the error is None and the
    source says "none" (never a guess)."""
    assert averaged_error({"averaged": None}) == (None, "none")
    assert averaged_error({"averaged": 1.0, "simulated": None, "stderr": None}) == (None, "none")
    # an unmeasured Fokker-Planck error is not used: the next reference is
    assert averaged_error({"averaged": 1.0, "fokker_planck": 1.1}, None, 1.05)[1] == "next order"


def test_text_states_the_expected_error(capsys):
    """``kbm noise`` prints the expected error with the order and its source.  The command
    runs in-process (its ``main``, the status it returns and what it prints; starting a
    process is checked by tests/test_startup.py and the bad-input catalogue)."""
    from numerics.cli import main

    code = main(["noise", "vdp", "-p", "mu=0.1", "-p", "D=0.05", "--trajectories", "8",
                 "--t-end", "20"])
    out = capsys.readouterr()
    assert code == 0, out.err
    assert "expected error of the averaged values (order 1): <a^2> +- " in out.out
    assert "against the Fokker-Planck solution" in out.out


def test_an_uncertain_fokker_planck_reference_is_passed_over():
    """A Fokker-Planck solve whose own error ``e |FP|`` exceeds the next source's estimate
    is not the reference (main's SEDF mu = 0.002 solve stated e = 0.14 and gave
    <a^2> = 3.669 against the averaged 4.006): the next order, else the simulation, is;
    a certain one still is."""
    m = {"averaged": 4.006, "fokker_planck": 3.669, "simulated": 4.00, "stderr": 0.01}
    assert averaged_error(m, 0.14) == (pytest.approx(0.026), "simulation")
    assert averaged_error(m, 0.14, 4.010) == (pytest.approx(0.004), "next order")
    err, source = averaged_error(dict(m, fokker_planck=4.0053), 1.5e-4)
    assert source == "fokker-planck" and err == pytest.approx(0.0007 + 1.5e-4 * 4.0053)
    assert averaged_error({"averaged": 4.006, "fokker_planck": 3.669}, 0.14)[1] == \
        "fokker-planck"  # no other estimate: the stated one, with its error in it
