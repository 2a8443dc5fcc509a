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
from dataclasses import dataclass, field

import numpy as np

from kbm.errors import ParameterError

from ..errors import NumericsError

__all__ = ["PSD", "ensemble_psd", "ResolutionError", "resolution_of", "welch_rows", "combine",
           "bin_means"]


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
    rows : numpy.ndarray or None
        The per-trajectory estimates (trajectories x frequencies) the mean is taken over:
        independent samples for statistics over bins (:func:`bin_means`).
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
    rows: np.ndarray | None = field(default=None, repr=False)

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
               se, float(resolution), n_traj, float(confidence), int(nperseg), rows)


def bin_means(rows: np.ndarray, reference: np.ndarray) -> dict:
    """Means over frequency bins of an ensemble's departure from a reference spectrum, with
    standard errors that hold the correlation of the bins.

    Neighbouring bins of a Welch estimate are not independent: with a Hann window the
    estimates one bin apart correlate by ``|sum h_t^2 e^{2 pi i t/N}|^2 / (sum h_t^2)^2 =
    4/9``, two bins apart by ``1/36`` (Percival and Walden, *Spectral Analysis for Physical
    Applications*, 1993, sec. 6.6 and 7.1, for a locally flat spectrum), so a mean over
    ``n`` bins has about ``1 + 2 (4/9 + 1/36) = 1.94`` times the variance of ``n``
    independent ones, and more where the process is not Gaussian (a nonlinear
    oscillator's trajectory carries its total power into every bin: a weak long-range
    correlation).  Rather than model this, the standard errors are measured from the
    independent trajectories: each trajectory ``j`` gives one mean over the bins, and the
    ensemble's mean of those is the statistic, so their spread over ``sqrt(N)`` is its
    standard error with every correlation between bins in it.

    Parameters
    ----------
    rows : numpy.ndarray, shape (N, n)
        Per-trajectory estimates at ``n`` bins (:attr:`PSD.rows`, restricted to the bins).
    reference : numpy.ndarray, shape (n,)
        The spectrum compared with (e.g. the Floquet route's).

    Returns
    -------
    dict
        ``relative``: the mean over bins and trajectories of ``rows/reference - 1`` and
        ``relative_stderr``, ``sd_j(d_j)/sqrt(N)`` of the trajectories' means ``d_j`` over
        bins (Student's ``t`` with ``dof = N - 1`` under the null: ``d_j`` averages ``n``
        bins and is close to Gaussian); ``mean_z``: the mean over bins of ``z_k =
        (reference_k - mean_k)/stderr_k`` and ``mean_z_stderr``,
        ``sqrt((N - 1)/(N - 3)) sd_j(m_j)/sqrt(N)`` with ``m_j`` the mean over bins of
        ``(reference_k - rows_jk)/stderr_k`` (``mean_z`` is the mean of the ``m_j``; the
        factor is the variance of Student's ``t`` with ``N - 1`` degrees of freedom, the
        law of each ``z_k``).  ``mean_z`` leans by about ``+gamma/(2 sqrt N)`` (``gamma``
        the skewness of one trajectory's estimate; the studentised mean, Hall, Ann. Stat.
        15 (1987) 1491) and its standard error carries the noise of the per-bin standard
        errors: ``relative`` is the sharper test.

    Raises
    ------
    kbm.errors.ParameterError
        Fewer than 4 trajectories, or shapes that do not match.
    """
    rows = np.atleast_2d(np.asarray(rows, float))
    ref = np.asarray(reference, float)
    N = rows.shape[0]
    if N < 4 or rows.shape[1:] != ref.shape:
        raise ParameterError(f"bin_means needs >= 4 trajectories of {ref.shape} bins, got rows "
                             f"{rows.shape}")
    d = (rows / ref).mean(axis=1) - 1.0
    se = rows.std(axis=0, ddof=1) / math.sqrt(N)
    m = ((ref - rows) / se).mean(axis=1)
    return {"relative": float(d.mean()), "relative_stderr": float(d.std(ddof=1) / math.sqrt(N)),
            "mean_z": float(m.mean()),
            "mean_z_stderr": float(math.sqrt((N - 1) / (N - 3)) * m.std(ddof=1) / math.sqrt(N)),
            "dof": N - 1}
