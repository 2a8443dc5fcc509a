"""The averaged prediction and the step pilot of :func:`.stationary.noise_report`, computed
in a second process beside the Fokker-Planck solve (:func:`beside`).

Neither depends on the stationary Kramers solution, nor it on them: the averaging (the
energy envelope's orbit integrals, 3.1 s of the SEDF at mu = 0.01) and the pilot that
measures the step (1.1 to 1.4 s at mu = 0.1 and 0.02) ran before the solve, with the
second core idle, while the solve's ladder leaves that core idle for seconds after its
last grid step of ``P(E)`` (:mod:`numerics.fokker_planck._ahead`).  They are two calls,
:func:`.stationary.averaged_tabulated` then :func:`.stationary.step_pilot`, started in a
forked copy of this process by :class:`numerics.fokker_planck._ahead.Ahead` (the same
machinery, its processes and ``--workers``), whose results come back whole (pickled):
the same numbers, so the same bytes, whatever the number of processes.  The averaged
density's bin averages are computed there too, on the edges of the ensemble's histogram
(:class:`Tabulated`): the envelope's interpolants stay in that process.  With one
process (``--workers 1``, ``KBM_FP_WORKERS=1``, a daemonic process) the calls are made
here before the solve, in the order of before.  A refusal of the averaging (no
stationary state: the SEDF at beta = -1, whose energy drift is positive) stops the solve
at once (:class:`numerics.fokker_planck._ahead.Alarm`: the forked process signals this
one) and is raised as before, its exception sent back whole; the solve would otherwise
run on for nothing (3.6 s before, 15 s with the solve run to its end).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from .averaged import AveragedStationary

__all__ = ["Averaged", "Stepped", "Tabulated", "beside", "histogram_edges"]


def histogram_edges(avg: AveragedStationary, bins: int) -> np.ndarray:
    """The edges of the ensemble's histogram of ``avg.variable`` on ``avg.support`` (``0``
    below for the amplitude), as :func:`numerics.noise.ensemble.stationary_ensemble`
    makes them: ``bins`` equal bins."""
    lo, hi = avg.support
    return np.linspace(0.0 if avg.variable == "a" else float(lo), float(hi), bins + 1)


class Tabulated:
    """``bins(edges)`` of an :class:`.averaged.AveragedStationary` computed on one set of
    edges, for the process that asks for them (the envelope's interpolants do not leave
    the process that built them).

    Raises
    ------
    ValueError
        Called with other edges (a programming error: :func:`histogram_edges` gives the
        ensemble's).
    """

    def __init__(self, edges: np.ndarray, values: np.ndarray):
        self.edges, self.values = np.asarray(edges, float), values

    def __call__(self, edges):
        edges = np.asarray(edges, float)
        if not np.array_equal(edges, self.edges):
            raise ValueError("the averaged density was tabulated on the histogram's edges "
                             f"({self.edges.size - 1} bins on [{self.edges[0]:g}, "
                             f"{self.edges[-1]:g}]), not these")
        return self.values.copy()


@dataclasses.dataclass(frozen=True)
class Averaged:
    """The averaged state ``avg`` (its ``bins`` :class:`Tabulated`), or ``None`` and the
    reason ``why`` (:func:`.stationary.averaged_tabulated`)."""

    avg: AveragedStationary | None
    why: str


@dataclasses.dataclass(frozen=True)
class Stepped:
    """The step pilot's record ``pilot`` and the times ``(t_end, burn_in, dt)``
    (:func:`.stationary.step_pilot`)."""

    pilot: dict
    times: tuple


def _call(func, *args, **kwargs):
    return func(*args, **kwargs)


def _unless_taken(taken, pilot) -> Stepped:
    """``pilot()``, or an empty record when the caller has taken it on (``taken``, shared
    memory set by :func:`beside`: the forked process does not make it a second time)."""
    return Stepped({}, ()) if taken.value else pilot()


def beside(solve, averaged, pilot, workers: int) -> tuple:
    """``(solve(), averaged(), pilot())``, the last two in a forked process beside the
    first where ``workers`` allows (:class:`numerics.fokker_planck._ahead.Ahead`), else
    here in the order ``averaged``, ``pilot``, ``solve`` (that of before).  The errors
    come in that order too: a refusal of ``averaged`` stops ``solve`` at once
    (:class:`numerics.fokker_planck._ahead.Alarm`) and is raised, then ``pilot``'s.  When
    ``solve`` ends first and the forked process is still averaging, ``pilot`` is made here
    too (this process is free: SEDF mu = 0.1, 1.1 s), its warnings shown once ``averaged``
    has not refused (vdp at D = 1e300: none, as before)."""
    import multiprocessing
    import warnings

    from ..fokker_planck._ahead import Ahead, Alarm

    taken = multiprocessing.get_context().RawValue("b", 0)  # the pilot made here
    with Alarm() as alarm, Ahead(_call, workers, alarm=alarm.signum, raises=True) as ahead:
        if not ahead.start("averaged", averaged,
                           then=[("pilot", (_unless_taken, taken, pilot), {})]):
            first, second = averaged(), pilot()
            return solve(), first, second
        try:
            out = solve()
        except Exception:  # Alarmed, or the solve's own error after theirs
            alarm.disarm()
            ahead.result("averaged", averaged)
            ahead.result("pilot", pilot)
            raise
        alarm.disarm()
        if ahead.ready("pilot") or ahead.ready("averaged"):  # (the pilot under way there)
            return out, ahead.result("averaged", averaged), ahead.result("pilot", pilot)
        taken.value = 1
        try:
            with warnings.catch_warnings(record=True) as caught:
                second = pilot()
        except Exception:
            ahead.result("averaged", averaged)
            raise
        first = ahead.result("averaged", averaged)
        for w in caught:
            warnings.showwarning(w.message, w.category, w.filename, w.lineno, w.file, w.line)
        return out, first, second
