"""Many limit cycles at once: a parameter sweep on any executor, with a progress bar.

:func:`sweep` maps :func:`numerics.limit_cycle` over a list (or grid) of
parameter sets in chunks (:mod:`numerics.executor`: a local process pool by
default, or a Dask cluster).  Results come back in the order of the input,
whatever the scheduling and the executor, and a failed point is a
:class:`SweepPoint` with ``cycle = None`` and the error message, not an
exception that loses the rest of the sweep.
"""

from __future__ import annotations

import itertools
import os
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, replace

import numpy as np

from kbm.errors import KBMError
from kbm.parameters.bound import bind

from numerics.executor import chunk, map_chunks
from numerics.cycles.result import LimitCycle
from numerics.cycles.shooting import limit_cycle
from numerics.flow import model_template
from numerics._show import params_text

__all__ = ["SweepPoint", "sweep", "grid"]


@dataclass(frozen=True, eq=False)
class SweepPoint:
    """One point of a sweep: its parameters and the cycle, or why there is none."""

    params: Mapping[str, object]
    cycle: LimitCycle | None
    error: str | None = None

    def __repr__(self) -> str:
        what = repr(self.cycle) if self.cycle is not None else f"failed: {self.error}"
        return f"SweepPoint({params_text(self.params)}: {what})"

    @property
    def success(self) -> bool:
        return self.cycle is not None and self.cycle.success


def grid(**axes: Sequence[object]) -> list[dict[str, object]]:
    """The Cartesian product of parameter axes, e.g. ``grid(beta=[0.5, 1], Delta=[0.1, 0.2])``.

    The last axis varies fastest.
    """
    names = list(axes)
    return [dict(zip(names, combo)) for combo in itertools.product(*axes.values())]


def _chunk(args) -> list[SweepPoint]:
    """A contiguous run of points in one process: one template, continuation of guesses."""
    model, fixed, pts, kwargs, continuation = args
    # one lambdified template for the whole chunk (the driven variant when v is fixed)
    template = model_template(bind(model, {"v": fixed["v"]} if "v" in fixed else None).model)
    out = []
    guess = kwargs.pop("guess", None)
    for p in pts:
        params = {**fixed, **p}
        try:
            cyc = limit_cycle(model, params, template=template, guess=guess, **kwargs)
            out.append(SweepPoint(params=p, cycle=_strip(cyc)))
            if continuation and cyc.success and cyc.stable:
                guess = (cyc.amplitude_max, cyc.period)
        except KBMError as exc:
            error = str(exc)
            # a continuation guess may be what failed: retry from the KBM/transient start
            if guess is not None and continuation:
                try:
                    cyc = limit_cycle(model, params, template=template, **kwargs)
                    out.append(SweepPoint(params=p, cycle=_strip(cyc)))
                    guess = (cyc.amplitude_max, cyc.period) if cyc.stable else None
                    continue
                except KBMError as exc2:
                    error = str(exc2)
            out.append(SweepPoint(params=p, cycle=None, error=error))
            guess = None
    return out


def _strip(c: LimitCycle) -> LimitCycle:
    """Drop the orbit samples (keeps inter-process traffic small)."""
    empty = np.empty(0)
    return replace(c, t=empty, x=empty, xdot=empty)


def sweep(model, points: Iterable[Mapping[str, object]], *,
          fixed: Mapping[str, object] | None = None, workers: int | None = None,
          progress: bool | None = None, chunksize: int | None = None,
          continuation: bool = True, executor: object | None = None,
          store: object | None = None, **cycle_kwargs) -> list[SweepPoint]:
    """Limit cycles for many parameter sets, on all cores, in input order.

    Parameters
    ----------
    model
        A built-in model name or an :class:`~kbm.model.builtins.Oscillator`.
    points
        Parameter sets (e.g. from :func:`grid`), merged over ``fixed``.
    workers
        Processes of the default local pool (default: the number of CPUs); 1 runs
        in this process.
    executor
        Where the chunks run (:func:`numerics.executor.map_chunks`): ``None`` (the
        local pool), a :class:`concurrent.futures.Executor` or a Dask
        :class:`distributed.Client`; the results are the same on each (the chunks are
        cut by the data, never by the worker count).
    store
        A :class:`numerics.store.PointStore` that keeps every finished chunk (and, with
        ``resume``, skips the chunks it holds).
    progress
        Show a progress bar on standard error (default: when more than 50 points).
    chunksize
        Points per task; a task runs its points in order in one process.
    continuation
        Start each point's Newton iteration from the previous (stable) cycle of
        its task: order the points so that neighbours are close (as
        :func:`grid` does).
    cycle_kwargs
        Passed to :func:`numerics.limit_cycle` (``rtol``, ``guess``, ...).

    Returns
    -------
    list of SweepPoint
        Failed points carry ``cycle = None`` and the error message.

    Examples
    --------
    >>> pts = sweep("vdp", grid(mu=[0.5, 1.0]), workers=1)
    >>> [round(p.cycle.period, 6) for p in pts]
    [6.380676, 6.663287]
    """
    pts = [dict(p) for p in points]
    fixed = dict(fixed or {})
    show = len(pts) > 50 if progress is None else progress
    workers = workers or os.cpu_count() or 1
    chunks = chunk(pts, chunksize)
    jobs = [(model, fixed, c, dict(cycle_kwargs), continuation) for c in chunks]

    def lost(job, exc):
        return [SweepPoint(params=p, cycle=None, error=f"task failed: {exc}") for p in job[2]]

    definition = repr(("numerics.cycles.sweep", model, sorted(fixed.items()), chunks,
                       sorted(cycle_kwargs.items()), continuation))
    return map_chunks(_chunk, jobs, executor=executor, workers=workers, progress=show,
                      desc=f"sweep {getattr(model, 'name', model)}", unit="cycle",
                      sizes=[len(c) for c in chunks], on_error=lost, store=store,
                      definition=definition)
