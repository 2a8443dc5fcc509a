"""Ensembles of the full Langevin equation recording x(t), on the executor.

Trajectory ``i`` starts on the averaged cycle (``x = a*``, ``x' = 0``), runs ``burn_in``,
then ``duration`` more, sampled every ``sample`` (a whole number of steps ``dt``), with
its own seed (``SeedSequence(seed, spawn_key=(i,))``, :mod:`numerics.noise.seeds`).  Each
trajectory is reduced where it runs, to its Welch PSD in a window of frequencies
(:func:`numerics.spectrum.psd.welch_rows`), its mean angular frequency and the sums of its
phase increments at the lags (:mod:`numerics.spectrum.linewidth`); the reductions are
combined in trajectory order, so a run gives the same bytes on any executor, worker count
and chunking, and ``store`` keeps finished chunks for a resumed run.

The scheme is Kloeden-Platen's weak order-2 scheme (:mod:`numerics.noise.langevin`),
whose deterministic part (Heun) turns a rotation ``omega h`` per step into ``omega h (1 +
(omega h)^2/6)``: the frequency is biased by ``omega (omega h)^2/6``, reported as
``step_bias`` (4e-5 at the default 400 steps per period).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from kbm.errors import ParameterError

from ..errors import NumericsError
from ..executor import chunk, map_chunks
from ..noise.ensemble import MIN_TRAJECTORIES, Estimate
from ..noise.langevin import langevin_system
from ..noise.seeds import check_seed, trajectory_states
from ..noise.budget import STEP_BUDGET
from ._cost import check_cost
from .linewidth import increment_sums, phase_growth, unwrapped_phase
from .psd import PSD, ResolutionError, combine, resolution_of, welch_rows

__all__ = ["SimulatedLine", "simulate_line", "STEPS_PER_PERIOD"]

#: the default step: this many per linear period
STEPS_PER_PERIOD = 400


@dataclass(frozen=True, eq=False)
class SimulatedLine:
    """The simulated spectrum, frequency and phase diffusion of an ensemble.

    Attributes
    ----------
    psd : PSD
        The ensemble PSD in the window of frequencies.
    frequency, linewidth : Estimate
        Mean angular frequency and ``D_eff`` (half the growth rate of the phase variance).
    taus, m2, m2_stderr : numpy.ndarray
        The lags and the mean squared phase increments about ``Omega tau``.
    trajectories : int
    duration, burn_in, dt, sample : float
    seed : int
    step_bias : float
        ``omega0 (omega0 dt)^2/6``: the scheme's frequency bias.
    """

    psd: PSD
    frequency: Estimate
    linewidth: Estimate
    taus: np.ndarray
    m2: np.ndarray
    m2_stderr: np.ndarray
    trajectories: int
    duration: float
    burn_in: float
    dt: float
    sample: float
    seed: int
    step_bias: float

    def __repr__(self) -> str:
        return (f"SimulatedLine(Omega = {self.frequency!r}, HWHM = {self.linewidth!r}; "
                f"{self.trajectories} trajectories x {self.duration:g}, dt = {self.dt:g})")


def _task(task) -> list:
    """One chunk of trajectories (module level: it runs in worker processes)."""
    (model, params, D, first, count, y0, dt, n_burn, n_run, stride, seed, nperseg, lo, hi,
     lags) = task
    system = langevin_system(model, params, D)
    states = trajectory_states(seed, first, count)
    out = []
    for j in range(count):
        y = system.kernels.sample_path(system._p(), system.sigma, np.asarray(y0, float), 0.0,
                                       dt, n_burn + n_run, stride, states[j])
        y = y[n_burn // stride:]
        if not np.all(np.isfinite(y)):
            out.append(None)
            continue
        psi = unwrapped_phase(y[:, 0], y[:, 1], system.omega0)
        _, p = welch_rows(y[:, 0], dt * stride, nperseg)
        out.append((float(psi[-1] - psi[0]), p[0, lo:hi].tolist(),
                    increment_sums(psi, np.asarray(lags)).tolist()))
    return out


def simulate_line(model, params: dict, D: float, *, trajectories: int, duration: float,
                  burn_in: float, window: tuple[float, float], resolution: float,
                  tau_min: float, amplitude: float, dt: float | None = None,
                  sample: float | None = None, seed: int = 0, workers: int | None = None,
                  executor=None, store=None, progress: bool = False,
                  confidence: float = 0.95, shared: int = 1) -> SimulatedLine:
    """Simulate the ensemble and measure its line.

    Parameters
    ----------
    model : str or kbm.model.builtins.Oscillator
    params : dict
        ``mu`` and the model's parameters.
    D : float
        Noise intensity (``> 0``).
    trajectories : int
        At least :data:`numerics.noise.ensemble.MIN_TRAJECTORIES`.
    duration, burn_in : float
        Recorded time per trajectory and the time discarded before it.
    window : (lo, hi)
        Angular frequencies kept of the PSD.
    resolution : float
        Requested angular resolution of the PSD (one Welch segment ``2 pi/resolution``).
    tau_min : float
        The shortest lag of the phase-variance fit (several ``1/lambda``); the longest is
        ``duration/8``.
    amplitude : float
        Start ``x = amplitude``, ``x' = 0``.
    dt, sample : float, optional
        Step (default ``2 pi/(400 omega0)``) and sample interval (default ``2 pi/(8 hi)``
        with ``hi`` the window's top frequency, rounded down to whole steps: Nyquist at
        four times the window's top).
    seed, workers, executor, store, progress :
        As :func:`numerics.noise.ensemble.stationary_ensemble`.
    shared : int
        Runs of a sweep the step limit is shared by (:func:`numerics.spectrum._cost.check_cost`).

    Raises
    ------
    numerics.spectrum.psd.ResolutionError
        ``duration`` shorter than one segment of the requested resolution.
    kbm.errors.ParameterError
        Too few trajectories, a bad time, a run above the step or memory limit.
    numerics.errors.NumericsError
        Diverged trajectories.
    """
    if not isinstance(trajectories, (int, np.integer)) or trajectories < MIN_TRAJECTORIES:
        raise ParameterError(f"trajectories = {trajectories!r}: at least {MIN_TRAJECTORIES} "
                             "are needed for a meaningful standard error")
    for name, val in (("duration", duration), ("resolution", resolution)):
        if not (isinstance(val, (int, float)) and math.isfinite(val) and val > 0):
            raise ParameterError(f"{name} must be a positive number, got {val!r}")
    seed = check_seed(seed)
    system = langevin_system(model, params, D)
    w0 = system.omega0
    if dt is None:
        dt = 2 * math.pi / (w0 * STEPS_PER_PERIOD)
    if sample is None:
        sample = 2 * math.pi / (8.0 * max(window[1], w0))  # Nyquist: 4 x the window's top
    stride = max(1, int(sample / dt))
    sample = stride * dt
    n_run = int(round(duration / sample)) * stride
    n_burn = int(math.ceil(burn_in / sample)) * stride if burn_in > 0 else 0
    samples = n_run // stride + 1
    # a trajectory's path (burn-in included) is recorded whole before it is reduced
    check_cost(trajectories, n_burn + n_run, 16.0 * ((n_burn + n_run) // stride + 1),
               budget=STEP_BUDGET / shared, shared=shared)
    nperseg = int(math.ceil(2 * math.pi / (resolution * sample) - 1e-9))
    if nperseg > samples:
        raise ResolutionError(
            f"--duration {duration:g} is too short for the resolution {resolution:.4g} "
            f"(angular) the line needs: it gives {resolution_of(samples, sample):.4g}; "
            f"run at least {nperseg * sample:.6g} long")
    omega = 2 * math.pi * np.fft.rfftfreq(nperseg, sample)
    lo = int(np.searchsorted(omega, window[0]))
    hi = int(np.searchsorted(omega, window[1], side="right"))
    t_max = (samples - 1) * sample / 8
    if tau_min >= t_max:
        raise ResolutionError(
            f"--duration {duration:g} is too short for the phase-variance growth: its lags "
            f"must run from {tau_min:.4g} (several amplitude relaxation times) to "
            f"duration/8; run at least {8 * 2 * tau_min:.6g} long")
    lags = np.unique(np.round(np.geomspace(tau_min, t_max, 12) / sample).astype(int))
    groups = chunk(list(range(int(trajectories))))
    y0 = (float(amplitude), 0.0)
    tasks = [(model, dict(params), float(D), g[0], len(g), y0, float(dt), n_burn, n_run,
              stride, seed, nperseg, lo, hi, lags.tolist()) for g in groups]
    definition = repr(("spectrum_line", _describe(model), sorted(map(str, params.items())),
                       float(D), int(trajectories), float(dt), n_burn, n_run, stride, seed,
                       nperseg, lo, hi, lags.tolist(), y0))
    rows = map_chunks(_task, tasks, executor=executor, workers=workers, progress=progress,
                      desc="trajectories", unit="trajectory", sizes=[len(g) for g in groups],
                      store=store, definition=definition if store is not None else None)
    bad = [i for i, r in enumerate(rows) if r is None]
    if bad:
        raise NumericsError(f"{len(bad)} of {trajectories} trajectories diverged (the first is "
                            f"trajectory {bad[0]}): with this noise the model has no "
                            f"stationary cycle, or dt = {dt:g} is too large")
    T = n_run * dt
    freqs = np.array([r[0] for r in rows]) / T
    psd = combine(omega[lo:hi], np.array([r[1] for r in rows]), resolution_of(nperseg, sample),
                  nperseg, confidence)
    sums = np.array([r[2] for r in rows])
    f_est = Estimate.of(freqs)
    taus = lags * sample
    lw, m2, m2_se = phase_growth(sums, taus, f_est.value)
    return SimulatedLine(psd, f_est, lw, taus, m2, m2_se, int(trajectories), float(T),
                         float(n_burn * dt), float(dt), float(sample), seed,
                         float(w0 * (w0 * dt) ** 2 / 6))


def _describe(model) -> str:
    return model if isinstance(model, str) else f"{model.name}: {model.F}; {model.omega0}"
