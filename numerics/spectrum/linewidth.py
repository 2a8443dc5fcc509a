"""The linewidth and mean frequency measured on sampled trajectories.

The phase of a trajectory is the unwrapped polar angle ``psi = atan2(-x'/omega0, x)`` of
the state (``x = a cos psi``, ``x' = -a omega0 sin psi``); it differs from the cycle's
asymptotic phase by a bounded periodic function, which changes neither its mean growth
nor its diffusion at long times.

* The mean angular frequency of trajectory ``i`` is ``(psi_i(T) - psi_i(0))/T``; the
  estimate is their mean, with the standard error of independent trajectories.
* The phase variance grows as ``var[psi(t + tau) - psi(t)] = 2 D_eff tau + c`` for ``tau``
  much longer than the amplitude's relaxation time ``1/lambda`` (the constant ``c`` comes
  from the amplitude-phase coupling and the periodic part of the angle).  Each trajectory
  gives ``M_2(tau)``, the mean of ``(psi(t + tau) - psi(t) - Omega tau)^2`` over every
  ``t`` (overlapping windows; ``Omega`` the ensemble's mean frequency, whose own error
  biases ``M_2`` by a relative ``tau/(N T)`` only), at several lags; half the
  least-squares slope of ``M_2`` against ``tau`` is its ``D_eff``, the HWHM of the
  fundamental.  The estimate is the mean over trajectories with its standard error.
* A Lorentzian plus a constant, least-squares fitted to the ensemble PSD near the
  fundamental with the PSD's standard errors as weights, gives a third HWHM; its standard
  error is the jackknife over trajectories (the Welch bins are correlated).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..noise.ensemble import Estimate
from .psd import PSD

__all__ = ["unwrapped_phase", "increment_sums", "phase_growth", "LorentzianFit",
           "fit_lorentzian"]


def unwrapped_phase(x: np.ndarray, v: np.ndarray, omega0: float) -> np.ndarray:
    """``psi = atan2(-x'/omega0, x)``, unwrapped (``x = a cos psi``)."""
    return np.unwrap(np.arctan2(-np.asarray(v, float) / omega0, np.asarray(x, float)))


def increment_sums(psi: np.ndarray, lags: np.ndarray) -> np.ndarray:
    """``[[count, sum d, sum d^2], ...]`` of the increments ``d = psi[k + L] - psi[k]`` over
    every ``k``, one row per lag ``L`` (in samples)."""
    out = np.empty((len(lags), 3))
    for j, L in enumerate(lags):
        d = psi[L:] - psi[:-L]
        out[j] = (d.size, float(np.sum(d)), float(np.sum(d * d)))
    return out


def phase_growth(sums: np.ndarray, taus: np.ndarray, frequency: float
                 ) -> tuple[Estimate, np.ndarray, np.ndarray]:
    """``(D_eff, M_2 mean, M_2 stderr)`` from every trajectory's :func:`increment_sums`.

    Parameters
    ----------
    sums : numpy.ndarray, shape (n_trajectories, n_lags, 3)
    taus : numpy.ndarray
        The lags in time units.
    frequency : float
        The ensemble's mean angular frequency.
    """
    n, s1, s2 = sums[..., 0], sums[..., 1], sums[..., 2]
    wt = frequency * taus[None, :]
    m2 = s2 / n - 2 * wt * s1 / n + wt * wt
    tc = taus - taus.mean()
    slopes = (m2 - m2.mean(axis=1, keepdims=True)) @ tc / np.sum(tc * tc)
    k = m2.shape[0]
    se = m2.std(axis=0, ddof=1) / math.sqrt(k) if k > 1 else np.zeros(m2.shape[1])
    return Estimate.of(slopes / 2) if k > 1 else Estimate(float(slopes[0] / 2), math.nan), \
        m2.mean(axis=0), se


@dataclass(frozen=True)
class LorentzianFit:
    """A Lorentzian ``P Gamma/(pi ((w - w_c)^2 + Gamma^2)) + b`` fitted to a PSD.

    Attributes
    ----------
    hwhm, hwhm_stderr, centre, power, background : float
    success : bool
    message : str
    stderr_source : str
        How ``hwhm_stderr`` was found: the jackknife over trajectories, or the least-squares
        covariance and why (fewer than :data:`JACKKNIFE_MIN` trajectories, or a refit of the
        jackknife failed); that covariance takes the correlated Welch bins as independent.
    """

    hwhm: float
    hwhm_stderr: float
    centre: float
    power: float
    background: float
    success: bool = True
    message: str = ""
    stderr_source: str = ""


#: the trajectories below which the fit's standard error is the least-squares one
JACKKNIFE_MIN = 8
#: what the least-squares standard error leaves out
_LEAST_SQUARES = ("least squares, which takes the correlated Welch bins as independent "
                  "(about 1.5 times too small)")


def fit_lorentzian(psd: PSD, centre: float, hwhm: float, *, span: float = 8.0
                   ) -> LorentzianFit:
    """Fit a Lorentzian to ``psd`` within ``centre -+ span hwhm`` (weights 1/stderr^2).

    The Welch estimate is the line convolved with the Hann window's kernel, which widens it
    by about a resolution; keep the resolution well below ``hwhm``.
    """
    from scipy.optimize import curve_fit

    if psd.resolution > hwhm / 2:
        return LorentzianFit(math.nan, math.nan, centre, math.nan, math.nan, False,
                             f"the resolution {psd.resolution:.3g} is coarser than half the "
                             f"line's width {hwhm:.3g}: no fit")
    sel = np.abs(psd.omega - centre) <= span * max(hwhm, psd.resolution)
    if np.count_nonzero(sel) < 6:
        return LorentzianFit(math.nan, math.nan, centre, math.nan, math.nan, False,
                             f"{np.count_nonzero(sel)} frequencies within the fit window: the "
                             "resolution is too coarse for the line")
    w, s = psd.omega[sel], psd.mean[sel]
    err = np.where(psd.stderr[sel] > 0, psd.stderr[sel], np.max(s) * 1e-3 + 1e-300)

    def model(w, c, g, p, b):
        return p * abs(g) / math.pi / ((w - c) ** 2 + g * g) + b

    p0 = (centre, hwhm, float(np.sum(s)) * psd.resolution, 0.0)
    try:
        popt, pcov = curve_fit(model, w, s, p0=p0, sigma=err, absolute_sigma=True,
                               maxfev=20000)
    except (RuntimeError, ValueError) as exc:
        return LorentzianFit(math.nan, math.nan, centre, math.nan, math.nan, False, str(exc))
    se = math.sqrt(pcov[1, 1]) if np.all(np.isfinite(pcov)) else math.nan
    n = 0 if psd.rows is None else len(psd.rows)
    source = (f"{_LEAST_SQUARES}: {n} trajectories, the jackknife needs {JACKKNIFE_MIN}"
              if n < JACKKNIFE_MIN else "jackknife over trajectories")
    if n >= JACKKNIFE_MIN:
        jack = _jackknife_hwhm(psd.rows[:, sel], w, err, model, popt)
        if isinstance(jack, str):
            source = f"{_LEAST_SQUARES}: {jack}"
        else:
            se = jack
    return LorentzianFit(abs(float(popt[1])), float(se), float(popt[0]), float(popt[2]),
                         float(popt[3]), stderr_source=source)


def _jackknife_hwhm(rows, w, err, model, popt) -> float | str:
    """The delete-one jackknife standard error of the fitted half width over the
    trajectories (``rows``, trajectories x bins): the fit refitted to the mean of every
    ``N - 1`` of them, weighted by their own standard errors (the weights vary with the
    data as the estimate's do).  Neighbouring Welch bins are correlated (Hann: ``4/9`` one bin
    apart, half overlap adds more), which the least-squares covariance, taking the bins as
    independent, leaves out: it understated the scatter of the half width about 1.5 times
    (a phase-diffusion line, 40 ensembles).  Where a refit fails, what failed (a string)."""
    from scipy.optimize import curve_fit

    n = len(rows)
    total, squares = rows.sum(axis=0), (rows * rows).sum(axis=0)
    widths = np.empty(n)
    for j in range(n):
        mean = (total - rows[j]) / (n - 1)  # the replicate, and its own weights
        var = np.maximum((squares - rows[j] ** 2 - (n - 1) * mean * mean) / (n - 2), 0.0)
        se = np.sqrt(var / (n - 1))
        try:
            pj, _ = curve_fit(model, w, mean, p0=popt,
                              sigma=np.where(se > 0, se, err), absolute_sigma=True,
                              maxfev=20000)
        except (RuntimeError, ValueError) as exc:
            return f"the jackknife's refit without trajectory {j} failed ({exc})"
        widths[j] = abs(pj[1])
    return float(math.sqrt((n - 1) / n * np.sum((widths - widths.mean()) ** 2)))
