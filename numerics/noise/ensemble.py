"""Stationary ensembles of Langevin trajectories on the executor, with standard errors.

Each trajectory starts at ``y0``, runs ``burn_in`` to forget it, then ``t_end`` more,
over which the time averages of ``x^2``, ``a^2 = x^2 + (x'/omega0)^2``, ``x'^2`` and the
spring force are taken, and a histogram of one observable (the amplitude ``a``, ``x``
or the energy ``E = x'^2/2 + G(x)``), with four-point Gauss-Hermite increments (their
moments the Gaussian's up to the seventh: the ``h^2`` coefficient of the bias is the one the
step pilot :func:`numerics.noise._pilot.measured_step` measures with Gaussian increments;
kernel ``stationary_stats4`` of :mod:`numerics.noise._pair_kernels`).  The estimate is the
mean over trajectories;
its standard error is their standard deviation over ``sqrt(N)`` (the trajectories
are independent, so this is valid whatever the correlation time within one).

Trajectory ``i`` has its own seed (:mod:`numerics.noise.seeds`) and the results are
summed in trajectory order, so the numbers are the same to the bit on any executor,
worker count and chunking (a test checks it).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from kbm.errors import ParameterError

from ..errors import NumericsError
from ..executor import chunk, map_chunks
from .langevin import LangevinSystem, langevin_system, steps_of
from .seeds import check_seed, trajectory_states

__all__ = ["Estimate", "StationaryEnsemble", "stationary_ensemble", "MIN_TRAJECTORIES",
           "OBSERVABLES"]

#: fewer trajectories give no meaningful standard error
MIN_TRAJECTORIES = 8

#: the histogrammed observables and their kernel codes
OBSERVABLES = {"a": 0, "x": 1, "E": 2}

#: the largest per-trajectory moment whose standard error is formed (its square, ~1e300,
#: stays below double precision's 1.8e308)
HUGE_MOMENT = 1e150


@dataclass(frozen=True)
class Estimate:
    """A Monte Carlo mean and its standard error."""

    value: float
    stderr: float

    def __repr__(self) -> str:
        return f"{self.value:.6g} +- {self.stderr:.2g}"

    @classmethod
    def of(cls, samples) -> "Estimate":
        s = np.asarray(samples, float)
        return cls(float(np.mean(s)), float(np.std(s, ddof=1) / math.sqrt(s.size)))


@dataclass(frozen=True, eq=False)
class StationaryEnsemble:
    """Time- and ensemble-averaged stationary statistics of a noisy model.

    Attributes
    ----------
    system : LangevinSystem
    trajectories : int
    t_end, burn_in, dt : float
        Averaging time per trajectory (after the burn-in) and time step.
    seed : int
    x2, a2, v2, force : Estimate
        ``<x^2>``, ``<x^2 + (x'/omega0)^2>``, ``<x'^2>`` and the mean spring force.
    variable : str
        The histogrammed observable (``"a"``, ``"x"`` or ``"E"``).
    edges : numpy.ndarray
        Bin edges.
    density, density_stderr : numpy.ndarray
        The probability density per bin and its standard error.
    outside : float
        Fraction of the samples outside the bins.
    """

    system: LangevinSystem
    trajectories: int
    t_end: float
    burn_in: float
    dt: float
    seed: int
    x2: Estimate
    a2: Estimate
    v2: Estimate
    force: Estimate
    variable: str
    edges: np.ndarray
    density: np.ndarray
    density_stderr: np.ndarray
    outside: float

    def __repr__(self) -> str:
        return (f"StationaryEnsemble({self.system.bound.name}, D={self.system.D:g}: "
                f"<x^2> = {self.x2!r}, <a^2> = {self.a2!r}; {self.trajectories} trajectories "
                f"x t = {self.t_end:g} after {self.burn_in:g}, dt = {self.dt:g}, "
                f"seed {self.seed})")

    @property
    def centres(self) -> np.ndarray:
        """The bins' centres."""
        return 0.5 * (self.edges[1:] + self.edges[:-1])


def _stats_task(task) -> list:
    """One chunk of trajectories (module level: it runs in worker processes)."""
    (model, params, D, first, count, y0, dt, n_burn, n_run, seed, kind, lo, hi, nbins,
     scheme) = task
    system = langevin_system(model, params, D, scheme)
    states = trajectory_states(seed, first, count)
    y = np.ascontiguousarray(np.tile(np.asarray(y0, float), (count, 1)))
    # four-point increments: the h^2 coefficient of the step pilot's Gaussian pair
    sums, hist = system.kernels.stationary_stats4(
        system._p(), system.sigma, y, 0.0, dt, n_burn, n_run, states, system.omega0, kind,
        lo, hi, nbins)
    return [(tuple(map(float, sums[i])), hist[i].tolist()) for i in range(count)]


def stationary_ensemble(model, params: dict, D: float, *, trajectories: int, t_end: float,
                        burn_in: float, dt: float, seed: int = 0, variable: str = "a",
                        bins: tuple[float, float, int] = (0.0, 4.0, 40), y0=(0.0, 0.0),
                        executor=None, workers: int | None = None, progress: bool = False,
                        store=None, scheme: str = "kp") -> StationaryEnsemble:
    """Stationary moments and the density of one observable, with standard errors.

    Parameters
    ----------
    model : str or kbm.model.builtins.Oscillator
    params : dict
        Parameter values (``mu`` included, ``D`` apart).
    D : float
        Noise intensity of ``sqrt(2 D) xi``.
    trajectories : int
        Independent trajectories (at least :data:`MIN_TRAJECTORIES`).
    t_end, burn_in, dt : float
        Averaging time per trajectory, the time discarded before it, the step; both
        times whole numbers of steps.
    seed : int
        Root seed (one spawned ``SeedSequence`` per trajectory).
    variable : {"a", "x", "E"}
        The observable whose density is estimated.
    bins : (lo, hi, n)
        ``n`` equal bins on ``[lo, hi)``.
    y0 : (x, x')
        Start of every trajectory.
    executor, workers, progress, store :
        As :func:`numerics.executor.map_chunks` (``store`` keeps finished chunks for a
        resumed run).
    scheme : {"kp", "baoab", "auto"}
        The integrator (:func:`numerics.noise.langevin.langevin_system`).

    Raises
    ------
    kbm.errors.ParameterError
        Too few trajectories, a bad time or bin range, an unknown observable.
    numerics.errors.NumericsError
        When trajectories diverge (with how many and the first one's index).
    """
    if not isinstance(trajectories, (int, np.integer)) or trajectories < MIN_TRAJECTORIES:
        raise ParameterError(f"trajectories = {trajectories!r}: at least {MIN_TRAJECTORIES} "
                             "are needed for a meaningful standard error")
    if variable not in OBSERVABLES:
        raise ParameterError(f"variable must be one of {', '.join(OBSERVABLES)}, got "
                             f"{variable!r}")
    lo, hi, nbins = float(bins[0]), float(bins[1]), int(bins[2])
    if not (math.isfinite(lo) and math.isfinite(hi) and hi > lo and nbins >= 1):
        raise ParameterError(f"bins = {bins!r}: need lo < hi (finite) and at least one bin")
    seed = check_seed(seed)
    system = langevin_system(model, params, D, scheme)  # validates before any work starts
    n_run = steps_of(t_end, dt)
    n_burn = 0 if burn_in == 0 else steps_of(burn_in, dt)
    if variable == "E" and not math.isfinite(system.kernels.energy(0.0, 0.0, system._p())):
        raise ParameterError(f"model {system.bound.name!r} has no closed-form potential: "
                             "its energy cannot be histogrammed; use variable 'x' or 'a'")
    groups = chunk(list(range(int(trajectories))))
    tasks = [(model, dict(params), float(D), g[0], len(g), tuple(map(float, y0)), float(dt),
              n_burn, n_run, seed, OBSERVABLES[variable], lo, hi, nbins, system.scheme)
             for g in groups]
    definition = repr(("stationary_ensemble", _describe(model), sorted(map(str, params.items())),
                       float(D), int(trajectories), n_run, n_burn, float(dt), seed, variable,
                       lo, hi, nbins, tuple(map(float, y0)))
                      + (() if system.scheme == "kp" else (system.scheme,))
                      + ("four-point increments",))
    rows = map_chunks(_stats_task, tasks, executor=executor, workers=workers,
                      progress=progress, desc="trajectories", unit="trajectory",
                      sizes=[len(g) for g in groups], store=store,
                      definition=definition if store is not None else None)
    sums = np.array([r[0] for r in rows])
    hist = np.array([r[1] for r in rows])
    bad = np.nonzero(~np.isfinite(sums[:, 0]))[0]
    if bad.size:
        raise NumericsError(f"{bad.size} of {trajectories} trajectories diverged (the first is "
                            f"trajectory {bad[0]}): the state became non-finite; with this "
                            f"noise the model has no stationary state, or dt = {dt:g} is too "
                            "large")
    top = float(np.max(np.abs(sums[:, :4])))
    if top > HUGE_MOMENT:  # the standard errors square them: inf and a RuntimeWarning
        raise NumericsError(f"the ensemble's moments reach {top:.3g}, beyond the {HUGE_MOMENT:g} "
                            "whose spread double precision can hold (their squares overflow): "
                            "the noise is too strong for a meaningful stationary state in "
                            "floating point; lower D")
    width = (hi - lo) / nbins
    dens = hist / width
    return StationaryEnsemble(
        system, int(trajectories), float(t_end), float(burn_in), float(dt), seed,
        Estimate.of(sums[:, 0]), Estimate.of(sums[:, 1]), Estimate.of(sums[:, 2]),
        Estimate.of(sums[:, 3]), variable, np.linspace(lo, hi, nbins + 1),
        dens.mean(axis=0), dens.std(axis=0, ddof=1) / math.sqrt(len(rows)),
        float(1.0 - hist.sum(axis=1).mean()))


def _describe(model) -> str:
    return model if isinstance(model, str) else f"{model.name}: {model.F}; {model.omega0}"
