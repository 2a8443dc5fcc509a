"""The thermal friction laws' fits recover the parameters of data generated from the laws.

* :func:`numerics.thermal.fits.fit_muser`: Muser, PRB 84 (2011) 125419,
  ``F = a(T) arsinh(v/v_c(T))`` with ``a(T) = c T^alpha``;
* :func:`numerics.escape.creep.fit_creep`: Sang, Dube and Grant, PRL 87 (2001) 174301,
  ``F_c - F = c T^a |ln(v/v_c(T))|^b``.

Without noise a fit of the law it fits returns its parameters to rounding.  With seeded
Gaussian noise the errors a fit states are checked by their z-scores ``(estimate -
truth)/error`` over fixed seeds: centred within three standard errors of their mean and
with a spread near 1 (an error of a least-squares fit is an estimate of the estimator's
standard deviation).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from kbm.errors import ParameterError
from numerics.escape.creep import fit_creep
from numerics.thermal.fits import fit_muser

TEMPS = np.array([0.01, 0.02, 0.04, 0.08])

# Muser: c = 0.8, alpha = 2/3, v_c(T) = 0.01 (T/0.01)^1.5, v over four decades
MUSER = {"c": 0.8, "alpha": 2 / 3}
V_M = np.logspace(-3, 1, 9)
KT_M, VV_M = np.repeat(TEMPS, V_M.size), np.tile(V_M, TEMPS.size)
VC_M = 0.01 * (TEMPS / 0.01)**1.5
F_M = MUSER["c"] * KT_M**MUSER["alpha"] * np.arcsinh(VV_M / np.repeat(VC_M, V_M.size))

# Sang et al.: c = 1.5, a = b = 2/3, F_c = 3, v_c(T) = 10 exp(-0.05/T), v << v_c
CREEP = {"c": 1.5, "a": 2 / 3, "b": 2 / 3, "Fc": 3.0}
V_C = np.logspace(-6, -2, 8)
KT_C, VV_C = np.repeat(TEMPS, V_C.size), np.tile(V_C, TEMPS.size)
VC_C = 10.0 * np.exp(-0.05 / TEMPS)
G_C = CREEP["c"] * KT_C**CREEP["a"] * np.abs(np.log(VV_C / np.repeat(VC_C, V_C.size)))**CREEP["b"]


def _z_scores(pairs):
    z = np.asarray(pairs, float)
    return z.mean(axis=0), z.std(axis=0, ddof=1), len(z)


def test_muser_fit_recovers_the_law_exactly_without_noise():
    """``F = c T^alpha arsinh(v/v_c(T))`` evaluated exactly: every parameter back."""
    r = fit_muser(KT_M, VV_M, F_M, np.full(F_M.size, 0.01))
    assert r.kT == pytest.approx(tuple(TEMPS), rel=0, abs=0)
    assert r.a == pytest.approx(tuple(MUSER["c"] * TEMPS**MUSER["alpha"]), rel=1e-9)
    assert r.v_c == pytest.approx(tuple(VC_M), rel=1e-9)
    assert r.alpha == pytest.approx(MUSER["alpha"], rel=1e-9)
    assert max(r.chi2) < 1e-12


def test_muser_fit_errors_are_standard_deviations_of_the_estimates():
    """Gaussian noise of standard deviation ``sigma`` given as ``F_err``, 100 seeds: the
    z-scores of ``alpha`` and of ``a`` at the lowest temperature are centred (|mean| below
    three standard errors of the mean) with a spread within 25 % of 1 (``alpha``'s below 1:
    the covariance is scaled up by the reduced chi-square when it exceeds 1)."""
    sigma = np.full(F_M.size, 0.02 * F_M.mean())
    z = []
    for seed in range(100):
        F = F_M + sigma * np.random.default_rng(seed).standard_normal(F_M.size)
        r = fit_muser(KT_M, VV_M, F, sigma)
        z.append(((r.alpha - MUSER["alpha"]) / r.alpha_err,
                  (r.a[0] - MUSER["c"] * TEMPS[0]**MUSER["alpha"]) / r.a_err[0]))
    mean, spread, n = _z_scores(z)
    assert np.all(np.abs(mean) < 3 * spread / math.sqrt(n)), (mean, spread)
    assert np.all((0.75 < spread) & (spread < 1.25)), spread


def test_creep_fit_recovers_the_law_exactly_without_noise():
    """``F = F_c - c T^a |ln(v/v_c(T))|^b`` evaluated exactly: every parameter back."""
    r = fit_creep(VV_C, KT_C, CREEP["Fc"] - G_C, CREEP["Fc"])
    assert (r.a, r.b, r.c) == pytest.approx((CREEP["a"], CREEP["b"], CREEP["c"]), rel=1e-9)
    assert r.b_each == pytest.approx((CREEP["b"],) * TEMPS.size, rel=1e-9)
    assert r.v_c == pytest.approx(tuple(VC_C), rel=1e-9)
    assert r.rms < 1e-12 and r.points == G_C.size


def test_creep_fit_errors_are_standard_deviations_of_the_estimates():
    """Log-normal noise ``F_c - F = G exp(0.02 xi)``, 100 seeds: the z-scores of ``a`` and
    ``b`` are centred (|mean| below three standard errors of the mean), ``a``'s spread
    within 25 % of 1 (it was 3 before ``a_err`` took in the error of the common ``b``) and
    ``b``'s below 2 (its error is a spread over four temperatures: Student's t with 3
    degrees of freedom, standard deviation sqrt(3))."""
    z = []
    for seed in range(100):
        noise = np.exp(0.02 * np.random.default_rng(seed).standard_normal(G_C.size))
        r = fit_creep(VV_C, KT_C, CREEP["Fc"] - G_C * noise, CREEP["Fc"])
        z.append(((r.a - CREEP["a"]) / r.a_err, (r.b - CREEP["b"]) / r.b_err))
    mean, spread, n = _z_scores(z)
    assert np.all(np.abs(mean) < 3 * spread / math.sqrt(n)), (mean, spread)
    assert 0.75 < spread[0] < 1.25, spread
    assert 0.75 < spread[1] < 2.0, spread


def _muser_args(**change):
    args = {"kT": KT_M, "v": VV_M, "F": F_M, "F_err": np.full(F_M.size, 0.01)}
    args.update(change)
    return args


@pytest.mark.parametrize("change, words", [
    ({"F": F_M[:-1]}, "same length"),
    ({"v": np.where(VV_M == VV_M[0], 0.0, VV_M)}, "v must be > 0"),
    ({"kT": -KT_M}, "kT must be > 0"),
    ({"F": np.where(VV_M == VV_M[0], np.nan, F_M)}, "F must be finite"),
    ({"F_err": np.full(F_M.size, -0.01)}, "F_err must be >= 0"),
    ({"F": np.where(KT_M == TEMPS[0], -F_M, F_M)}, "a = .* is not positive"),
    ({"kT": np.full(F_M.size, 0.01)}, "two temperatures"),
    ({"kT": KT_M[7:], "v": VV_M[7:], "F": F_M[7:], "F_err": np.full(F_M.size - 7, 0.01)},
     "three velocities"),                                # two left at the lowest T
])
def test_muser_fit_refuses_bad_points_with_what_to_change(change, words):
    with pytest.raises(ParameterError, match=words):
        fit_muser(**_muser_args(**change))


@pytest.mark.parametrize("args, words", [
    ((VV_C, KT_C[:-1], CREEP["Fc"] - G_C, CREEP["Fc"]), "same length"),
    ((-VV_C, KT_C, CREEP["Fc"] - G_C, CREEP["Fc"]), "v must be > 0"),
    ((VV_C, KT_C, CREEP["Fc"] + G_C, CREEP["Fc"]), "below the static force"),
    ((VV_C, KT_C, CREEP["Fc"] - G_C, math.nan), "Fc must be a finite number"),
    ((VV_C, np.full(G_C.size, 0.01), CREEP["Fc"] - G_C, CREEP["Fc"]), "two temperatures"),
    ((VV_C[5:], KT_C[5:], CREEP["Fc"] - G_C[5:], CREEP["Fc"]), "four velocities"),
])
def test_creep_fit_refuses_bad_points_with_what_to_change(args, words):
    with pytest.raises(ParameterError, match=words):
        fit_creep(*args)
