"""Many limit cycles at once: a parameter sweep over both cores, with a progress bar.

:func:`sweep` maps :func:`numerics.limit_cycle` over a list (or grid) of
parameter sets with a process pool.  Results come back in the order of the
input, whatever the scheduling, and a failed point is a
:class:`SweepPoint` with ``cycle = None`` and the error message, not an
exception that loses the rest of the sweep.
"""

from __future__ import annotations

import itertools
import os
import sys
from collections.abc import Iterable, Mapping, Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, replace

import numpy as np
from tqdm import tqdm

from kbm.errors import KBMError
from kbm.models import bind

from numerics.cycles.result import LimitCycle
from numerics.cycles.shooting import limit_cycle
from numerics.flow import model_template

__all__ = ["SweepPoint", "sweep", "grid"]


@dataclass(frozen=True, eq=False)
class SweepPoint:
    """One point of a sweep: its parameters and the cycle, or why there is none."""

    params: Mapping[str, object]
    cycle: LimitCycle | None
    error: str | None = None

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
          continuation: bool = True, **cycle_kwargs) -> list[SweepPoint]:
    """Limit cycles for many parameter sets, on all cores, in input order.

    Parameters
    ----------
    model
        A built-in model name or an :class:`~kbm.models.Oscillator`.
    points
        Parameter sets (e.g. from :func:`grid`), merged over ``fixed``.
    workers
        Processes (default: the number of CPUs); 1 runs in this process.
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
    total = len(pts)
    show = total > 50 if progress is None else progress
    workers = workers or os.cpu_count() or 1
    size = chunksize or max(1, min(64, -(-total // (4 * workers))))
    chunks = [pts[i:i + size] for i in range(0, total, size)]
    jobs = [(model, fixed, c, dict(cycle_kwargs), continuation) for c in chunks]
    out: list[SweepPoint] = []
    with tqdm(total=total, disable=not show, file=sys.stderr, unit="cycle",
              desc=f"sweep {getattr(model, 'name', model)}") as bar:
        if workers == 1 or len(chunks) == 1:
            for job in jobs:
                res = _chunk(job)
                out.extend(res)
                bar.update(len(res))
            return out
        with ProcessPoolExecutor(max_workers=workers) as ex:
            for res in ex.map(_chunk, jobs):
                out.extend(res)
                bar.update(len(res))
    return out
