"""Independent tasks on any executor: this process, a local process pool, or a Dask cluster.

A sweep (limit cycles over a grid, friction laws over ``(v, Delta, beta)``) is cut into
*chunks*, runs of neighbouring points that one task computes in order (one compiled
model, continuation of guesses, small per-task overhead).  :func:`map_chunks` sends the
chunks to

- this process (``workers=1``, or a single chunk);
- a local :class:`concurrent.futures.ProcessPoolExecutor` (the default), made and shut
  down here;
- any :class:`concurrent.futures.Executor` the caller made (and will shut down);
- a :class:`distributed.Client` of Dask (the optional extra ``kbm[dask]``): a
  ``LocalCluster`` or a running scheduler (:func:`connect`),

and returns the chunks' results **in input order**, whatever the scheduling: the same
chunks give the same numbers on every executor.  A chunk whose task fails as a whole
(a worker lost, an unpicklable result) does not lose the others: ``on_error(chunk,
exc)`` turns it into per-point failures.  Progress is a :mod:`tqdm` bar (terminal or
notebook) counting points as chunks complete.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Callable, Sequence
from concurrent.futures import Executor, ProcessPoolExecutor, as_completed
from typing import Any, TypeVar

from tqdm.auto import tqdm

from numerics.errors import NumericsError

__all__ = ["map_chunks", "chunk", "connect", "is_dask_client", "SchedulerError"]

T = TypeVar("T")

#: how long :func:`connect` waits for a scheduler by default, in seconds
CONNECT_TIMEOUT = 10.0


class SchedulerError(NumericsError):
    """A Dask scheduler could not be reached, or Dask is not installed."""


def chunk(items: Sequence[T], workers: int, size: int | None = None,
          largest: int = 64) -> list[list[T]]:
    """Cut ``items`` into contiguous chunks: about four per worker, at most ``largest``
    points each (or ``size`` points each when given)."""
    n = len(items)
    if size is None:
        size = max(1, min(largest, -(-n // (4 * max(1, workers)))))
    if size < 1:
        raise NumericsError(f"the chunk size must be >= 1, got {size}")
    return [list(items[i:i + size]) for i in range(0, n, size)]


def is_dask_client(executor: object) -> bool:
    """Whether ``executor`` is a :class:`distributed.Client` (duck-typed: no import)."""
    return type(executor).__module__.split(".")[0] == "distributed" and hasattr(executor, "map")


def connect(address: str, timeout: float = CONNECT_TIMEOUT):
    """A :class:`distributed.Client` of the running Dask scheduler at ``address``.

    Raises
    ------
    SchedulerError
        If Dask is not installed (``pip install 'kbm[dask]'``) or no scheduler answers
        at ``address`` within ``timeout`` seconds.
    """
    try:
        from distributed import Client
    except ImportError:
        raise SchedulerError("a Dask scheduler needs the optional extra: "
                             "pip install 'kbm[dask]' (dask.distributed)") from None
    if not (isinstance(address, str) and address.strip()):
        raise SchedulerError(f"the scheduler address must be a string such as "
                             f"tcp://host:8786, got {address!r}")
    try:
        return Client(address, timeout=f"{float(timeout)}s", set_as_default=False)
    except (OSError, TimeoutError, ValueError, TypeError) as exc:
        raise SchedulerError(f"no Dask scheduler answered at {address} within {timeout:g} s "
                             f"({type(exc).__name__}: {' '.join(str(exc).split()[:20])}); "
                             "start one with 'dask scheduler' or run without a scheduler "
                             "(local processes)") from None


def map_chunks(fn: Callable[[Any], list], chunks: Sequence[Any], *,
               executor: Executor | object | None = None, workers: int | None = None,
               progress: bool = False, desc: str = "", unit: str = "point",
               sizes: Sequence[int] | None = None,
               on_error: Callable[[Any, BaseException], list] | None = None) -> list:
    """``[fn(c) for c in chunks]`` (concatenated) on an executor, in input order.

    Parameters
    ----------
    fn
        A picklable (module-level) function of one chunk returning a list (one item per
        point).
    chunks
        The tasks' arguments.
    executor
        ``None`` (a local process pool of ``workers`` processes, or this process when
        ``workers == 1`` or there is one chunk), a :class:`concurrent.futures.Executor`,
        or a Dask :class:`distributed.Client`.
    workers
        Processes of the default pool (default: the number of CPUs).
    progress, desc, unit
        A :mod:`tqdm` bar of points (``sizes[i]`` points per chunk, 1 by default).
    on_error
        ``on_error(chunk, exc)`` -> the list that stands for a chunk whose task raised;
        without it the exception propagates.
    """
    sizes = list(sizes) if sizes is not None else [1] * len(chunks)
    results: list = [None] * len(chunks)

    def settle(i: int, get: Callable[[], list]) -> None:
        try:
            results[i] = get()
        except Exception as exc:  # noqa: BLE001 - a lost task becomes per-point failures
            if on_error is None:
                raise
            results[i] = on_error(chunks[i], exc)
        bar.update(sizes[i])

    with tqdm(total=sum(sizes), disable=not progress, file=sys.stderr, unit=unit,
              desc=desc or None, dynamic_ncols=True) as bar:
        workers = workers or os.cpu_count() or 1
        if executor is None and (workers == 1 or len(chunks) <= 1):
            for i, c in enumerate(chunks):
                settle(i, lambda c=c: fn(c))
        elif is_dask_client(executor):
            from distributed import as_completed as dask_completed

            futures = executor.map(fn, list(chunks), pure=False)
            index = {f.key: i for i, f in enumerate(futures)}
            # the client's own loop: a client made by connect() is not the default one
            for f in dask_completed(futures, loop=executor.loop):
                settle(index[f.key], f.result)
        elif executor is None:
            with ProcessPoolExecutor(max_workers=workers) as pool:
                _run_pool(pool, fn, chunks, settle)
        elif isinstance(executor, Executor):
            _run_pool(executor, fn, chunks, settle)
        else:
            raise NumericsError(f"executor must be None, a concurrent.futures.Executor or a "
                                f"dask.distributed Client, got {type(executor).__name__}")
    return [item for r in results for item in r]


def _run_pool(pool: Executor, fn, chunks, settle) -> None:
    futures = {pool.submit(fn, c): i for i, c in enumerate(chunks)}
    for f in as_completed(futures):
        settle(futures[f], f.result)
