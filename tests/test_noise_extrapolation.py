"""The weak order of BAOAB and of its Richardson pair, measured (issue 36, the integrator).

Independent references:

- the exact Boltzmann average ``<x^2>`` of ``x'' + x = -x' - x^3 + sqrt(2) xi`` (kT = 1), by
  quadrature of ``exp(-(x^2/2 + x^4/4))``;
- BAOAB samples the configurational density of a harmonic potential exactly at any
  stable step (Leimkuhler & Matthews, Appl. Math. Res. Express 2013, 34, sec. 4): the
  transfer operator of :mod:`numerics.noise.invariant` must give ``<x^2> = kT``;
- the transfer operator (a deterministic second method) against the compiled kernel's
  ensembles at the same steps (within a few standard errors).

The Richardson pair ``(4 E_{h/2} - E_h)/3`` is of weak order 4 because BAOAB's expansion has
even powers only (Talay & Tubaro 1990; a symmetric splitting).
"""

from __future__ import annotations

import math

import pytest
from scipy.integrate import quad

from kbm.errors import ParameterError
from kbm.model.builtins import custom_model
from numerics.noise import langevin_system
import numpy as np

from numerics.noise.extrapolate import (ORDER, _antithetic_rows, _pair_rows, richardson_moments,
                                        two_level_moments)
from numerics.noise.invariant import baoab_stationary_averages

GRID = {"nx": 56, "nu": 40, "nodes": 24}


def _force(x):
    return -x - x**3


def _exact_x2() -> float:
    def w(x):
        return math.exp(-(x * x / 2 + x**4 / 4))

    return (quad(lambda x: x * x * w(x), -30, 30, epsrel=1e-13)[0]
            / quad(w, -30, 30, epsrel=1e-13)[0])


def _bias(h: float, **grid) -> float:
    (x2,), residual = baoab_stationary_averages(_force, 1.0, math.sqrt(2.0), h,
                                                [lambda z: z * z], **(grid or GRID))
    assert residual < 1e-4
    return x2 / _exact_x2() - 1


def test_transfer_operator_is_exact_for_a_harmonic_potential():
    """Leimkuhler & Matthews (2013): BAOAB's configurational <x^2> = kT at any stable step
    (to 1e-7: the grid's resolution)."""
    for h, kT in ((0.5, 1.0), (0.3, 0.5)):
        (x2,), res = baoab_stationary_averages(lambda x: -x, 1.0, math.sqrt(2 * kT), h,
                                               [lambda z: z * z], nx=56, nu=48, nodes=24,
                                               x_half=7 * math.sqrt(kT),
                                               u_half=7 * math.sqrt(kT))
        assert res < 1e-5
        assert x2 == pytest.approx(kT, rel=1e-7)


def test_baoab_weak_order_two_and_the_pair_removes_it():
    """BAOAB's bias of <x^2> on the quartic falls like h^2 (measured order 2.14 between
    h = 0.3 and 0.15: the h^4 term); the Richardson pair at h = 0.3 removes 97 % of it."""
    b15, b30 = _bias(0.15), _bias(0.3)
    order = math.log2(b30 / b15)
    assert 1.9 < order < 2.3
    assert b30 < -1e-3  # a bias an ensemble resolves (below)
    assert abs((4 * b15 - b30) / 3) < 0.05 * abs(b30)


@pytest.mark.slow
def test_richardson_pair_weak_order_four():
    """R(h) = (4 E_{h/2} - E_h)/3 at h = 0.3 and 0.4: its error falls like h^4 (even
    expansion; Talay & Tubaro 1990)."""
    fine = {"nx": 96, "nu": 48, "nodes": 30}
    b = {h: _bias(h, **fine) for h in (0.15, 0.2, 0.3, 0.4)}
    r3, r4 = (4 * b[0.15] - b[0.3]) / 3, (4 * b[0.2] - b[0.4]) / 3
    assert math.log(r4 / r3) / math.log(4 / 3) == pytest.approx(ORDER, abs=0.3)


def test_pair_ensemble_against_the_transfer_operator_and_quadrature():
    """The compiled pair kernel at h = 0.3 (Gaussian increments, one Brownian path):
    ``E_h`` and ``E_{h/2}`` agree with the transfer operator within 4 standard errors;
    the extrapolated <x^2> agrees with exact quadrature within 3, where ``E_h`` is off
    by more than 3."""
    exact = _exact_x2()
    s = langevin_system(custom_model("-xdot - x**3", name="quartic"), {"mu": 1.0}, 1.0, "baoab")
    rich = richardson_moments(s, 0.3, trajectories=64, t_end=30000.0, burn_in=15.0,
                              seed=11)["x2"]
    b30, b15 = _bias(0.3), _bias(0.15)
    se_plain = rich.stderr  # E_h and R share their noise: the same order of error
    assert abs(rich.coarse / exact - 1 - b30) < 4 * se_plain / exact
    assert abs(rich.fine / exact - 1 - b15) < 4 * se_plain / exact
    assert abs(rich.extrapolated - exact) < 3 * rich.stderr
    assert abs(rich.coarse - exact) > 3 * rich.stderr
    assert abs(rich.correction - (b15 - b30) / 3 * exact) < 4 * rich.correction_stderr


def test_extrapolation_needs_baoab():
    s = langevin_system("rayleigh", {"mu": 0.1}, 0.05, "kp")
    with pytest.raises(ParameterError, match="BAOAB"):
        richardson_moments(s, 0.1, trajectories=8, t_end=1.0, burn_in=0.0)


def test_noise_report_extrapolate_states_method_and_error():
    """``kbm noise --extrapolate`` (library report): the Richardson <x^2> of the linearly
    damped oscillator (kT = 1) within 4 standard errors of the exact Boltzmann value; the
    JSON says how and states the error estimate; every other key stays."""
    from numerics.thermal.stationary import noise_report

    rep = noise_report("linear_damping", {"mu": 1, "zeta": 1, "D": 1}, trajectories=16, t_end=100.0,
                       dt=0.02, workers=1, fokker_planck=False, extrapolate=True)
    ext = rep["extrapolation"]
    assert ext["applied"] and ext["order"] == ORDER and ext["dt"] == rep["dt"]
    assert set(ext) >= {"method", "error_estimate", "correction", "correction_stderr"}
    assert ext["method"] == "two-level Richardson"
    assert ext["trajectories"]["coarse"] == 16
    assert ext["trajectories"]["pilot"] <= ext["trajectories"]["correction"] <= 16
    for k in ("x2", "a2"):  # the stated error combines both levels
        assert ext["error_estimate"][k] == pytest.approx(
            math.hypot(ext["coarse_stderr"][k], ext["correction_stderr"][k]), rel=1e-12)
        assert rep["moments"][k]["extrapolated"] == pytest.approx(
            ext["coarse"][k] + ext["correction"][k], rel=1e-12)
    x2 = rep["moments"]["x2"]
    assert set(x2) >= {"averaged", "simulated", "stderr", "boltzmann", "extrapolated",
                       "extrapolated_stderr"}
    assert abs(x2["extrapolated"] - x2["boltzmann"]) < 4 * x2["extrapolated_stderr"]
    assert ext["error_estimate"]["x2"] == x2["extrapolated_stderr"]
    plain = noise_report("linear_damping", {"mu": 1, "zeta": 1, "D": 1}, trajectories=8, t_end=10.0,
                         dt=0.02, workers=1, fokker_planck=False)
    assert plain["extrapolation"] is None and "extrapolated" not in plain["moments"]["x2"]


def test_two_level_estimator_against_quadrature_and_the_transfer_operator():
    """The two-level estimator at h = 0.3 on the quartic: level 0 (BAOAB, Gaussian
    increments) sits at the transfer operator's E_h within 4 standard errors and more than 3
    from exact quadrature; level 0 plus the pair's correction agrees with exact quadrature
    within 3 (Talay & Tubaro 1990; Giles 2008 for the allocation: fewer correction
    trajectories than level-0 ones)."""
    exact = _exact_x2()
    s = langevin_system(custom_model("-xdot - x**3", name="quartic"), {"mu": 1.0}, 1.0, "baoab")
    mom, sizes = two_level_moments(s, 0.3, trajectories=64, t_end=60000.0, burn_in=15.0,
                                   seed=21)
    m = mom["x2"]
    assert abs(m.coarse / exact - 1 - _bias(0.3)) < 4 * m.coarse_stderr / exact
    assert abs(m.coarse - exact) > 3 * m.coarse_stderr
    assert abs(m.value - exact) < 3 * m.stderr
    assert sizes["pilot"] <= sizes["correction"] < sizes["coarse"]
    assert m.stderr == pytest.approx(math.hypot(m.coarse_stderr, m.correction_stderr))


def test_two_level_same_numbers_however_split():
    """Each correction trajectory's numbers depend on (seed, index) alone (one SeedSequence
    child per trajectory): one call over 12 trajectories equals two calls over 5 and 7, and
    the estimator is the same with level 0 given or run inside."""
    s = langevin_system(custom_model("-xdot - x**3", name="quartic"), {"mu": 1.0}, 1.0, "baoab")
    whole = _pair_rows(s, 0.2, 10, 200, 4, 0, 12)
    parts = np.vstack([_pair_rows(s, 0.2, 10, 200, 4, 0, 5), _pair_rows(s, 0.2, 10, 200, 4, 5, 7)])
    assert np.array_equal(whole, parts)
    whole = _antithetic_rows(s, 0.2, 10, 200, 4, 0, 12)
    parts = np.vstack([_antithetic_rows(s, 0.2, 10, 200, 4, 0, 5),
                       _antithetic_rows(s, 0.2, 10, 200, 4, 5, 7)])
    assert np.array_equal(whole, parts)
    a, sa = two_level_moments(s, 0.2, trajectories=16, t_end=40.0, burn_in=2.0, seed=4)
    given = {k: (a[k].coarse, a[k].coarse_stderr) for k in ("x2", "a2")}
    b, sb = two_level_moments(s, 0.2, trajectories=16, t_end=40.0, burn_in=2.0, seed=4,
                              coarse=given)
    assert a == b and sa == sb
    c, _ = two_level_moments(s, 0.2, trajectories=16, t_end=40.0, burn_in=2.0, seed=5)
    assert c["x2"].value != a["x2"].value


def test_antithetic_correction_against_the_transfer_operator():
    """The antithetic correction (Giles & Szpruch 2014: the coarse step takes g_1 + g_2, the
    two fine runs (g_1, g_2) and (g_2, g_1)) has the synchronous pair's mean, (4/3)(E_{h/2} -
    E_h) of the transfer operator at h = 0.3 within 4 standard errors, and a variance more
    than 5 times smaller on the same streams (the part linear in g_1 - g_2 cancels;
    measured 24x at h = 0.32)."""
    exact = _exact_x2()
    s = langevin_system(custom_model("-xdot - x**3", name="quartic"), {"mu": 1.0}, 1.0, "baoab")
    h, m = 0.3, 32
    anti = _antithetic_rows(s, h, 50, 20000, 3, 0, m)[:, 0]
    sync = _pair_rows(s, h, 50, 20000, 3, 0, m)[:, 0]
    want = 4.0 / 3.0 * (_bias(h / 2) - _bias(h)) * exact
    se = anti.std(ddof=1) / math.sqrt(m)
    assert abs(anti.mean() - want) < 4 * se
    assert se < 0.1 * abs(want)  # a correction the ensemble resolves
    assert anti.var(ddof=1) < sync.var(ddof=1) / 5


def test_two_level_couplings_agree_with_quadrature():
    """Both couplings of the two-level estimator at h = 0.3 on the quartic agree with exact
    quadrature within 3 standard errors; the antithetic one runs fewer correction
    trajectories (Giles' allocation at five force evaluations per coarse step) and reports
    its coupling."""
    exact = _exact_x2()
    s = langevin_system(custom_model("-xdot - x**3", name="quartic"), {"mu": 1.0}, 1.0, "baoab")
    got = {c: two_level_moments(s, 0.3, trajectories=128, t_end=3000.0, burn_in=15.0,
                                seed=22, coupling=c) for c in ("antithetic", "synchronous")}
    for c, (mom, sizes) in got.items():
        assert abs(mom["x2"].value - exact) < 3 * mom["x2"].stderr
        assert sizes["coupling"] == c
    assert got["antithetic"][1]["correction"] < got["synchronous"][1]["correction"]
    assert got["antithetic"][0]["x2"].variance_ratio < got["synchronous"][0]["x2"].variance_ratio


def test_two_level_needs_baoab_and_trajectories():
    s = langevin_system("rayleigh", {"mu": 0.1}, 0.05, "kp")
    with pytest.raises(ParameterError, match="BAOAB"):
        two_level_moments(s, 0.1, trajectories=8, t_end=1.0, burn_in=0.0)
    q = langevin_system(custom_model("-xdot - x**3", name="quartic"), {"mu": 1.0}, 1.0, "baoab")
    with pytest.raises(ParameterError, match="pilot"):
        two_level_moments(q, 0.1, trajectories=8, t_end=1.0, burn_in=0.0, pilot=1)
    with pytest.raises(ParameterError, match="coupling"):
        two_level_moments(q, 0.1, trajectories=8, t_end=1.0, burn_in=0.0, coupling="none")


@pytest.mark.slow
def test_three_point_increments_have_another_h2_coefficient():
    """The toolkit's three-point increments (moments the Gaussian's up to the fifth, the
    sixth 9 instead of 15) give BAOAB another stationary bias than Gaussian ones: on the
    quartic at h = 0.4 the three-point ensemble's <x^2> sits more than 4 standard errors
    from the transfer operator's Gaussian E_h and further from exact quadrature (measured:
    -7.55e-3 +- 1.3e-4 against -4.86e-3, a coefficient 1.5 times the Gaussian one).  Why
    the two-level estimator runs its level 0 with Gaussian increments."""
    import numpy as np

    from numerics.noise.seeds import trajectory_states

    exact = _exact_x2()
    s = langevin_system(custom_model("-xdot - x**3", name="quartic"), {"mu": 1.0}, 1.0, "baoab")
    m, h = 64, 0.4
    sums, _ = s.kernels.stationary_stats(s._p(), s.sigma, np.zeros((m, 2)), 0.0, h, 50,
                                         200000, trajectory_states(8, 0, m), s.omega0, 1,
                                         -1.0, 1.0, 1)
    x2 = sums[:, 0] / exact - 1
    b3, se = float(x2.mean()), float(x2.std(ddof=1) / math.sqrt(m))
    bg = _bias(h, nx=96, nu=48, nodes=30)
    assert abs(b3 - bg) > 4 * se
    assert b3 < bg < 0
    assert 1.2 < b3 / bg < 1.9
