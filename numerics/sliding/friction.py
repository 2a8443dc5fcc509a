"""The steady sliding state of a pulled slider and its friction: one point of a friction law.

:func:`friction_point` runs the compiled driven slider (:mod:`numerics.sliding.driven`)
block after block until its steady state has been seen long enough, then measures it.

**Criterion** (every number a :class:`FrictionSettings` field):

1. *Transient.*  The first ``max(transient_wells lam/v, transient_damping/mu)`` of the
   run is dropped (whole stage periods ``lam/v``), and then the first
   ``transient_slips`` slips.
2. *Stick and slip.*  The slider is *stuck* while ``|x_dot| < v_stick = min(v/2,
   0.02 Omega lam)`` for at least half a natural period ``pi/Omega`` (a velocity
   reversal of an oscillation is not a stick); a *slip* runs from the end of one
   stuck interval to the start of the next.
3. *Window.*  With stick-slip: from the onset of one slip to the onset of the slip
   ``slips`` later (both at the same point of the stick-slip cycle, so whole wells are
   crossed in between).  Without any stuck interval: ``max(sliding_wells,
   20 natural periods)`` whole stage periods ``lam/v``, the end moved by up to two
   natural periods (whole wells again) to where the energy ``E`` returns closest to its
   starting value.
4. *Steady.*  The mean friction force of the window's two halves agree within
   ``steady_tol``, and the stored energy ``E`` changes over the window by less than
   ``energy_tol`` of the work of the stage; both relative to the larger of the mean force
   and the energy flow per distance through the non-conservative forces (``(gain G_+ +
   G_-)/(v Delta t)``; the dissipation itself for the CDC, but for a self-oscillating
   SEDF, whose net friction may be 0, the energy it both gains and loses).  If not, the window counts as
   transient and one twice as long (twice the slips, or twice the wells) is measured
   after it, at most ``max_doublings`` times.  The paper's SEDF (``sedf``) is never steady: its damping ``mu beta x^2``
   grows with the distance slid.
5. *Runaway.*  A spring force above ``runaway_force (Delta + Omega^2 lam + mu v)``, or
   a damping rate above ``runaway_damping`` well frequencies, ends the run: there is no
   bounded sliding state from rest.

**Measures** over the window: the mean spring force ``F_bar = Delta J/Delta t`` (the
kinetic friction; ``J`` the spring's impulse, integrated), its standard deviation, the
static friction (the peak spring force of each stuck interval before a slip; their
mean), the dissipation per unit sliding distance ``Delta Gamma/(v Delta t)``, the fraction
of time stuck, the wells crossed per slip, and the regime: ``stick-slip``, ``smooth
sliding`` (never stuck, ``x_dot > 0`` throughout), ``self-oscillating sliding`` (never
stuck, velocity reversals, a model with an energy source), ``oscillating sliding``
(the same without a source) or ``runaway``.

**Built-in check**: ``v Delta J = Delta Gamma + Delta E`` is exact (power balance), so in
steady state the dissipation per distance equals ``F_bar`` up to ``Delta E/(v Delta t)``;
:attr:`FrictionPoint.energy_residual` is ``|F_bar - Gamma/(v Delta t)|`` relative to the
scale of criterion 4 (``|F_bar|`` itself for the CDC), and :attr:`FrictionPoint.audit` the
integration error of the balance.

Each point is reported against the Prandtl-Tomlinson parameter ``eta = 2 pi Delta/(Omega^2
lam)`` (stick-slip needs ``eta > 1``) with the quasi-static static friction ``Delta
sqrt(1 - 1/eta^2)``.

References
----------
M. D'Acunto, eqs. (3), (4), (10)-(12); L. Prandtl (1928), G. A. Tomlinson (1929); the
friction-velocity curves of the Prandtl-Tomlinson model: O. M. Braun and Y. S. Kivshar,
*The Frenkel-Kontorova Model* (Springer 2004), ch. 9.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, fields, replace

import numpy as np

from kbm.errors import KBMError, ParameterError

from numerics.sliding.driven import DrivenSystem, driven_system
from numerics._show import num, params_text

__all__ = ["FrictionSettings", "FrictionPoint", "friction_point", "eta", "REGIMES", "V_RANGE"]

#: the stage velocities measured, in units of Omega lam (the samples and the run lengths stay
#: bounded: at most ~2 million samples, 30000 natural periods)
V_RANGE = (1e-4, 1e3)
#: the most samples in one stage period (a strong potential at a slow stage)
MAX_SAMPLES_PER_WELL = 500_000

#: the regimes of a steady sliding state
REGIMES = ("stick-slip", "smooth sliding", "self-oscillating sliding", "oscillating sliding",
           "runaway")


@dataclass(frozen=True)
class FrictionSettings:
    """The steady-state criterion and its run lengths (see the module docstring).

    Attributes
    ----------
    slips
        Slips averaged over in stick-slip.
    transient_slips, transient_wells, transient_damping
        The transient dropped: slips, stage periods ``lam/v``, times ``1/mu``.
    sliding_wells
        Whole stage periods averaged over when the slider never sticks (at least 20
        natural periods ``2 pi/Omega``).
    max_wells, max_periods
        The longest run, in stage periods ``lam/v`` and in natural periods (a point
        that has shown no window by then is an error).
    max_doublings, max_doublings_sliding
        How often a window that is not steady is dropped and one twice as long measured
        after it, with stick-slip and without (sliding windows are short: a mean force
        that is a small difference of large energy flows, as in the self-oscillating
        sliding of the SEDF, needs long ones); then the point is reported as measured,
        flagged not steady.
    samples_per_period
        Samples per period of the oscillation at the bottom of a well,
        ``2 pi/sqrt(Omega^2 + Delta k)``.
    steady_tol
        Largest relative difference of the two halves' mean forces of a steady window;
        a window that fails is dropped (counted as transient) and one twice as long
        is measured after it.
    energy_tol
        Largest change of the stored energy over a steady window, relative to the work
        of the stage ``F_bar v Delta t``.
    runaway_force, runaway_damping
        A run whose spring force exceeds ``runaway_force (Delta + Omega^2 lam + mu v)``,
        or whose damping rate exceeds ``runaway_damping`` times the well frequency
        ``sqrt(Omega^2 + Delta k)``, has no bounded sliding state (regime ``runaway``).
    """

    slips: int = 20
    transient_slips: int = 2
    transient_wells: float = 3.0
    transient_damping: float = 10.0
    sliding_wells: int = 20
    max_wells: int = 3000
    max_periods: float = 30_000.0
    max_doublings: int = 2
    max_doublings_sliding: int = 5
    samples_per_period: int = 16
    steady_tol: float = 0.01
    energy_tol: float = 1e-3
    runaway_force: float = 10.0
    runaway_damping: float = 50.0

    def __post_init__(self) -> None:
        for f in fields(self):
            val = getattr(self, f.name)
            if not (isinstance(val, (int, float)) and math.isfinite(val) and val >= 0):
                raise ParameterError(f"friction setting {f.name} must be a number >= 0, "
                                     f"got {val!r}")
        for name in ("slips", "sliding_wells", "max_wells", "samples_per_period"):
            if int(getattr(self, name)) != getattr(self, name) or getattr(self, name) < 1:
                raise ParameterError(f"friction setting {name} must be an integer >= 1, "
                                     f"got {getattr(self, name)!r}")


@dataclass(frozen=True)
class FrictionPoint:
    """The friction measures of one steady sliding state (NaN where a measure does not apply).

    Attributes
    ----------
    model, params
        The slider and its physical parameters.
    eta
        Prandtl-Tomlinson parameter ``2 pi Delta/(Omega^2 lam)``.
    regime
        One of :data:`REGIMES` (``""`` when the run failed).
    steady
        Whether the two halves of the window agree (:class:`FrictionSettings`).
    mean_force, force_fluctuation
        Mean spring force over the window (kinetic friction) and its standard deviation.
    static_force, static_quasistatic
        Mean peak spring force before the slips; the quasi-static ``Delta sqrt(1 -
        1/eta^2)`` (NaN for ``eta <= 1``).
    peak_force
        Largest spring force in the window.
    dissipation_per_distance
        ``Delta Gamma/(v Delta t)``.
    energy_residual, audit
        ``|F_bar - dissipation_per_distance|`` over the larger of ``|F_bar|`` and the
        energy flow per distance (criterion 4); the power balance's integration error
        ``|v Delta J - Delta Gamma - Delta E|/Delta Gamma``.
    stuck_fraction, wells_per_slip, slips
        Fraction of the window stuck; mean wells crossed per slip; slips in the window.
    halves
        Mean force of the window's two halves.
    window
        ``(t0, t1)``.
    steps
        Integrator steps of the whole run.
    note
        What the reader should know (not steady, fewer slips, runaway), or ``""``.
    error
        Why there is no result (the rest is NaN), or ``None``.
    """

    model: str
    params: Mapping[str, float]
    eta: float
    regime: str = ""
    steady: bool = False
    mean_force: float = math.nan
    force_fluctuation: float = math.nan
    static_force: float = math.nan
    static_quasistatic: float = math.nan
    peak_force: float = math.nan
    dissipation_per_distance: float = math.nan
    energy_residual: float = math.nan
    audit: float = math.nan
    stuck_fraction: float = math.nan
    wells_per_slip: float = math.nan
    slips: int = 0
    halves: tuple[float, float] = (math.nan, math.nan)
    window: tuple[float, float] = (math.nan, math.nan)
    steps: int = 0
    note: str = ""
    error: str | None = field(default=None)

    @property
    def ok(self) -> bool:
        """A measured point (no error)."""
        return self.error is None

    def __repr__(self) -> str:
        head = f"FrictionPoint({self.model}; {params_text(self.params)}"
        if self.error:
            return f"{head}: failed: {self.error})"
        return (f"{head}: {self.regime or 'no regime'}, mean force {num(self.mean_force, 6)}, "
                f"static {num(self.static_force, 6)}, stuck {num(self.stuck_fraction, 3)}, "
                f"{'steady' if self.steady else 'not steady'})")

    def to_json(self) -> dict:
        """Every field, JSON-ready (NaN stays NaN; :func:`kbm.strict_json.finite` maps it)."""
        out = {f.name: getattr(self, f.name) for f in fields(self)}
        out["params"] = dict(self.params)
        out["halves"], out["window"] = list(self.halves), list(self.window)
        return out


def eta(params: Mapping[str, float]) -> float:
    """Prandtl-Tomlinson parameter ``eta = 2 pi Delta/(Omega^2 lam)`` (``Omega = 1``, ``lam
    = 1`` by default)."""
    return (2 * math.pi * float(params.get("Delta", 0.0))
            / (float(params.get("Omega", 1.0))**2 * float(params.get("lam", 1.0))))


def _static_quasistatic(params: Mapping[str, float]) -> float:
    e = eta(params)
    return float(params.get("Delta", 0.0)) * math.sqrt(1 - 1 / e**2) if e > 1 else math.nan


def friction_point(model: str, params: Mapping[str, object], *,
                   settings: FrictionSettings | None = None, engine: str = "compiled",
                   rtol: float = 1e-9, atol: float = 1e-9) -> FrictionPoint:
    """The steady sliding state of ``model`` at ``params`` and its friction measures.

    Parameters
    ----------
    model
        ``"sedf_comoving"``, ``"cdc"`` or ``"sedf"`` (the paper's, never steady).
    params
        ``mu, Delta, lam, v`` (``v > 0``), ``beta`` for the self-excited sliders,
        ``Omega`` (1 by default).
    settings
        The steady-state criterion (:class:`FrictionSettings`).
    engine
        ``"compiled"`` (numba) or ``"scipy"`` (the reference path).

    Raises
    ------
    kbm.errors.ParameterError
        For bad parameters or settings, or ``v`` outside :data:`V_RANGE` times ``Omega
        lam``.  A run that fails (diverges) is not raised: the point carries the
        ``error``.

    Examples
    --------
    >>> p = friction_point("cdc", {"mu": 3, "Omega": 2, "Delta": 3, "lam": 1, "v": 0.01},
    ...                    settings=FrictionSettings(slips=4))
    >>> p.regime, p.wells_per_slip, p.energy_residual < 1e-3
    ('stick-slip', 1.0, True)
    """
    settings = settings or FrictionSettings()
    system = driven_system(model, params, engine=engine, rtol=rtol, atol=atol)
    scale = system.omega * system.lam
    lo, hi = V_RANGE
    if not lo * scale <= system.v <= hi * scale:
        raise ParameterError(
            f"v = {system.v:g} is outside the range of the friction laws, {lo:g} to {hi:g} "
            f"times Omega lam = {scale:g}: below it one stage period lam/v spans more than "
            "10^5 natural periods (the quasi-static limit: use the saddle-node slip energy, "
            "numerics.saddle_node), above it the slider slides smoothly with F = mu v")
    base = dict(model=model, params=dict(system.params), eta=eta(system.params),
                static_quasistatic=_static_quasistatic(system.params))
    try:
        return _measure(system, settings, base)
    except ParameterError:
        raise
    except KBMError as exc:
        return FrictionPoint(**base, error=str(exc))


class _Run:
    """The samples kept after the transient (rows ``(x, x_dot, tau, G_+, G_-, W, J)``), in a
    buffer that doubles when full."""

    def __init__(self, system: DrivenSystem, per_well: int, y0: np.ndarray, steps: int,
                 t_fast: float):
        self.system, self.per_well, self.steps, self.t_fast = system, per_well, steps, t_fast
        self.failure = ""
        self._buf = np.empty((64 * per_well + 1, len(y0)))
        self._buf[0] = y0
        self._n = 1

    @property
    def y(self) -> np.ndarray:
        return self._buf[:self._n]

    def discard(self) -> None:
        """Drop every sample but the last (after the transient)."""
        self._buf[0] = self._buf[self._n - 1]
        self._n = 1

    def extend(self, wells: int) -> None:
        duration = wells * self.system.lam / self.system.v
        blk = self.system.run(self._buf[self._n - 1], duration, wells * self.per_well,
                              max_steps=_step_limit(duration, self.t_fast), partial=True)
        self.failure = blk.message if blk.status else ""
        new = blk.y[1:][np.isfinite(blk.y[1:, 0])]
        if self._n + len(new) > len(self._buf):
            grown = np.empty((2 * (self._n + len(new)), self._buf.shape[1]))
            grown[:self._n] = self._buf[:self._n]
            self._buf = grown
        self._buf[self._n:self._n + len(new)] = new
        self._n += len(new)
        self.steps += blk.steps


def _measure(system: DrivenSystem, s: FrictionSettings, base: dict) -> FrictionPoint:
    p = system.params
    v, lam, Om, mu = system.v, system.lam, system.omega, p["mu"]
    k = 2 * math.pi / lam
    Tn = 2 * math.pi / Om
    Tw = lam / v
    t_fast = 2 * math.pi / math.sqrt(Om**2 + p.get("Delta", 0.0) * k)
    per_well = max(1, math.ceil(Tw / (t_fast / s.samples_per_period)))
    if per_well > MAX_SAMPLES_PER_WELL:
        raise ParameterError(
            f"one stage period lam/v = {Tw:.4g} holds {per_well} samples of the well's "
            f"oscillation (period {t_fast:.3g}); the limit is {MAX_SAMPLES_PER_WELL}: raise v "
            "or lower Delta")
    dt = Tw / per_well
    block = max(1, math.ceil(50 * Tn / Tw))  # wells per block: >= 50 natural periods
    skip = math.ceil(max(s.transient_wells * Tw, s.transient_damping / mu) / Tw)
    longest = min(s.max_wells, math.ceil(s.max_periods * Tn / Tw))
    if skip >= longest:
        return FrictionPoint(**base, error=(
            f"the transient max({s.transient_wells:g} lam/v, {s.transient_damping:g}/mu) = "
            f"{skip * Tw:.4g} time units is not shorter than the longest run "
            f"({longest} stage periods lam/v = {longest * Tw:.4g}); raise mu, v or "
            "max_wells/max_periods"))
    run = _Run(system, per_well, system.initial_state(), 0, t_fast)
    v_stick = min(v / 2, 0.02 * Om * lam)
    min_stuck = max(1, math.ceil(0.5 * Tn / dt))
    limits = (s.runaway_force * (p.get("Delta", 0.0) + Om**2 * lam + mu * v),
              s.runaway_damping * 2 * math.pi / t_fast)
    done = 0
    while done < skip:  # the transient: integrated, then dropped
        n = min(block, skip - done)
        run.extend(n)
        done += n
        stop = _runaway(run, base, limits)
        if stop is not None:
            return stop
        run.discard()
    slide_wells = max(s.sliding_wells, math.ceil(20 * Tn / Tw))
    extra = max(1, math.ceil(2 * Tn / Tw))
    need_slips, need_wells, attempt, previous = s.slips, slide_wells, 0, None
    while True:
        run.extend(block)
        done += block
        stop = _runaway(run, base, limits)
        if stop is not None:
            return stop
        stuck = _stuck_intervals(np.abs(run.y[:, 1]) < v_stick, min_stuck)
        onsets = [e for (_, e) in stuck if e < len(run.y) - 1][s.transient_slips:]
        tail = len(run.y) - 1 - (need_wells + extra) * per_well
        last = done >= longest
        pt = None
        if len(onsets) >= need_slips + 1 or (last and len(onsets) >= 3):
            pt = _stick_slip(run, base, stuck, onsets[-(need_slips + 1):], dt, s)
        elif tail >= 0 and all(e < tail for _, e in stuck):
            pt = _sliding(run, base, need_wells, extra, dt, s)
        if pt is not None:
            cap = s.max_doublings if pt.regime == "stick-slip" else s.max_doublings_sliding
            if pt.steady or last or attempt >= cap:
                return _noted(pt, need_slips, done, Tw, s)
            # not steady yet: what was measured counts as transient; twice as long next
            attempt, need_slips, need_wells = attempt + 1, 2 * need_slips, 2 * need_wells
            previous = pt
            run.discard()
            continue
        if last and previous is not None:
            return _noted(previous, need_slips, done, Tw, s)
        if last:
            return FrictionPoint(**base, steps=run.steps,
                                 error=f"no steady state within {done} stage periods lam/v "
                                       f"= {done * Tw:.4g} time units ({len(onsets)} slips "
                                       f"after the transient); raise max_wells or max_periods")


def _runaway(run: _Run, base: dict, limits: tuple[float, float]) -> FrictionPoint | None:
    """A ``runaway`` point (or a failure) if the run has left every bounded state (criterion 5)."""
    f_limit, damping_limit = limits
    system = run.system
    last = run.y[-1]
    F_end = abs(system.omega**2 * (system.v * last[2] - last[0]))
    rate = float(system.damping(last)[0])
    if F_end <= f_limit and rate <= damping_limit and not run.failure:
        return None
    if F_end > f_limit:
        why = f"the spring force reached {F_end:.4g} (limit {f_limit:.4g})"
    elif rate > damping_limit:
        why = f"the damping rate reached {rate:.4g} (limit {damping_limit:.4g})"
    else:
        return FrictionPoint(**base, steps=run.steps,
                             error=f"the driven {system.model} failed at t = "
                                   f"{run.y[-1, 2]:.6g}: {run.failure}")
    return FrictionPoint(**base, regime="runaway", steps=run.steps,
                         note=f"{why} at t = {run.y[-1, 2]:.4g}: no bounded sliding state from "
                              "rest (the friction grows without bound)")


def _noted(pt: FrictionPoint, slips: int, done: int, Tw: float,
           s: FrictionSettings) -> FrictionPoint:
    """The point with a note when it is not steady or has fewer slips than asked."""
    notes = []
    if pt.regime == "stick-slip" and pt.slips < slips:
        notes.append(f"only {pt.slips} slips by the longest run")
    if not pt.steady:
        notes.append(f"not steady after {done} stage periods ({done * Tw:.4g} time units): "
                     f"the halves' mean forces {pt.halves[0]:.6g}, {pt.halves[1]:.6g} "
                     f"(tolerance {s.steady_tol:g}), stored energy change "
                     f"{pt.energy_residual:.2g} of the work (tolerance {s.energy_tol:g})")
    return replace(pt, note="; ".join(notes)) if notes else pt


def _stuck_intervals(mask: np.ndarray, min_len: int) -> list[tuple[int, int]]:
    """``(start, end)`` sample indices of the runs of ``mask`` at least ``min_len`` long."""
    d = np.diff(np.concatenate([[0], mask.astype(np.int8), [0]]))
    starts, ends = np.nonzero(d == 1)[0], np.nonzero(d == -1)[0] - 1
    return [(int(a), int(b)) for a, b in zip(starts, ends) if b - a + 1 >= min_len]


def _force(run: _Run) -> np.ndarray:
    Om2 = run.system.omega**2
    return Om2 * (run.system.v * run.y[:, 2] - run.y[:, 0])


def _window_means(run: _Run, i0: int, i1: int) -> dict:
    """Mean force, dissipation per distance, residuals over samples ``i0..i1``."""
    sys_, y = run.system, run.y
    T = y[i1, 2] - y[i0, 2]
    dJ = y[i1, 6] - y[i0, 6]
    dG = float(sys_.gamma(y[i1])[0] - sys_.gamma(y[i0])[0])
    dE = float(sys_.energy(y[i1])[0] - sys_.energy(y[i0])[0])
    F = dJ / T
    D = dG / (sys_.v * T)
    flow = _flow(run, i0, i1) / (sys_.v * T)
    F_s = _force(run)[i0:i1 + 1]
    scale = max(abs(F), flow)
    return dict(mean_force=float(F), dissipation_per_distance=float(D),
                energy_residual=float(abs(F - D) / scale) if scale else math.inf,
                audit=float(abs(sys_.v * dJ - dG - dE) / max(abs(dG), 1e-300)),
                force_fluctuation=float(np.std(F_s)), peak_force=float(np.max(F_s)),
                window=(float(y[i0, 2]), float(y[i1, 2])))


def _flow(run: _Run, i0: int, i1: int) -> float:
    """The energy that flows through the non-conservative forces over samples ``i0..i1``,
    ``gain G_+ + G_-`` (the dissipation of the CDC; for the SEDF the damping and the
    self-excitation both count, though their difference, the net dissipation, may be 0)."""
    y, g = run.y, run.system.gain_factor
    return float(abs(g * (y[i1, 3] - y[i0, 3])) + abs(y[i1, 4] - y[i0, 4]))


def _steady(run: _Run, i0: int, im: int, i1: int, s: FrictionSettings) -> tuple[bool, tuple]:
    """Whether the halves' mean forces agree and the stored energy returns (criterion 4),
    both relative to the larger of the mean force and the energy flow per distance."""
    f1 = _window_means(run, i0, im)["mean_force"]
    f2 = _window_means(run, im, i1)["mean_force"]
    sys_, y = run.system, run.y
    T = y[i1, 2] - y[i0, 2]
    flow = _flow(run, i0, i1)
    scale = max(abs(f1), abs(f2), flow / (sys_.v * T), 1e-300)
    dE = abs(float(sys_.energy(y[i1])[0] - sys_.energy(y[i0])[0]))
    work = max(abs(sys_.v * (y[i1, 6] - y[i0, 6])), flow)
    return bool(abs(f1 - f2) <= s.steady_tol * scale and dE <= s.energy_tol * work), (f1, f2)


def _step_limit(duration: float, t_fast: float) -> int:
    """At most 2000 steps per fast period (a run that needs more is stiff: a runaway)."""
    return int(2000 * duration / t_fast) + 100_000


def _stick_slip(run: _Run, base: dict, stuck, onsets: list[int], dt: float,
                s: FrictionSettings) -> FrictionPoint:
    i0, i1 = onsets[0], onsets[-1]
    lam = run.system.lam
    F = _force(run)
    by_end = {e: a for a, e in stuck}
    starts = sorted(a for a, _ in stuck)
    peaks, wells = [], []
    for j, e in enumerate(onsets[:-1]):
        a = by_end[e]
        peaks.append(float(np.max(F[a:e + 1])))
        nxt = next(st for st in starts if st > e)
        wells.append(round(run.y[nxt, 0] / lam) - round(run.y[e, 0] / lam))
    stuck_time = sum(max(0, min(e, i1) - max(a, i0)) for a, e in stuck) * dt
    m = _window_means(run, i0, i1)
    steady, halves = _steady(run, i0, onsets[len(onsets) // 2], i1, s)
    return FrictionPoint(**base, regime="stick-slip", steady=steady, halves=halves,
                         static_force=float(np.mean(peaks)),
                         stuck_fraction=float(stuck_time / (m["window"][1] - m["window"][0])),
                         wells_per_slip=float(np.mean(wells)), slips=len(onsets) - 1,
                         steps=run.steps, **m)


def _sliding(run: _Run, base: dict, wells: int, extra: int, dt: float,
             s: FrictionSettings) -> FrictionPoint:
    pw = run.per_well
    i0 = len(run.y) - 1 - (wells + extra) * pw
    ends = np.arange(i0 + wells * pw, i0 + (wells + extra) * pw + 1, pw)
    E = run.system.energy(run.y[ends])
    i1 = int(ends[np.argmin(np.abs(E - run.system.energy(run.y[i0])[0]))])
    m = _window_means(run, i0, i1)
    half = i0 + ((i1 - i0) // pw // 2) * pw
    steady, halves = _steady(run, i0, half, i1, s)
    reverses = bool(np.min(run.y[i0:i1 + 1, 1]) < 0)
    regime = ("smooth sliding" if not reverses else
              "self-oscillating sliding" if run.system.has_source else "oscillating sliding")
    return FrictionPoint(**base, regime=regime, steady=steady, halves=halves, stuck_fraction=0.0,
                         steps=run.steps, **m)
