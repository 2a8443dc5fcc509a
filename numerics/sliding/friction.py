"""The steady sliding state of a pulled slider and its friction: one point of a friction law.

:func:`friction_point` runs the compiled driven slider (:mod:`numerics.sliding.driven`)
block after block until its steady state has been seen long enough, then measures it
(the window's measures: :mod:`numerics.sliding.window`; the settings and the point:
:mod:`numerics.sliding.friction_records`).

**Criterion** (every number a :class:`FrictionSettings` field):

1. *Transient.*  The first ``max(transient_wells lam/v, transient_damping/mu)`` of the
   run is dropped (whole stage periods ``lam/v``), and then the first
   ``transient_slips`` slips, and then any slips before the slip pattern repeats: the
   smallest cycle of ``p <= 8`` slips for which each slip from some slip on matches the
   one ``p`` later (the same wells crossed, onset forces within ``steady_tol`` of the
   largest onset force, or two samples' growth of the force in a stick) over at least
   three cycles (and four slips) to the last slip; no such cycle (an irregular
   stick-slip), nothing more is dropped.  The point's note says how many slips were
   dropped when more than ``transient_slips``.
2. *Stick and slip.*  The slider is *stuck* while ``|x_dot| < v_stick = min(v/2,
   0.02 Omega lam)`` for at least half a natural period ``pi/Omega`` (a velocity
   reversal of an oscillation is not a stick); two stuck intervals are one stick when the
   motion between them ends in the well it left (an oscillation in the well, such as the
   stage-attached SEDF's, self-excited while the stage passes within ``1/sqrt(beta)``,
   crosses no well); a *slip* runs from the end of one stick to the start of the next,
   in another well.
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
6. *Irregular stick-slip.*  A stick-slip whose slips show no repeating cycle (criterion
   1) is measured again with :data:`TIGHTER` times smaller ``rtol`` and ``atol``, each
   block integrated from the state moved back by whole wells (``x - n lam, tau - n
   lam/v``, a symmetry of ``sedf_comoving`` and ``cdc``: the integrator's error, relative to
   ``|x|`` and ``tau``, then does not grow with the distance slid): if they repeat there,
   that point is reported (the irregular slips were integration error, which the
   stage-attached SEDF's self-excitation multiplies by ``exp(2 mu/(3 v sqrt(beta)))`` each
   time the stage passes the stuck slider); if not, it is steady only when its mean force
   is within ``steady_tol`` of the first run's.  The note gives the first run's mean force
   and wells per slip, and for a stage-attached SEDF whose rounding :data:`ROUNDING` times
   that gain exceeds :data:`UNRESOLVED` wells, that its motion is not resolved in double
   precision; such a point is measured in long double instead, over two consecutive
   stick-slip cycles (:func:`numerics.sliding.extended.beyond_double`), where long
   double's rounding times the gain stays below :data:`UNRESOLVED`.

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
from dataclasses import replace

from kbm.errors import KBMError, ParameterError

from numerics.sliding.driven import DrivenSystem, driven_system
from numerics.sliding.extended import ROUNDING, UNRESOLVED, beyond_double
from numerics.sliding.friction_records import (FrictionPoint, FrictionSettings, eta,
                                               _static_quasistatic)
from numerics.sliding.window import (_TRANSLATION_INVARIANT, _Run, _settling, _slip_pattern,
                                     _sliding, _stick_phases, _stick_slip)

__all__ = ["friction_point", "V_RANGE", "ROUNDING", "UNRESOLVED"]

#: the stage velocities measured, in units of Omega lam (the samples and the run lengths stay
#: bounded: at most ~2 million samples, 30000 natural periods)
V_RANGE = (1e-4, 1e3)
#: the most samples in one stage period (a strong potential at a slow stage)
MAX_SAMPLES_PER_WELL = 500_000
#: a stick-slip without a repeating slip pattern is measured again at tolerances this many
#: times smaller (criterion 6), down to MIN_TOL (the smallest the driven slider takes)
TIGHTER = 100
MIN_TOL = 1e-14


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
        pt, repeats = _measure(system, settings, base)
    except ParameterError:
        raise
    except KBMError as exc:
        return FrictionPoint(**base, error=str(exc))
    if pt.ok and pt.regime == "stick-slip" and not repeats:
        return _irregular(system, settings, base, pt)
    return pt


def _irregular(system: DrivenSystem, s: FrictionSettings, base: dict,
               loose: FrictionPoint) -> FrictionPoint:
    """Criterion 6: a stick-slip whose slips show no repeating pattern, measured again at
    :data:`TIGHTER` times smaller tolerances, the state moved back by whole wells.  A
    pattern that repeats there was integration error (the stage-attached SEDF amplifies it
    by ``exp(2 mu/(3 v sqrt(beta)))`` each time the stage passes the slider): the tighter
    point is reported.  Irregular at both, the tighter point is steady only if its mean
    force agrees with the first within ``steady_tol``; the note gives both.  Where double
    precision's rounding times that gain is too large, the cycle measured in long double
    instead (:func:`numerics.sliding.extended.beyond_double`)."""
    said = (f"the slips show no repeating pattern at rtol {system.rtol:g}, atol "
            f"{system.atol:g} (mean force {loose.mean_force:.6g}, "
            f"{loose.wells_per_slip:.3g} wells per slip over {loose.slips} slips)")
    rtol, atol = system.rtol / TIGHTER, system.atol / TIGHTER
    if min(rtol, atol) < MIN_TOL:
        return _add_note(replace(loose, steady=False),
                         f"{said}; not steady: not checked at {TIGHTER} times tighter "
                         f"tolerances (below {MIN_TOL:g})")
    try:
        tight, repeats = _measure(replace(system, rtol=rtol, atol=atol), s, base, True)
    except KBMError as exc:
        tight, repeats = FrictionPoint(**base, error=str(exc)), False
    tight = replace(tight, steps=tight.steps + loose.steps)
    where = f"at rtol {rtol:g}, atol {atol:g}" + (
        ", each block from the state moved back by whole wells"
        if system.model in _TRANSLATION_INVARIANT else "")
    if not tight.ok:
        return _add_note(replace(loose, steady=False),
                         f"{said}; not steady: the run {where} failed: {tight.error}")
    if tight.regime == "stick-slip" and repeats:
        return _add_note(tight, f"{said}; {where}, they repeat (the irregular slips were "
                                "integration error): the point as measured there")
    F1, F2 = loose.mean_force, tight.mean_force
    agree = (tight.regime == "stick-slip"
             and abs(F1 - F2) <= s.steady_tol * max(abs(F1), abs(F2)))
    if agree:
        pt = _add_note(tight, f"{said}; {where}, they do not repeat either (irregular "
                              f"stick-slip): mean force {F2:.6g}, within {s.steady_tol:g} of "
                              "the first")
    else:
        pt = _add_note(replace(tight, steady=False),
                       f"{said}; not steady: {where}, the {tight.regime} has mean force "
                       f"{F2:.6g} (tolerance {s.steady_tol:g})")
    _, _, dt, v_stick, min_stuck = _grid(system, s)
    return beyond_double(system, s, base, pt, f"{said}; {where}, they do not repeat either "
                         f"(the {tight.regime} has mean force {F2:.6g})", dt, v_stick, min_stuck)


def _add_note(pt: FrictionPoint, text: str) -> FrictionPoint:
    return replace(pt, note=f"{pt.note}; {text}" if pt.note else text)


def _grid(system: DrivenSystem, s: FrictionSettings) -> tuple[float, int, float, float, int]:
    """The well's period ``t_fast``, the samples per stage period and their spacing ``dt``,
    the stick velocity ``v_stick`` and the fewest samples of a stuck interval (criterion 2)."""
    v, lam, Om = system.v, system.lam, system.omega
    Tw = lam / v
    t_fast = 2 * math.pi / math.sqrt(Om**2 + system.params.get("Delta", 0.0) * (2 * math.pi / lam))
    per_well = max(1, math.ceil(Tw / (t_fast / s.samples_per_period)))
    if per_well > MAX_SAMPLES_PER_WELL:
        raise ParameterError(
            f"one stage period lam/v = {Tw:.4g} holds {per_well} samples of the well's "
            f"oscillation (period {t_fast:.3g}); the limit is {MAX_SAMPLES_PER_WELL}: raise v "
            "or lower Delta")
    dt = Tw / per_well
    return (t_fast, per_well, dt, min(v / 2, 0.02 * Om * lam),
            max(1, math.ceil(0.5 * (2 * math.pi / Om) / dt)))


def _measure(system: DrivenSystem, s: FrictionSettings, base: dict, recentre: bool = False
             ) -> tuple[FrictionPoint, bool]:
    """The point (criteria 1-5), and whether its slips repeat (criterion 1's cycle found;
    ``True`` for every other point); with ``recentre`` each block integrated from the state
    moved back by whole wells (:class:`~numerics.sliding.window._Run`)."""
    p = system.params
    v, lam, Om, mu = system.v, system.lam, system.omega, p["mu"]
    Tn = 2 * math.pi / Om
    Tw = lam / v
    t_fast, per_well, dt, v_stick, min_stuck = _grid(system, s)
    block = max(1, math.ceil(50 * Tn / Tw))  # wells per block: >= 50 natural periods
    skip = math.ceil(max(s.transient_wells * Tw, s.transient_damping / mu) / Tw)
    longest = min(s.max_wells, math.ceil(s.max_periods * Tn / Tw))
    if skip >= longest:
        return FrictionPoint(**base, error=(
            f"the transient max({s.transient_wells:g} lam/v, {s.transient_damping:g}/mu) = "
            f"{skip * Tw:.4g} time units is not shorter than the longest run "
            f"({longest} stage periods lam/v = {longest * Tw:.4g}); raise mu, v or "
            "max_wells/max_periods")), True
    run = _Run(system, per_well, system.initial_state(), 0, t_fast, recentre)
    limits = (s.runaway_force * (p.get("Delta", 0.0) + Om**2 * lam + mu * v),
              s.runaway_damping * 2 * math.pi / t_fast)
    done = 0
    while done < skip:  # the transient: integrated, then dropped
        n = min(block, skip - done)
        run.extend(n)
        done += n
        stop = _runaway(run, base, limits)
        if stop is not None:
            return stop, True
        run.discard()
    slide_wells = max(s.sliding_wells, math.ceil(20 * Tn / Tw))
    extra = max(1, math.ceil(2 * Tn / Tw))
    need_slips, need_wells, attempt, previous = s.slips, slide_wells, 0, None
    previous_settling = 0
    while True:
        run.extend(block)
        done += block
        stop = _runaway(run, base, limits)
        if stop is not None:
            return stop, True
        stuck = _stick_phases(run, v_stick, min_stuck)
        # a phase's end is a slip's onset once the next phase has begun in another well;
        # the first slips dropped, then those before the slip pattern repeats
        onsets = [e for (_, e) in stuck[:-1]][s.transient_slips:]
        pattern = _slip_pattern(run, stuck)
        settling = _settling(pattern[s.transient_slips:],
                             _onset_tol(pattern, s, 2 * Om**2 * v * dt))
        onsets = onsets[settling:]
        tail = len(run.y) - 1 - (need_wells + extra) * per_well
        last = done >= longest
        pt = None
        if len(onsets) >= need_slips + 1 or (last and len(onsets) >= 3):
            pt = _stick_slip(run, base, stuck, onsets[-(need_slips + 1):], dt, s)
        elif tail >= 0 and all(e < tail for _, e in stuck):
            pt = _sliding(run, base, need_wells, extra, s)
        if pt is not None:
            cap = s.max_doublings if pt.regime == "stick-slip" else s.max_doublings_sliding
            if pt.steady or last or attempt >= cap:
                return _noted(pt, need_slips, done, Tw, s, settling), settling is not None
            # not steady yet: what was measured counts as transient; twice as long next
            attempt, need_slips, need_wells = attempt + 1, 2 * need_slips, 2 * need_wells
            previous, previous_settling = pt, settling
            run.discard()
            continue
        if last and previous is not None:
            return (_noted(previous, need_slips, done, Tw, s, previous_settling),
                    previous_settling is not None)
        if last:
            return FrictionPoint(**base, steps=run.steps,
                                 error=f"no steady state within {done} stage periods lam/v "
                                       f"= {done * Tw:.4g} time units "
                                       f"({_slips_seen(run, stuck, len(onsets), need_slips)}); "
                                       "raise max_wells or max_periods"), True


def _slips_seen(run: _Run, stuck: list[tuple[int, int]], after: int, need: int) -> str:
    """How many slips a run too short for a window saw, and, with two or more, how far
    apart they were and how long a run the window would need."""
    text = f"{after} slip{'' if after == 1 else 's'} after the transient"
    ends = [run.y[e, 2] for _, e in stuck[:-1]]
    if len(ends) < 2:
        return text
    apart = (ends[-1] - ends[0]) / (len(ends) - 1) * run.system.v / run.system.lam
    return (f"{text}; the slips come {apart:.3g} stage periods lam/v apart, so {need} slips need "
            f"about {need * apart:.3g}")


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


def _onset_tol(pattern: list[tuple[int, float]], s: FrictionSettings,
               resolution: float) -> float:
    """How close two slips' onset forces are when the slip pattern repeats: ``steady_tol``
    of the largest onset force of the run's slips, at least ``resolution`` (the force's
    growth over two samples of a stick)."""
    largest = max((abs(f) for _, f in pattern), default=0.0)
    return max(s.steady_tol * largest, resolution)


def _noted(pt: FrictionPoint, slips: int, done: int, Tw: float,
           s: FrictionSettings, settling: int | None = 0) -> FrictionPoint:
    """The point with a note when it is not steady, has fewer slips than asked, or had a
    transient longer than the fixed one (``settling`` more slips dropped)."""
    notes = []
    if pt.regime == "stick-slip" and settling:
        notes.append(f"{s.transient_slips + settling} slips dropped as transient after the "
                     f"fixed drop of whole stage periods, {settling} more than the "
                     f"{s.transient_slips} of the default: the slip pattern (wells crossed, "
                     "onset force) repeats only after them")
    if pt.regime == "stick-slip" and pt.slips < slips:
        notes.append(f"only {pt.slips} slips by the longest run")
    if not pt.steady:
        notes.append(f"not steady after {done} stage periods ({done * Tw:.4g} time units): "
                     f"the halves' mean forces {pt.halves[0]:.6g}, {pt.halves[1]:.6g} "
                     f"(tolerance {s.steady_tol:g}), stored energy change "
                     f"{pt.energy_residual:.2g} of the work (tolerance {s.energy_tol:g})")
    return replace(pt, note="; ".join(notes)) if notes else pt
