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
import time
from collections.abc import Iterable, Mapping, Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass

from kbm.errors import KBMError

from .cycle import LimitCycle, limit_cycle

__all__ = ["SweepPoint", "sweep", "grid"]


@dataclass(frozen=True)
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


def _one(args) -> SweepPoint:
    model, fixed, p, kwargs = args
    params = {**fixed, **p}
    try:
        cyc = limit_cycle(model, params, **kwargs)
        return SweepPoint(params=p, cycle=_strip(cyc))
    except KBMError as exc:
        return SweepPoint(params=p, cycle=None, error=str(exc))


def _strip(c: LimitCycle) -> LimitCycle:
    """Drop the orbit samples (keeps inter-process traffic small)."""
    from dataclasses import replace
    import numpy as np

    empty = np.empty(0)
    return replace(c, t=empty, x=empty, xdot=empty)


def _bar(done: int, total: int, t0: float) -> None:
    frac = done / total
    n = int(30 * frac)
    el = time.perf_counter() - t0
    eta = el / frac - el if frac > 0 else float("nan")
    sys.stderr.write(f"\r[{'#' * n}{'.' * (30 - n)}] {done}/{total}  {el:6.1f} s  "
                     f"eta {eta:6.1f} s")
    sys.stderr.flush()
    if done == total:
        sys.stderr.write("\n")


def sweep(model, points: Iterable[Mapping[str, object]], *,
          fixed: Mapping[str, object] | None = None, workers: int | None = None,
          progress: bool | None = None, chunksize: int | None = None,
          **cycle_kwargs) -> list[SweepPoint]:
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
    [6.38502, 6.663287]
    """
    pts = [dict(p) for p in points]
    fixed = dict(fixed or {})
    jobs = [(model, fixed, p, cycle_kwargs) for p in pts]
    total = len(jobs)
    show = total > 50 if progress is None else progress
    workers = workers or os.cpu_count() or 1
    t0 = time.perf_counter()
    out: list[SweepPoint] = []
    if workers == 1 or total < 4:
        for i, job in enumerate(jobs, 1):
            out.append(_one(job))
            if show:
                _bar(i, total, t0)
        return out
    chunksize = chunksize or max(1, min(64, total // (8 * workers) or 1))
    with ProcessPoolExecutor(max_workers=workers) as ex:
        for i, res in enumerate(ex.map(_one, jobs, chunksize=chunksize), 1):
            out.append(res)
            if show and (i % max(1, total // 200) == 0 or i == total):
                _bar(i, total, t0)
    return out
