"""The averaged prediction and the step pilot of :func:`.stationary.noise_report`, computed
in a second process beside the Fokker-Planck solve (:func:`.stationary.averaged_and_step`).

Neither depends on the stationary Kramers solution, nor it on them: the averaging (the
energy envelope's orbit integrals, 3.1 s of the SEDF at mu = 0.01) and the pilot that
measures the step (1.1 to 1.4 s at mu = 0.1 and 0.02) ran before the solve, with the
second core idle, while the solve's ladder leaves that core idle for seconds after its
last grid step of ``P(E)`` (:mod:`numerics.fokker_planck._ahead`).  They are one call,
:func:`.stationary.averaged_and_step`, started in a forked copy of this process by
:class:`numerics.fokker_planck._ahead.Ahead` (the same machinery, its processes and
``--workers``), whose result comes back whole (pickled): the same numbers, so the same
bytes, whatever the number of processes.  The averaged density's bin averages are
computed there too, on the edges of the ensemble's histogram (:class:`Tabulated`): the
envelope's interpolants stay in that process.  With one process (``--workers 1``,
``KBM_FP_WORKERS=1``, a daemonic process) the call is made here before the solve, in
the order of before.  A refusal of the averaging (no stationary state: the SEDF at
beta = -1, whose energy drift is positive) stops the solve at once
(:class:`numerics.fokker_planck._ahead.Alarm`: the forked process signals this one) and
is raised as before, its exception sent back whole; the solve would otherwise run on
for nothing (3.6 s before, 15 s with the solve run to its end).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from .averaged import AveragedStationary

__all__ = ["Beside", "Tabulated", "histogram_edges"]


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
class Beside:
    """What :func:`.stationary.averaged_and_step` returns: the averaged state ``avg`` (its ``bins``
    :class:`Tabulated`) or ``None`` with the reason ``why``, the step pilot's record
    ``pilot`` and the times ``(t_end, burn_in, dt)``."""

    avg: AveragedStationary | None
    why: str
    pilot: dict
    times: tuple
