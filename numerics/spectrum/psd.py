"""The power spectral density of an ensemble of sampled trajectories, with a confidence band.

Each trajectory's one-sided PSD is estimated by Welch's method (Hann windows, half
overlap, the segment mean removed; :func:`scipy.signal.welch`) and converted to angular
frequency, so that

``integral_0^{pi/dt} S(omega) d omega = var(x)``

(Wiener-Khinchin with ``S(omega) = (1/pi) integral C(tau) cos(omega tau) d tau`` for
``omega >= 0``).  The estimate is the mean over trajectories; as the trajectories are
independent, its standard error is their standard deviation over ``sqrt(N)``, and the band
is ``mean -+ q stderr`` with ``q`` the Student quantile of ``N - 1`` degrees of freedom
(clipped below at 0: a density is not negative).  Every segment's mean is removed, so
the bin at ``omega = 0`` is biased low.

References
----------
P. D. Welch, IEEE Trans. Audio Electroacoust. 15, 70 (1967).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from kbm.errors import ParameterError

from ..errors import NumericsError

__all__ = ["PSD", "ensemble_psd", "ResolutionError", "resolution_of", "welch_rows", "combine"]


class ResolutionError(NumericsError):
    """The run is too short for the requested frequency resolution (the message gives the
    resolution the run would give)."""


@dataclass(frozen=True, eq=False)
class PSD:
    """A one-sided PSD in angular frequency, the mean over an ensemble with its band.

    Attributes
    ----------
    omega : numpy.ndarray
        Angular frequencies ``0, dw, 2 dw, ..., pi/dt``.
    mean : numpy.ndarray
        The ensemble mean of the per-trajectory Welch estimates.
    lower, upper : numpy.ndarray
        The confidence band ``mean -+ q stderr`` (``lower >= 0``).
    stderr : numpy.ndarray
        The standard error of ``mean``.
    resolution : float
        The spacing ``dw = 2 pi/(nperseg dt)`` of ``omega`` (angular).
    trajectories : int
    confidence : float
    nperseg : int
        Samples per Welch segment.
    """

    omega: np.ndarray
    mean: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    stderr: np.ndarray
    resolution: float
    trajectories: int = 0
    confidence: float = 0.95
    nperseg: int = 0

    def __post_init__(self) -> None:
        n = self.omega.shape
        for name in ("mean", "lower", "upper", "stderr"):
            if getattr(self, name).shape != n:
                raise ValueError(f"PSD.{name} has shape {getattr(self, name).shape}, "
                                 f"omega has {n}")

    def __repr__(self) -> str:
        return (f"PSD({self.omega.size} frequencies up to {self.omega[-1]:.4g}, resolution "
                f"{self.resolution:.3g}, {self.trajectories} trajectories)")

    def variance(self) -> float:
        """The integral of ``mean`` over omega by the trapezoid rule (Parseval's sum: the
        mean of the windowed segments' variances)."""
        w = np.full(self.omega.size, self.resolution)
        w[0] = 0.5 * self.resolution
        if self.nperseg % 2 == 0:
            w[-1] = 0.5 * self.resolution  # the Nyquist bin of an even segment
        return float(np.sum(w * self.mean))


def resolution_of(n_samples: int, dt: float) -> float:
    """The angular resolution ``2 pi/(n dt)`` of a segment of ``n`` samples at step ``dt``."""
    return 2.0 * math.pi / (n_samples * dt)


def ensemble_psd(x: np.ndarray, dt: float, *, nperseg: int | None = None,
                 confidence: float = 0.95, resolution: float | None = None) -> PSD:
    """The one-sided PSD (angular frequency) of an ensemble, with its confidence band.

    Parameters
    ----------
    x : numpy.ndarray, shape (n_trajectories, n_samples)
        Independent trajectories sampled every ``dt`` (a 1-d array is one trajectory; its
        band is then undefined and set to the estimate).
    dt : float
        The sample step.
    nperseg : int, optional
        Samples per Welch segment (default: a quarter of the run, so that each trajectory
        averages seven half-overlapping segments).
    confidence : float
        Level of the band (Student's ``t`` with ``N - 1`` degrees of freedom).
    resolution : float, optional
        The requested angular resolution instead of ``nperseg``: ``nperseg = ceil(2 pi/
        (resolution dt))``.

    Returns
    -------
    PSD

    Raises
    ------
    ResolutionError
        When a trajectory is shorter than the segment the resolution needs (the message
        gives the resolution the run would give).
    kbm.errors.ParameterError
        A bad step, level or array.

    Examples
    --------
    White noise of variance 1 has the flat density ``1/(pi/dt)``:

    >>> import numpy as np
    >>> x = np.random.default_rng(0).standard_normal((16, 4096))
    >>> p = ensemble_psd(x, 0.1, nperseg=256)
    >>> bool(abs(p.variance() - 1) < 0.02), bool(abs(p.mean[1:-1].mean() * np.pi / 0.1 - 1) < 0.02)
    (True, True)
    """
    x = np.asarray(x, float)
    if x.ndim == 1:
        x = x[None, :]
    if x.ndim != 2 or x.shape[1] < 2:
        raise ParameterError(f"x must have shape (n_trajectories, n_samples), got {x.shape}")
    if not np.all(np.isfinite(x)):
        raise ParameterError("x holds non-finite samples: the trajectories diverged")
    if not (isinstance(dt, (int, float, np.floating)) and math.isfinite(dt) and dt > 0):
        raise ParameterError(f"dt must be a positive number, got {dt!r}")
    if not 0 < confidence < 1:
        raise ParameterError(f"confidence must lie in (0, 1), got {confidence!r}")
    n_traj, n = x.shape
    if resolution is not None:
        if not (math.isfinite(resolution) and resolution > 0):
            raise ParameterError(f"resolution must be a positive number, got {resolution!r}")
        nperseg = math.ceil(2.0 * math.pi / (resolution * dt) - 1e-9)
    if nperseg is None:
        nperseg = max(2, n // 4)
    nperseg = int(nperseg)
    if nperseg < 2:
        raise ParameterError(f"nperseg = {nperseg}: a segment needs at least 2 samples")
    if nperseg > n:
        raise ResolutionError(
            f"the run is too short for the requested resolution "
            f"{resolution_of(nperseg, dt):.4g} (angular; {nperseg} samples per segment): "
            f"its {n} samples at dt = {dt:g} give at best {resolution_of(n, dt):.4g}; "
            f"run at least {nperseg * dt:.6g} long or ask for a coarser resolution")
    omega, p = welch_rows(x, dt, nperseg)
    return combine(omega, p, resolution_of(nperseg, dt), nperseg, confidence)


def welch_rows(x: np.ndarray, dt: float, nperseg: int) -> tuple[np.ndarray, np.ndarray]:
    """``(omega, rows)``: each row's one-sided Welch PSD per unit angular frequency (Hann,
    half overlap, segment means removed; the bins at 0 and Nyquist doubled like the others,
    so that every bin estimates the density)."""
    from scipy import signal

    f, p = signal.welch(np.atleast_2d(x), fs=1.0 / dt, window="hann", nperseg=nperseg,
                        noverlap=nperseg // 2, detrend="constant", return_onesided=True,
                        scaling="density", axis=-1)
    p = p / (2.0 * math.pi)  # per unit angular frequency
    # scipy leaves the bins at 0 and at Nyquist undoubled (Parseval's sum); doubled, every
    # bin estimates the one-sided density S(omega) and the trapezoid rule gives the variance
    p[:, 0] *= 2.0
    if nperseg % 2 == 0:
        p[:, -1] *= 2.0
    return 2.0 * math.pi * f, p


def combine(omega: np.ndarray, rows: np.ndarray, resolution: float, nperseg: int,
            confidence: float = 0.95) -> PSD:
    """The ensemble :class:`PSD` of per-trajectory estimates ``rows`` (n_trajectories x
    n_frequencies): their mean, its standard error and the Student band."""
    from scipy import stats

    rows = np.atleast_2d(np.asarray(rows, float))
    n_traj = rows.shape[0]
    mean = rows.mean(axis=0)
    if n_traj > 1:
        se = rows.std(axis=0, ddof=1) / math.sqrt(n_traj)
        q = float(stats.t.ppf(0.5 + confidence / 2.0, n_traj - 1))
    else:
        se, q = np.zeros_like(mean), 0.0
    return PSD(np.asarray(omega, float), mean, np.maximum(mean - q * se, 0.0), mean + q * se,
               se, float(resolution), n_traj, float(confidence), int(nperseg))
