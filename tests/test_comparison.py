"""KBM predictions against the true limit cycle: convergence orders, dissipation, CLI."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from numerics.cli import main
from numerics.comparison import compare, convergence_study, fit_slope, predicted_orders
from numerics.paper import paper_prediction

SEDF_SMALL = {"mu": 0.05, "Delta": 0.1, "beta": 1, "lam": 1}


@pytest.fixture(scope="module")
def vdp_study():
    return convergence_study("vdp", [0.025, 0.05, 0.1], orders=(1, 2, 3))


@pytest.fixture(scope="module")
def sedf_study():
    return convergence_study("sedf", [0.025, 0.05, 0.1], orders=(1, 2),
                             fixed={"delta": 2, "beta": 1, "k": "2*pi"})


def test_predicted_orders_vdp_parity():
    """Time reversal x(t; -eps) = x(-t; eps) of van der Pol (A_even = B_odd = 0) rounds the
    generic orders up to the parity of each quantity (numerics.comparison.convergence docstring)."""
    got = [predicted_orders("vdp", N) for N in (1, 2, 3, 4)]
    assert [g["amplitude"] for g in got] == [2, 2, 4, 4]
    assert [g["frequency"] for g in got] == [2, 4, 4, 6]
    assert [g["dissipation"] for g in got] == [3, 3, 5, 5]
    sedf = predicted_orders("sedf", 2)
    assert (sedf["amplitude"], sedf["frequency"], sedf["dissipation"]) == (2, 3, 3)


def test_fit_slope_exact_power():
    """The fit recovers the exponent of err = 3 eps^2.5 exactly."""
    eps = np.array([0.01, 0.02, 0.04])
    assert fit_slope(eps, 3 * eps**2.5) == pytest.approx(2.5, abs=1e-12)


@pytest.mark.parametrize("key", ["amplitude", "amplitude_max", "frequency", "harmonic3",
                                 "floquet_exponent", "dissipation"])
def test_vdp_slopes_match_theory(vdp_study, key):
    """Log-log slope of each error of KBM orders 1-3 for van der Pol equals the predicted
    order (Bogoliubov & Mitropolsky ch. 1; derivation in numerics.comparison.convergence)."""
    for N in (1, 2, 3):
        assert vdp_study.slopes[(N, key)] == pytest.approx(vdp_study.predicted[(N, key)],
                                                           abs=0.15), (N, key)


@pytest.mark.parametrize("key", ["amplitude", "frequency", "harmonic3", "floquet_exponent",
                                 "dissipation", "amplitude_max"])
def test_sedf_slopes_match_theory(sedf_study, key):
    """sedf (paper eq. 3) at fixed delta = Delta/mu = 2, beta = 1, lam = 1: the errors of
    KBM orders 1 and 2 fall at the predicted (generic) orders N, N + 1."""
    for N in (1, 2):
        assert sedf_study.slopes[(N, key)] == pytest.approx(sedf_study.predicted[(N, key)],
                                                            abs=0.4), (N, key)


def test_true_cycle_dissipation_zero(vdp_study, sedf_study):
    """Paper eq. (10): Gamma over the true cycle is zero (energy balance), to integration
    accuracy, while Gamma over the first-order KBM orbit is not."""
    for s in (vdp_study, sedf_study):
        assert np.max(s.numeric_dissipation) < 1e-9
        assert np.min(s.errors[(1, "dissipation")]) > 1e-6


def test_kbm_dissipation_shrinks_with_order(vdp_study):
    """Gamma over the reconstructed orbit shrinks with eps at order N + 1 (N + 2 for odd N
    of van der Pol), and with the order at fixed eps."""
    e = vdp_study.errors
    for i in range(3):
        assert e[(1, "dissipation")][i] > e[(2, "dissipation")][i] > e[(3, "dissipation")][i]


def test_sedf_order2_beats_order1_small_delta():
    """sedf, mu = 0.05, beta = 1, Delta = 0.1 (Delta/mu = 2): the second-order amplitude,
    frequency and maximum are closer to the true cycle than the first-order ones."""
    c = compare("sedf", SEDF_SMALL, orders=(1, 2))
    p1, p2 = c.predictions
    for key in ("amplitude", "frequency", "amplitude_max", "harmonic3", "dissipation"):
        assert c.relative_error(p2, key) < c.relative_error(p1, key) / 3, key
    assert c.relative_error(p2, "amplitude") < 1e-4


def test_vdp_first_order_cycle_values():
    """van der Pol, first order: a* = 2, omega* = 1, multiplier exp(-2 pi mu) (textbook);
    the true cycle at mu = 0.1 has the first-harmonic amplitude 2 + mu^2/64 + O(mu^4)
    (kbm.limit_cycle_series)."""
    c = compare("vdp", {"mu": 0.1}, orders=(1,))
    p = c.predictions[0]
    assert p.amplitude == pytest.approx(2.0, abs=1e-12)
    assert p.frequency == 1.0
    assert p.floquet_multiplier == pytest.approx(math.exp(-2 * math.pi * 0.1), rel=1e-12)
    assert c.numeric.amplitude_first_harmonic == pytest.approx(2 + 0.01 / 64, abs=1e-7)
    assert p.harmonics[3] == pytest.approx(0.1 * 8 / 32, rel=1e-10)


def test_paper_row_far_from_truth_at_small_delta():
    """The paper's eqs. (6)-(9) as printed miss the true cycle even where KBM is valid
    (mu = 0.05, Delta = 0.1): eq. (7) puts Delta J_1(k a) in the amplitude equation."""
    c = compare("sedf", SEDF_SMALL, orders=(2,), extra=[paper_prediction])
    pp, pk = c.predictions
    assert pp.source == "paper" and pp.order == 0 and pp.success
    assert c.relative_error(pp, "amplitude") > 100 * c.relative_error(pk, "amplitude")


def test_cli_compare_json(capsys):
    """``kbm compare vdp --json`` has the documented keys and the textbook first-order
    values."""
    assert main(["compare", "vdp", "--param", "mu=0.1", "--orders", "1,3", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["model"] == "vdp" and out["params"] == {"mu": 0.1}
    for k in ("period", "frequency", "amplitude_first_harmonic", "amplitude_max",
              "dissipation"):
        assert k in out["numeric"]
    assert [r["order"] for r in out["kbm"]] == [1, 3]
    for r in out["kbm"]:
        for k in ("amplitude", "amplitude_max", "frequency", "dissipation",
                  "floquet_multiplier"):
            assert isinstance(r[k], float)
    assert out["kbm"][0]["amplitude"] == pytest.approx(2.0)
    assert abs(out["numeric"]["dissipation"]) < 1e-9


def test_cli_compare_bad_orders(capsys):
    """A bad --orders is a one-line error with exit status 2."""
    assert main(["compare", "vdp", "--param", "mu=0.1", "--orders", "0"]) == 2
    assert "orders" in capsys.readouterr().err


def test_cli_convergence_json(capsys):
    """``kbm compare vdp --convergence`` fits the textbook order 2 of the first-order
    frequency error (omega = 1 - mu^2/16 + ...)."""
    assert main(["compare", "vdp", "--convergence", "0.05,0.1", "--orders", "1",
                 "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["predicted"]["1:frequency"] == 2
    assert out["slopes"]["1:frequency"] == pytest.approx(2.0, abs=0.05)


def test_time_reversal_symmetry_detection():
    """F(x, -x') = -F(x, x') for van der Pol and Rayleigh, not for the SEDF (its potential
    force -delta sin(k x) is even in x') nor for Duffing."""
    from numerics.comparison.convergence import time_reversal_symmetric

    assert time_reversal_symmetric("vdp") and time_reversal_symmetric("rayleigh")
    assert not time_reversal_symmetric("sedf") and not time_reversal_symmetric("duffing")


def test_compare_custom_model_rayleigh_velocity():
    """A user model: Rayleigh written with --rhs.  Its velocity obeys van der Pol, so the
    true cycle has amplitude 2 + O(mu^2) in x' and the first-order a* = 2 (omega0 = 1)."""
    from kbm.model.builtins import custom_model

    c = compare(custom_model("(1 - xdot**2/3)*xdot"), {"mu": 0.1}, orders=(1, 3))
    p1, p3 = c.predictions
    assert p1.amplitude == pytest.approx(2.0, abs=1e-12)
    assert c.relative_error(p3, "amplitude") < c.relative_error(p1, "amplitude") / 100


def test_averaged_cycles_keeps_roots_with_positive_frequency():
    """The order-2 averaged amplitude equation of the SEDF at Delta = 3 has a stable root at
    a = 2.1408 (sign change of sum mu^n A_n found by an independent scan here); the
    averaged cycles should include it."""
    from scipy.optimize import brentq

    from kbm import averaged_cycles
    from numerics.comparison.prediction import derived

    res = derived("sedf", 2)  # the derivation (and its compiled functions) of the comparisons
    vals = {"Omega": 1.0, "beta": 1.0, "delta": 30.0, "k": 2 * math.pi}
    f = res.functions("numpy")
    pars = [vals[p] for p in res.params]
    root = brentq(lambda s: f.amplitude_rate(s, 0.1, *pars, order=2), 2.0, 2.3)
    cycles = averaged_cycles(res, {"mu": 0.1, **vals}, order=2)
    assert any(abs(c.amplitude - root) < 1e-9 and c.stable for c in cycles)


def test_cli_compare_json_is_strict_at_the_paper_potential(capsys):
    """Paper eq. (3) at Delta = 3, beta = 1 (the paper's Fig. 4 potential, v = 0), where
    classical KBM is outside its range (delta = Delta/mu = 30): the JSON output is strict
    JSON (no NaN/Infinity tokens), order 1 gives the van der Pol amplitude a* = 2 exactly
    (A_1 = a/2 (1 - beta a^2/4): the potential only shifts the frequency, B&M ch. 1), and
    each reported relative error equals |predicted - true|/|true| recomputed here from the
    printed numbers."""
    def no_nan(token):
        raise ValueError(f"non-standard JSON constant {token}")

    assert main(["compare", "sedf", "-p", "mu=0.1", "-p", "Delta=3", "-p", "beta=1",
                 "-p", "lam=1", "--x-start", "3", "--json"]) == 0
    out = json.loads(capsys.readouterr().out, parse_constant=no_nan)
    o1, o2 = out["kbm"]
    true_a = out["numeric"]["amplitude_first_harmonic"]
    assert o1["success"] and o1["amplitude"] == pytest.approx(2.0, abs=1e-12)
    assert true_a == pytest.approx(2.0537, abs=1e-3)
    for row in (o1, o2):
        if row["success"]:
            assert row["relative_error"]["amplitude"] == pytest.approx(
                abs(row["amplitude"] - true_a) / true_a, rel=1e-12)
        else:
            assert row["amplitude"] is None or math.isfinite(row["amplitude"])


@pytest.mark.slow
def test_vdp_order4_slopes():
    """van der Pol, KBM order 4 on mu = 0.05, 0.1, 0.2 (at mu = 0.025 the frequency error,
    ~1e-13, is at the shooting accuracy): amplitude 4, frequency 6, third harmonic and
    Floquet exponent 5, as predicted.  (max x and Gamma, predicted 4 and 5, have small
    leading coefficients and show the next power on this range.)"""
    s = convergence_study("vdp", [0.05, 0.1, 0.2], orders=(4,))
    for key in ("amplitude", "frequency", "harmonic3", "floquet_exponent"):
        assert s.slopes[(4, key)] == pytest.approx(s.predicted[(4, key)], abs=0.25), key
