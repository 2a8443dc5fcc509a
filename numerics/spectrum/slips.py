"""Phase slips of noisy coupled self-excited oscillators: Stratonovich's formula against counts.

The averaged side is :mod:`numerics.spectrum.adler` (the noisy Adler equation of the pair,
Stratonovich's net slip rate ``J`` and the mean phase ``Psi``).

**Simulated.**  An ensemble of the full system (:mod:`numerics.noise.coupled`); the phases
``theta_i = atan2(-x_i'/omega_i, x_i)`` unwrapped, ``gamma = theta_2 - theta_1``.  Every
trajectory starts at the same state, so what ``gamma`` does inside a well is the same in
all of them: it relaxes after the burn-in, and it carries a fast ripple of ``O(mu)``
(``theta_i`` is not the averaged phase) sampled at the same instants.  The change ``gamma(T)
- gamma(0)`` therefore has a bias of order ``delta gamma/T`` of one sign that the spread
over trajectories does not show (``coupled-vdp``, ``mu = 0.1``, ``c = 0.3``, ``sigma =
0.1``, ``D = 1e-5``: 2.1e-6 +- 1e-7 slips per unit time where none occur).  So the net
slips of a trajectory are the change of ``Psi(gamma)/(2 pi)``, ``Psi`` the mean phase: flat
inside a well (a bounded excursion counts zero, a slip a whole turn) and running at a
constant rate outside locking; unbiased in the stationary state because ``Psi - gamma`` is
periodic, and, for the reduced equation, from any start.  The change is between two
periodic Hann windows of :data:`WINDOW` of the run each (whole multiples of
:data:`PERIODS` periods), one after the burn-in and one at the end, which removes the
ripple's harmonics and, outside locking, averages the slips' own period at weak noise,
where all trajectories slip in step; the rate divides it by the time between the windows.
Rates and standard errors are over trajectories.  The forward and backward slips are
counted with a hysteresis of a full turn (a slip is a ``2 pi`` excursion from the last
counted level).
"""

from __future__ import annotations

import hashlib
import math
from collections.abc import Mapping

import numpy as np

from kbm.errors import ParameterError

from numerics.noise.coupled import CHUNK
from numerics.noise.validity import Z_FLAG, averaged_error, gap_z, validity_entry
from .adler import AdlerReduction, adler_reduction, mean_phase, stratonovich_rate
from .driven_sim import noisy_system

__all__ = ["simulate_slips", "slip_report", "slip_validity", "net_slips", "WINDOW", "PERIODS"]

#: the share of the run that each end's window takes (whole multiples of :data:`PERIODS`)
WINDOW = 1 / 8
#: the window's length is a multiple of this many periods of the fastest mode (64 samples
#: at the default step: the periodic Hann window then annuls the ripple's harmonics)
PERIODS = 5


def _turns(gamma: np.ndarray, phase: tuple[float, np.ndarray]) -> np.ndarray:
    """``Psi(gamma)/(2 pi)`` (``phase = (start, psi)`` of
    :func:`numerics.spectrum.adler.mean_phase`, linear between its grid points): whole
    turns from ``floor``, so values in the flat part of a well are exact integers."""
    start, psi = phase
    nodes = 2 * math.pi * np.arange(len(psi)) / (len(psi) - 1)
    y = np.asarray(gamma, dtype=float) - start
    turns = np.floor(y / (2 * math.pi))
    return turns + np.interp(y - 2 * math.pi * turns, nodes, psi) / (2 * math.pi)


def net_slips(gamma: np.ndarray, phase: tuple[float, np.ndarray], window: int) -> np.ndarray:
    """The net slips of each row of ``gamma`` (unwrapped, sampled evenly): the mean phase
    ``Psi/(2 pi)`` averaged with a periodic Hann window over the last ``window`` samples
    minus the same over the first ``window`` (the module docstring); the time between the
    two is ``columns - window`` samples."""
    gamma = np.atleast_2d(gamma)
    if not 1 <= window <= gamma.shape[1] // 2:
        raise ParameterError(f"the window of {window} samples does not fit twice in a run of "
                             f"{gamma.shape[1]}: raise --duration")
    hann = 1 - np.cos(2 * math.pi * np.arange(window) / window) if window > 1 else np.ones(1)
    hann /= hann.sum()
    ends = _turns(gamma[:, :window], phase), _turns(gamma[:, -window:], phase)
    return ends[1] @ hann - ends[0] @ hann


def _slip_task(task) -> list:
    """One chunk: per trajectory the hysteresis counts ``(forward, backward)`` and the net
    slips by the mean phase."""
    model, params, D, y0, dt, n_burn, n_run, stride, seed, first, count, phase, window = task
    system = noisy_system(model, params, D)
    rec = system.paths(np.tile(y0, (count, 1)), dt, n_burn + n_run, stride, seed=seed,
                       first=first)
    n, w = system.dof, system.omegas
    th = np.arctan2(-rec[:, :, n:n + 2] / w[None, None, :2], rec[:, :, 0:2])
    th = np.unwrap(th, axis=1)
    gam = th[:, :, 1] - th[:, :, 0]
    gam = gam[:, n_burn // stride:]
    net = net_slips(gam, phase, window)
    out = []
    for gr, k in zip(gam, net):
        fwd = bwd = 0
        ref = gr[0]
        for v in gr:  # hysteresis: a full turn from the last counted level
            while v >= ref + 2 * math.pi:
                fwd, ref = fwd + 1, ref + 2 * math.pi
            while v <= ref - 2 * math.pi:
                bwd, ref = bwd + 1, ref - 2 * math.pi
        out.append((fwd, bwd, float(k)))
    return out


def _stderr(x: np.ndarray) -> float:
    """The standard error of the mean of ``x``, scaled first (rates of 1e-170 deep in
    locking square to nothing)."""
    top = float(np.max(np.abs(x)))
    if top == 0:
        return 0.0
    return float((x / top).std(ddof=1) / math.sqrt(len(x)) * top)


def simulate_slips(model, params: Mapping[str, object], D: float, *, duration: float,
                   burn_in: float, trajectories: int = 32, seed: int = 0,
                   workers: int | None = None, store=None, progress: bool = False,
                   dt: float | None = None, shared: int = 1, order: int = 1,
                   detuning: str = "sigma", reduction: AdlerReduction | None = None) -> dict:
    """Net slips of the full noisy system (module docstring): ``{"rate", "stderr",
    "frequency", "frequency_stderr", "forward", "backward", "forward_slips",
    "backward_slips", "duration", "window", ...}``.

    ``rate`` is the mean over trajectories of the net slips by the mean phase of the reduced
    equation (``reduction``, or :func:`numerics.spectrum.adler.adler_reduction` at
    ``order``; :func:`net_slips`) per unit time between the two windows of ``duration``,
    ``frequency`` ``2 pi`` times it; ``forward`` and
    ``backward`` the hysteresis counts per unit time, ``forward_slips`` and
    ``backward_slips`` their totals; ``window`` the averaging time at each end; ``bound``
    where no turn was counted (else ``None``) the 95 % bound ``-ln(0.05)/(n T)`` on the
    net rate (Poisson: no event in ``n T``), which the spread of ``rate``, the motion
    inside the well, does not give.

    Raises
    ------
    kbm.errors.ParameterError
        For a bad time, ``D <= 0``, fewer than 2 trajectories, or a run above the step or
        memory limit (shared by ``shared`` runs of a sweep, :mod:`numerics.spectrum._cost`).
    """
    from numerics.executor import chunk, map_chunks
    from numerics.noise.budget import STEP_BUDGET
    from numerics.spectrum._cost import check_cost

    if trajectories < 2:
        raise ParameterError(f"--trajectories {trajectories}: a standard error needs at least 2")
    if not (duration > 0 and burn_in >= 0):
        raise ParameterError(f"--duration must be positive, got {duration!r}")
    params = {k: float(v) for k, v in params.items()}
    system = noisy_system(model, params, D)
    top = float(system.omegas.max())
    if dt is None:
        dt = 2 * math.pi / top / 64
    stride = max(1, int(0.5 / top / dt))  # a sample every half radian at least
    n_run = int(round(duration / dt / stride)) * stride
    n_burn = int(round(burn_in / dt / stride)) * stride
    if n_run // stride < 2:
        raise ParameterError(f"--duration {duration:g} is shorter than two samples of the "
                             f"phase ({2 * stride * dt:.3g}): raise it")
    period = 2 * math.pi / top / dt / stride  # samples per period of the fastest mode
    blocks = max(1, round(WINDOW * n_run / stride / (PERIODS * period)))
    window = max(1, min(int(round(blocks * PERIODS * period)), n_run // stride // 2))
    # a chunk of CHUNK paths is recorded whole (all 2 dof coordinates) before it is reduced
    check_cost(trajectories, n_burn + n_run, 8.0 * min(int(trajectories), CHUNK)
               * 2 * system.dof * ((n_burn + n_run) // stride + 1), budget=STEP_BUDGET / shared,
               shared=shared)
    if reduction is None:
        reduction = adler_reduction(model, params, D, order=order, detuning=detuning)
    phase = mean_phase(reduction.gamma, reduction.drift, reduction.diffusion)
    y0 = tuple([2.0] * system.dof + [0.0] * system.dof)
    groups = chunk(list(range(int(trajectories))), size=CHUNK)
    tasks = [(model, params, float(D), y0, float(dt), n_burn, n_run, stride, int(seed), g[0],
              len(g), phase, window) for g in groups]
    digest = hashlib.sha256(np.append(phase[1], phase[0]).tobytes()).hexdigest()[:16]
    definition = repr(("spectrum.slips", tasks[0][:8], int(seed), int(trajectories),
                       "mean phase", digest, window))
    rows = map_chunks(_slip_task, tasks, workers=workers, progress=progress,
                      desc="trajectories", unit="trajectory", sizes=[len(g) for g in groups],
                      store=store, definition=definition if store is not None else None)
    T = n_run * dt
    shift = (n_run // stride - window) * stride * dt  # between the windows
    rate = np.array([r[2] for r in rows]) / shift
    dg = 2 * math.pi * rate
    n = len(rows)
    fwd, bwd = sum(r[0] for r in rows), sum(r[1] for r in rows)
    # no turn counted: the net rate is below -ln(0.05)/(n T) at 95 % (Poisson, no event)
    bound = -math.log(0.05) / (n * T) if fwd == bwd == 0 else None
    return {"rate": float(rate.mean()), "stderr": _stderr(rate),
            "frequency": float(dg.mean()), "frequency_stderr": _stderr(dg),
            "forward": float(fwd / n / T), "backward": float(bwd / n / T),
            "forward_slips": int(fwd), "backward_slips": int(bwd),
            "duration": T, "burn_in": n_burn * dt, "window": window * stride * dt,
            "dt": float(dt), "trajectories": n, "seed": int(seed), "bound": bound}


def slip_report(model, params: Mapping[str, object], D: float, detunings, *, order: int = 1,
                detuning: str = "sigma", simulate: bool = True, duration: float | None = None,
                trajectories: int = 32, seed: int = 0, workers: int | None = None, store=None,
                progress: bool = False) -> list[dict]:
    """Per detuning: the averaged (Stratonovich) and simulated slip rate and frequency
    difference, ``{"detuning", "locked", "slip_rate": {averaged, simulated, stderr},
    "frequency_difference": {...}, "adler": {tilt, coupling}, ...}``.

    Each of the two also holds ``averaged_order`` and its expected error,
    ``expected_error`` and ``expected_error_source`` (the rule of
    :func:`numerics.noise.validity.averaged_error`, as ``kbm spectrum``'s line): the
    simulation's bound ``|averaged - simulated| + 2 stderr`` (``"simulation"``; ``None``
    and ``"none"`` without a simulation), at either order; where no turn was counted the
    standard error there is at least half the simulation's ``bound`` (the Poisson bound of
    :func:`simulate_slips`).  The second order's
    correction is not used as the first order's error here: the rate's error is mostly the
    reduction's (one Adler equation, amplitudes slaved, at finite ``D/mu``), which the
    next order of the averaging leaves as it is.  Measured (``coupled-vdp``, ``mu =
    0.05``, ``c = 0.3``, ``D/mu = 0.1``, 32 trajectories over 8000): ``|J_2 - J_1|`` is
    5.4e-5 and 2.8e-5 at ``sigma`` = 0.45 and 0.3, the simulated first-order gap (1.4 +-
    0.4)e-4 and (1.3 +- 0.4)e-4, three to five times more.

    The default duration is ``400/mu`` after a burn-in of ``20/mu``."""
    detunings = list(detunings)
    out = []
    for s in detunings:
        p = {**dict(params), detuning: float(s)}
        red = adler_reduction(model, p, D, order=order, detuning=detuning)
        J = stratonovich_rate(red.gamma, red.drift, red.diffusion)
        row = {"detuning": float(s), "locked": red.locked,
               "adler": {"tilt": red.tilt, "coupling": red.coupling,
                         "diffusion_mean": float(red.diffusion.mean())},
               "slip_rate": {"averaged": J, "simulated": None, "stderr": None,
                             "averaged_order": order},
               "frequency_difference": {"averaged": 2 * math.pi * J, "simulated": None,
                                        "stderr": None, "averaged_order": order}}
        if simulate:
            mu = float(p.get("mu", 0) or 0)
            if not mu > 0:
                raise ParameterError("the slip rate needs mu > 0 (-p mu=VALUE)")
            T = duration if duration is not None else 400 / mu
            sim = simulate_slips(model, p, D, duration=T, burn_in=20 / mu,
                                 trajectories=trajectories, seed=seed, workers=workers,
                                 store=store, progress=progress, shared=len(detunings),
                                 reduction=red)
            row["slip_rate"].update(simulated=sim["rate"], stderr=sim["stderr"])
            row["frequency_difference"].update(simulated=sim["frequency"],
                                               stderr=sim["frequency_stderr"])
            row["simulation"] = {k: sim[k] for k in (
                "forward", "backward", "duration", "burn_in", "dt", "trajectories", "seed",
                "forward_slips", "backward_slips", "window", "bound")}
        bound = row.get("simulation", {}).get("bound")
        for entry, unit in ((row["slip_rate"], 1.0), (row["frequency_difference"], 2 * math.pi)):
            moment = dict(entry)
            if bound is not None:  # no turn counted: the spread is the motion in the well
                moment["stderr"] = max(entry["stderr"], unit * bound / 2)
            entry["expected_error"], entry["expected_error_source"] = averaged_error(moment)
        if simulate:
            row["validity"] = slip_validity(row, mu=float(p["mu"]), detuning=detuning)
        out.append(row)
    return out


def slip_validity(row: Mapping, mu: float | None = None, detuning: str = "sigma") -> dict:
    """The gap ``(averaged - simulated)/stderr`` of one detuning's slip rate and the flag
    ``|z| > 4`` (:func:`numerics.noise.validity.gap_z`, as ``kbm noise`` and the line of
    ``kbm spectrum``), with what to do: ``{"z", "flagged", "threshold", "advice"}``.

    No gap where no turn was counted (``simulation.bound`` set: the spread is then the
    phase's motion in its well, not the slips' statistics).  The frequency difference is
    ``2 pi`` times the rate, the same gap.  The advice names ``--order 2`` at order 1: the
    second order moves Stratonovich's rate by ``O(mu)`` (``coupled-vdp``, ``mu = 0.1``,
    ``c = 0.3``, ``D = 1e-5``, ``sigma = 0.45``: the gap +118 standard errors at order 1,
    -26 at order 2; at ``mu = 0.02`` +3.2 at order 1), and the reduction to one Adler
    equation (amplitudes slaved) that neither order removes.
    """
    rate = row["slip_rate"]
    counted = row.get("simulation", {}).get("bound") is None
    z, bad = gap_z({"slip_rate": rate if counted else {**rate, "simulated": None}})

    def advise() -> str:
        order = rate["averaged_order"]
        at = "" if mu is None else f" at mu = {mu:g}"
        remedy = ("use --order 2 (second-order averaging) or a smaller mu" if order == 1
                  else "a smaller mu")
        return (f"the averaged slip rate is {z['slip_rate']:+.1f} standard errors from the "
                f"counted one (|z| > {Z_FLAG:g}) at {detuning} = {row['detuning']:g}: the "
                f"{'first' if order == 1 else 'second'}-order averaging and the reduction to "
                f"one Adler equation are not accurate enough{at}; {remedy}; a gap near "
                f"{Z_FLAG:g} may be the statistics: a longer --duration or more "
                "--trajectories shrink the standard error")
    return validity_entry(z["slip_rate"], bad, advise)
