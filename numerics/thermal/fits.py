"""The thermally activated friction laws fitted to simulated thermal friction maps.

* Muser, PRB 84 (2011) 125419: the kinetic friction ``F = a(T) arsinh(v/v_c(T))`` over the
  crossover from the linear (thermolubric, ``v << v_c``) to the logarithmic regime, with a
  power law ``a(T) = c T^alpha`` fitted to the per-temperature prefactors;
* Sang, Dube and Grant, PRL 87 (2001) 174301: the creep law of the slip force, ``F_c - F =
  c T^a |ln(v/v_c)|^b`` (:func:`numerics.escape.creep.fit_creep`, theory ``a = b = 2/3``).

Muser's fit (:func:`fit_muser`) is weighted by the standard errors of the simulated points
and returns the parameters with their standard errors (the covariance of the weighted least
squares, scaled by the reduced chi-square when it exceeds 1).  The creep fit
(:func:`numerics.escape.creep.fit_creep`) takes no standard errors: unweighted least squares
in logarithms, its errors from the spread of the per-temperature exponents and the
residuals of ``ln C`` against ``ln T``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import curve_fit

from kbm.errors import ParameterError
from kbm.output.strict_json import Rendered

from ..escape.creep import law_points

__all__ = ["MuserFit", "fit_muser"]


@dataclass(frozen=True)
class MuserFit(Rendered):
    """``F = a(T) arsinh(v/v_c(T))`` per temperature and ``a(T) = c T^alpha``.

    Attributes
    ----------
    kT : tuple of float
    a, a_err, v_c, v_c_err : tuple of float
        Per temperature.
    alpha, alpha_err : float
        The exponent of ``a(T)`` (weighted least squares of ``ln a`` against ``ln T``).
    chi2 : tuple of float
        Reduced chi-square of each temperature's fit.
    """

    kT: tuple
    a: tuple
    a_err: tuple
    v_c: tuple
    v_c_err: tuple
    alpha: float
    alpha_err: float
    chi2: tuple


def fit_muser(kT, v, F, F_err) -> MuserFit:
    """Fit Muser's ``F = a arsinh(v/v_c)`` at each temperature, then ``a = c T^alpha``.

    Raises
    ------
    kbm.errors.ParameterError
        Fewer than two temperatures or three velocities at one of them; columns of
        different lengths, not finite, ``kT`` or ``v`` not positive, ``F_err`` negative; a
        fitted prefactor ``a(T) <= 0`` (no power law ``c T^alpha``).
    """
    kT, v, F, F_err = law_points("fit_muser", {"kT": kT, "v": v, "F": F, "F_err": F_err},
                                 positive=("kT", "v"), errors=("F_err",))
    temps = np.unique(kT)
    if temps.size < 2:
        raise ParameterError("Muser's fit needs two temperatures at least")
    out = {k: [] for k in ("a", "a_err", "v_c", "v_c_err", "chi2")}
    for T in temps:
        m = kT == T
        if np.count_nonzero(m) < 3:
            raise ParameterError(f"Muser's fit needs three velocities at least at kT = {T:g}")
        sig = np.maximum(F_err[m], 1e-12)

        def law(z, a, lnvc):
            return a * np.arcsinh(np.exp(z - lnvc))

        p, cov = curve_fit(law, np.log(v[m]), F[m], p0=(float(np.max(F[m])) / 4,
                                                        float(np.log(np.min(v[m])))),
                           sigma=sig, absolute_sigma=True, maxfev=20000)
        r = (F[m] - law(np.log(v[m]), *p)) / sig
        dof = max(1, int(np.count_nonzero(m)) - 2)
        chi2 = float(np.sum(r**2) / dof)
        cov = cov * max(1.0, chi2)
        out["a"].append(float(p[0]))
        out["a_err"].append(float(math.sqrt(cov[0, 0])))
        out["v_c"].append(float(math.exp(p[1])))
        out["v_c_err"].append(float(math.exp(p[1]) * math.sqrt(cov[1, 1])))
        out["chi2"].append(chi2)
    a, ae = np.array(out["a"]), np.array(out["a_err"])
    if np.any(a <= 0):
        i = int(np.flatnonzero(a <= 0)[0])
        raise ParameterError(f"Muser's fit: the prefactor a = {a[i]:g} at kT = {temps[i]:g} "
                             "is not positive (the forces do not grow with v), so there is no "
                             "power law a = c T^alpha to fit")
    w = (a / ae) ** 2  # var(ln a) = (ae/a)^2
    X = np.vstack([np.ones_like(temps), np.log(temps)]).T
    cov = np.linalg.inv(X.T @ (w[:, None] * X))
    coef = cov @ X.T @ (w * np.log(a))
    resid = np.log(a) - X @ coef
    if temps.size > 2:
        cov = cov * max(1.0, float(np.sum(w * resid**2) / (temps.size - 2)))
    return MuserFit(tuple(map(float, temps)), tuple(out["a"]), tuple(out["a_err"]),
                    tuple(out["v_c"]), tuple(out["v_c_err"]), float(coef[1]),
                    float(math.sqrt(cov[1, 1])), tuple(out["chi2"]))
