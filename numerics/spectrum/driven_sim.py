"""Simulated noise spectra about driven steady states, and the report of ``kbm spectrum``.

An ensemble of the full SDE (:meth:`numerics.noise.coupled.NoisySystem.paths`: stochastic
Heun, one stream per trajectory, chunks of fixed size on the executor of
:func:`numerics.executor.map_chunks` with ``store``/``resume``) is started on the true
periodic response; a noise-free lane run by the same scheme is subtracted, so the record
is the fluctuation ``x - x_p`` (the coherent line removed to the scheme's accuracy).  After
a burn-in its PSD is :func:`numerics.spectrum.psd.ensemble_psd` with its Student band, and
the averaged and Floquet spectra of :mod:`numerics.spectrum.driven` are evaluated on the
same bins.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from kbm.errors import ParameterError
from kbm.output.strict_json import complex_pairs, jsonable
from kbm.parameters.names import noise_intensity

from numerics.errors import ConvergenceError
from numerics.noise.coupled import CHUNK, NOISE_NEED, NoisySystem, bound_system
from .driven import (AveragedFlow, Orbit, SteadyState, averaged_flow, averaged_spectrum,
                     detuning_name, floquet_spectrum, periodic_orbit, stable_states)

__all__ = ["ResponseSpectrum", "response_spectra", "simulate_fluctuations", "coherent_part",
           "noisy_system", "STEPS_PER_PERIOD", "RESOLUTION", "MIN_SEGMENTS"]

_SYSTEMS: dict = {}


def noisy_system(model, params: Mapping[str, object], D: float) -> NoisySystem:
    """The noisy system of ``model`` at ``params`` (bound by
    :func:`numerics.flow.coupled_flow.bind_coupled`; :func:`numerics.noise.coupled.bound_system`).

    Raises
    ------
    kbm.errors.ParameterError
        For an unknown name or a missing value, ``D <= 0``, or a model whose force depends
        on ``t`` other than through ``theta`` (a pulled slider).
    """
    from numerics.flow.coupled_flow import bind_coupled

    noise_intensity(D, NOISE_NEED)
    return bound_system(*bind_coupled(model, params), D)


def _cached_system(model, params, D):
    key = (repr(model), tuple(sorted(params.items())), D)
    if key not in _SYSTEMS:
        _SYSTEMS.clear()
        _SYSTEMS[key] = noisy_system(model, params, D)
    return _SYSTEMS[key]


def _fluct_task(task) -> list:
    """One chunk of trajectories: ``x_mode - x_p`` sampled after the burn-in."""
    model, params, D, y0, dt, n_burn, n_samples, stride, mode, seed, first, count = task
    system = _cached_system(model, params, D)
    rec = system.paths(np.tile(y0, (count, 1)), dt, n_burn + n_samples * stride, stride,
                       seed=seed, first=first, quiet_lane=True)
    skip = n_burn // stride
    x = rec[:, skip:skip + n_samples, mode]
    return [row for row in x[:count] - x[count]]


def simulate_fluctuations(model, params: Mapping[str, object], D: float, y0, *, dt: float,
                          burn_in_steps: int, samples: int, stride: int, mode: int = 0,
                          trajectories: int = 32, seed: int = 0, workers: int | None = None,
                          store=None, progress: bool = False, shared: int = 1) -> np.ndarray:
    """``x_mode(t) - x_p(t)`` of ``trajectories`` paths of the full SDE started at ``y0``
    (``trajectories x samples``, sampled every ``stride`` steps after ``burn_in_steps``).

    ``x_p`` is the noise-free lane of the same scheme, so the coherent response is removed
    to the scheme's accuracy; the chunks (:data:`numerics.noise.coupled.CHUNK` paths) and
    the seeds make the array the same on any executor and worker count.  A run above the
    step or memory limit, shared by ``shared`` runs of a sweep, is refused
    (:func:`numerics.spectrum._cost.check_cost`: the array of ``trajectories x samples``)."""
    from numerics.executor import chunk, map_chunks
    from numerics.noise.budget import STEP_BUDGET
    from numerics.spectrum._cost import check_cost

    steps = int(burn_in_steps) + int(samples) * int(stride)
    check_cost(trajectories, steps, 8.0 * int(trajectories) * int(samples),
               budget=STEP_BUDGET / shared, shared=shared)

    params = {k: float(v) for k, v in params.items()}
    idx = list(range(int(trajectories)))
    groups = chunk(idx, size=CHUNK)
    y0 = tuple(float(v) for v in y0)
    tasks = [(model, params, float(D), y0, float(dt), int(burn_in_steps), int(samples),
              int(stride), int(mode), int(seed), g[0], len(g)) for g in groups]
    definition = repr(("spectrum.driven", tasks[0][:9], int(seed), int(trajectories)))
    rows = map_chunks(_fluct_task, tasks, workers=workers, progress=progress,
                      desc="trajectories", unit="trajectory", sizes=[len(g) for g in groups],
                      store=store, definition=definition if store is not None else None)
    return np.array(rows)


@dataclass
class ResponseSpectrum:
    """The spectra about one stable state at one detuning (``to_json`` for the command)."""

    detuning: float
    state: SteadyState
    orbit: Orbit | None
    Omega: float
    omega: np.ndarray
    averaged: np.ndarray
    floquet: np.ndarray | None
    simulated: np.ndarray | None = None
    lower: np.ndarray | None = None
    upper: np.ndarray | None = None
    stderr: np.ndarray | None = None
    extra: dict = field(default_factory=dict)
    #: the per-trajectory Welch estimates at ``omega`` (trajectories x bins; not in the
    #: JSON): the independent samples of :func:`numerics.spectrum.psd.bin_means`
    rows: np.ndarray | None = field(default=None, repr=False)

    def decay_rate(self) -> float:
        """The slowest relaxation rate about the state: ``-max Re`` of the Floquet exponents
        ``log(rho)/T`` (or of the averaged eigenvalues when the orbit is missing)."""
        if self.orbit is not None:
            return float(-np.max(np.log(np.abs(self.orbit.multipliers))) / self.orbit.period)
        return float(-np.max(self.state.eigenvalues.real))

    def sidebands(self) -> dict:
        """The averaged sidebands ``Omega + Im(lambda)`` and the spectrum's values there (their
        ratio is the asymmetry)."""
        lam = self.state.eigenvalues
        return {"frequencies": [float(self.Omega + e.imag) for e in lam],
                "decay_rates": [float(-e.real) for e in lam]}

    def validity(self) -> dict | None:
        """The root-mean-square gap ``(theory - simulated)/stderr`` over the bins of the
        averaged spectrum (first order in mu and in D) and of the Floquet spectrum (the
        exact linearisation about the true response, first order in D), and the flag
        ``rms |z| > 4`` of the averaged one (issue 36: validity in every output; the
        threshold of :data:`numerics.noise.validity.Z_FLAG`), with what to do:
        ``{"z_rms": {"averaged", "floquet"}, "flagged", "threshold", "advice"}``; ``None``
        without a simulation.  (duffing-forced, mu = 0.05, zeta = 0.1, alpha = 1, h = 0.5,
        sigma = 1, D = 1e-4, 32 trajectories: the averaged spectra 4.1 and 8.2 rms about
        the two stable states, the Floquet spectra 1.5 and 1.8.)"""
        from numerics.noise.validity import Z_FLAG, validity_entry

        if self.simulated is None or self.stderr is None:
            return None
        ok = self.stderr > 0

        def rms(theory):
            if theory is None or not np.any(ok):
                return None
            z = (theory[ok] - self.simulated[ok]) / self.stderr[ok]
            return float(np.sqrt(np.mean(z**2)))

        z = {"averaged": rms(self.averaged), "floquet": rms(self.floquet)}
        bad = z["averaged"] is not None and z["averaged"] > Z_FLAG

        def advise() -> str:
            advice = (f"the averaged spectrum about the state of amplitude "
                      f"{self.state.amplitudes()[0]:.4g} at the detuning {self.detuning:g} is "
                      f"{z['averaged']:.1f} standard errors (rms over the bins) from the "
                      f"simulated one (> {Z_FLAG:g}): first-order averaging is not accurate "
                      "enough here (mu too large)")
            if z["floquet"] is None:
                advice += "; a smaller mu"
            elif z["floquet"] <= Z_FLAG:
                advice += (f"; the Floquet spectrum (exact linearisation about the true "
                           f"response) is {z['floquet']:.1f}: use it (the JSON's floquet)")
            else:
                advice += (f"; the Floquet spectrum, exact in mu, is {z['floquet']:.1f} too: "
                           "D is too large for the linear noise theory (a smaller D), or "
                           "the statistics (more --trajectories, a longer --duration)")
            return advice
        return validity_entry(z, bad, advise, key="z_rms")

    def to_json(self) -> dict:
        """The state, the spectra at ``omega``, :attr:`extra` (NaN as ``None``) and
        :meth:`validity`; the eigenvalues and multipliers as ``[re, im]``."""
        st = self.state
        return jsonable({
            "detuning": self.detuning, "state": {"amplitudes": st.amplitudes(), "U": st.U,
                                                 "eigenvalues": complex_pairs(st.eigenvalues)},
            "response_frequency": self.Omega,
            "multipliers": None if self.orbit is None else complex_pairs(self.orbit.multipliers),
            "decay_rate": self.decay_rate(), "sidebands": self.sidebands(), "omega": self.omega,
            "averaged": self.averaged, "floquet": self.floquet, "simulated": self.simulated,
            "lower": self.lower, "upper": self.upper, "stderr": self.stderr, **self.extra,
            "validity": self.validity()})


@dataclass(frozen=True)
class _Case:
    detuning: float
    params: dict
    system: NoisySystem
    flow: AveragedFlow
    state: SteadyState
    orbit: Orbit | None


def _cases(model, params, D, detunings, mode, amplitudes):
    out = []
    name = detuning_name(model)
    for s in detunings:
        p = {**dict(params), name: float(s)}
        system = noisy_system(model, p, D)
        if not 0 <= mode < system.dof:
            raise ParameterError(f"mode {mode + 1} is not a mode of {system.model.name!r} "
                                 f"({system.dof} degree(s) of freedom)")
        flow = averaged_flow(system)
        states = stable_states(flow, amplitudes)
        if not states:
            raise ParameterError(f"no stable steady state at {name} = {s:g} (amplitudes "
                                 f"{amplitudes[0]:g} to {amplitudes[1]:g}): choose a detuning "
                                 "on a stable branch (kbm response MODEL shows them)")
        for st in states:
            try:
                orb = periodic_orbit(flow, st)
            except ConvergenceError:
                orb = None
            if orb is not None and not orb.stable:
                orb = None
            out.append(_Case(float(s), p, system, flow, st, orb))
    return out


def response_spectra(model, params: Mapping[str, object], D: float, detunings: Sequence[float],
                     *, mode: int = 0, amplitudes: tuple[float, float] = (0.02, 5.0),
                     omega=None, points: int = 401, simulate: bool = False,
                     trajectories: int = 32, duration: float | None = None, seed: int = 0,
                     workers: int | None = None, store=None, progress: bool = False,
                     resolution: float | None = None) -> list[ResponseSpectrum]:
    """Averaged, Floquet and (``simulate``) simulated spectra of ``x_mode`` about every stable
    state at each detuning.

    The frequencies are ``omega``, or the PSD's bins within ``Omega +- min(6 max|lambda|,
    Omega/2)`` when
    simulated, or ``points`` values there.  The simulation (:func:`simulate_fluctuations`)
    takes :data:`STEPS_PER_PERIOD` steps per forcing period, samples ``x`` at least six
    times per period of ``Omega`` (a whole number of samples per period), discards
    ``6/gamma`` (whole periods; ``gamma`` the slowest Floquet decay rate), removes the
    noise-induced shift of the coherent response (:func:`coherent_part`, reported as
    ``coherent_shift``) and resolves ``gamma/8``: Welch segments of ``2 pi 8/gamma``, at
    least four of them (default eight); ``resolution`` asks another.

    Raises
    ------
    kbm.errors.ParameterError
        For ``D <= 0``, an unforced model, a detuning with no stable state (named), or a
        ``duration`` too short for the resolution (the resolution it would give named).
    """
    cases = _cases(model, params, D, detunings, mode, amplitudes)
    plans = [_plan(c, duration, resolution) for c in cases] if simulate else \
        [None] * len(cases)
    out = []
    for case, plan in zip(cases, plans):
        st, flow, orb = case.state, case.flow, case.orbit
        W = float(flow.Omega[mode])
        # the line's neighbourhood, away from omega = 0 (Welch removes each segment's mean)
        # and from the harmonics
        span = min(6 * float(np.max(np.abs(st.eigenvalues))), 0.5 * W)
        sim = None
        if plan is not None:
            from numerics.spectrum.psd import ensemble_psd

            dx = simulate_fluctuations(model, case.params, D, orb.y0, dt=plan["dt"],
                                       burn_in_steps=plan["burn"], samples=plan["samples"],
                                       stride=plan["stride"], mode=mode,
                                       trajectories=trajectories, seed=seed, workers=workers,
                                       store=store, progress=progress, shared=len(cases))
            q = int(round(W * flow.period / (2 * math.pi)))
            dx, shift = coherent_part(dx, plan["per_period"], q)
            sim = ensemble_psd(dx, plan["dt"] * plan["stride"], nperseg=plan["nperseg"])
            keep = np.abs(sim.omega - W) <= span
            w = sim.omega[keep]
        else:
            w = np.linspace(W - span, W + span, points) if omega is None else \
                np.asarray(omega, float)
        fl = floquet_spectrum(case.system, orb, w, mode)[0] if orb is not None else None
        spec = ResponseSpectrum(case.detuning, st, orb, W, w, averaged_spectrum(flow, st, w, mode),
                                fl)
        if sim is not None:
            spec.simulated, spec.lower, spec.upper = sim.mean[keep], sim.lower[keep], \
                sim.upper[keep]
            spec.stderr = sim.stderr[keep]
            spec.rows = sim.rows[:, keep]
            spec.extra = {"resolution": sim.resolution, "trajectories": int(trajectories),
                          "duration": plan["duration"], "burn_in": plan["burn"] * plan["dt"],
                          "dt": plan["dt"], "sample_step": plan["dt"] * plan["stride"],
                          "seed": int(seed), "coherent_shift": shift}
        out.append(spec)
    return out


#: Heun steps per forcing period (the scheme's frequency error is (omega dt)^2/6)
STEPS_PER_PERIOD = 256
#: the resolution asked of the simulated PSD, in units of the slowest decay rate
RESOLUTION = 1 / 8
#: Welch segments a run must hold at least (half-overlapping: seven estimates)
MIN_SEGMENTS = 4


def _plan(case: _Case, duration: float | None, resolution: float | None = None) -> dict:
    if case.orbit is None:
        raise ParameterError(f"the averaged stable state at detuning {case.detuning:g} has no "
                             "stable true periodic response near it (too close to a jump?): "
                             "choose another detuning")
    flow = case.flow
    T = flow.period
    per = STEPS_PER_PERIOD * max(1, int(math.ceil(flow.ratios.max())))
    dt = T / per
    top = max(float(flow.Omega.max()), float(flow.omega0.max()))
    most = max(1, int(math.floor(math.pi / (3 * top) / dt)))
    stride = max(d for d in range(1, per + 1) if per % d == 0 and d <= most)
    step = dt * stride
    gamma = float(-np.max(np.log(np.abs(case.orbit.multipliers))) / T)
    want = RESOLUTION * gamma
    why = f"1/8 of the slowest decay rate {gamma:.3g} at detuning {case.detuning:g}"
    if resolution is not None:
        if not (isinstance(resolution, (int, float)) and math.isfinite(resolution)
                and resolution > 0):
            raise ParameterError(f"--resolution must be a positive angular frequency, got "
                                 f"{resolution!r}")
        want, why = float(resolution), "as asked"
    nperseg = int(math.ceil(2 * math.pi / (want * step)))
    seg = nperseg * step
    burn = int(math.ceil(6 / gamma / T)) * per  # whole periods: sample k at phase k/sp
    if duration is None:
        duration = 2 * MIN_SEGMENTS * seg
    if not (isinstance(duration, (int, float)) and duration > 0):
        raise ParameterError(f"--duration must be a positive time, got {duration!r}")
    if duration < MIN_SEGMENTS * seg:
        got = 2 * math.pi / (duration / MIN_SEGMENTS)
        raise ParameterError(
            f"--duration {duration:g} is too short for the resolution {want:.3g} (angular; "
            f"{why}): it would give {got:.3g} ({MIN_SEGMENTS} Welch segments); give "
            f"--duration >= {MIN_SEGMENTS * seg:.6g}")
    sp = per // stride
    samples = int(math.floor(duration / step)) // sp * sp
    return {"dt": dt, "stride": stride, "nperseg": nperseg, "burn": burn, "samples": samples,
            "duration": samples * step, "per_period": sp}


def coherent_part(dx: np.ndarray, per_period: int, harmonic: int) -> tuple[np.ndarray, dict]:
    """``dx`` without its ensemble- and period-averaged periodic part (the noise-induced
    shift of the coherent response, an ``O(D)`` effect beyond linear response that would
    stand as a line at the response frequency), and that shift's harmonic ``harmonic``:
    ``{"amplitude", "stderr", "cos", "sin"}`` (``dx ~ cos cos(Omega t) + sin sin(Omega t)``,
    the stderr over trajectories).  The mean removed holds ``1/N`` of the fluctuation power
    of the bins at the harmonics."""
    n, m = dx.shape
    prof = dx.reshape(n, m // per_period, per_period).mean(axis=1)
    mean = prof.mean(axis=0)
    k = np.arange(per_period)
    e = np.exp(-2j * math.pi * harmonic * k / per_period)
    c = 2 * (prof @ e) / per_period  # per trajectory: dx ~ Re(c e^{i Omega t})
    cm = c.mean()
    se = math.sqrt((np.var(c.real, ddof=1) + np.var(c.imag, ddof=1)) / n)
    return dx - np.tile(mean, m // per_period)[None, :], {
        "amplitude": float(abs(cm)), "stderr": se, "cos": float(cm.real),
        "sin": float(-cm.imag)}


