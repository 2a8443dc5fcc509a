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

and returns the chunks' results **in input order**, whatever the scheduling.  The chunks are
cut by the data (:func:`chunk`), never by the number of workers, so a run gives the same
bytes on every executor and worker count.  A chunk whose task fails as a whole
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

__all__ = ["map_chunks", "chunk", "connect", "is_dask_client", "SchedulerError", "Interrupted"]

T = TypeVar("T")

#: how long :func:`connect` waits for a scheduler by default, in seconds
CONNECT_TIMEOUT = 10.0


class SchedulerError(NumericsError):
    """A Dask scheduler could not be reached, or Dask is not installed."""


class Interrupted(KeyboardInterrupt):
    """A run stopped by Ctrl-C (SIGINT) or SIGTERM, with how far it got.

    Raised by :func:`map_chunks` after the local pool's worker processes are killed (and
    a Dask run's tasks cancelled); ``finished`` of ``total`` points were done.
    """

    def __init__(self, finished: int, total: int, unit: str = "point", kept=None):
        super().__init__(finished, total, unit, kept)
        self.finished, self.total, self.unit, self.kept = finished, total, unit, kept

    def __str__(self) -> str:
        plural = (self.unit[:-1] + "ies" if self.unit.endswith("y") and self.unit[-2:-1]
                  not in "aeiou" else self.unit + "s")
        head = f"{self.finished} of {self.total} {plural} were finished before the interruption"
        if self.kept is None:
            return f"{head}; they are not kept (run with --store FILE to keep them)"
        return f"{head}; they are kept in {self.kept} (run again with --resume to continue)"


def _worker_init() -> None:  # pragma: no cover - runs in the worker processes
    """A local pool's worker: it dies with its parent (Linux ``PR_SET_PDEATHSIG``), and it
    ignores Ctrl-C, which reaches the whole process group: the parent stops the run."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if sys.platform.startswith("linux"):
        import ctypes

        try:
            ctypes.CDLL("libc.so.6", use_errno=True).prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG
        except OSError:
            pass
        if os.getppid() == 1:  # the parent died before prctl took effect
            os._exit(1)


def _kill_pool(pool: ProcessPoolExecutor) -> None:
    """Kill a local pool's worker processes now (no waiting for running tasks)."""
    procs = list(getattr(pool, "_processes", {}).values())
    for proc in procs:
        try:
            proc.kill()
        except (OSError, AttributeError):
            pass
    pool.shutdown(wait=False, cancel_futures=True)
    for proc in procs:
        proc.join(timeout=1.0)


#: chunks a run is cut into by default (about 16: enough to balance a few workers)
CHUNKS = 16


def chunk(items: Sequence[T], size: int | None = None, largest: int = 64) -> list[list[T]]:
    """Cut ``items`` into contiguous chunks of ``size`` points, by the data alone.

    The default size is ``ceil(len(items) / CHUNKS)``, at most ``largest``: it depends on
    the number of points only, never on the workers or the executor, so that a chunk's
    continuation of guesses (and so every number) is the same wherever it runs.
    """
    n = len(items)
    if size is None:
        size = max(1, min(largest, -(-n // CHUNKS)))
    if isinstance(size, bool) or not isinstance(size, int) or size < 1:
        raise NumericsError(f"the chunk size must be an integer >= 1, got {size!r}")
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
               on_error: Callable[[Any, BaseException], list] | None = None,
               store: object | None = None, definition: str | None = None) -> list:
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
        without it the exception propagates.  Such a chunk is not stored.
    store, definition
        A :class:`numerics.store.PointStore` and the text that defines the run: each
        finished chunk is committed to the store, and the chunks it already holds for
        this definition (``resume``) are not computed again.

    Raises
    ------
    Interrupted
        On Ctrl-C or SIGTERM, after the workers are stopped, with the count of finished
        points (and the store that keeps them).
    """
    sizes = list(sizes) if sizes is not None else [1] * len(chunks)
    results: list = [None] * len(chunks)
    record = None
    if store is not None:
        if definition is None:
            raise NumericsError("a store needs the run's definition (definition=...)")
        record = store.run(definition, len(chunks))
        for i, res in record.load().items():
            if i < len(chunks):
                results[i] = res
    todo = [i for i in range(len(chunks)) if results[i] is None]
    done = [sum(sizes) - sum(sizes[i] for i in todo)]

    def settle(j: int, get: Callable[[], list]) -> None:
        i = todo[j]
        try:
            results[i] = get()
            if record is not None:
                record.save(i, results[i])
        except Exception as exc:  # noqa: BLE001 - a lost task becomes per-point failures
            if on_error is None:
                raise
            results[i] = on_error(chunks[i], exc)
        done[0] += sizes[i]
        bar.update(sizes[i])

    with tqdm(total=sum(sizes), initial=done[0], disable=not progress, file=sys.stderr,
              unit=unit, desc=desc or None, dynamic_ncols=True) as bar:
        workers = workers or os.cpu_count() or 1
        try:
            _dispatch(fn, [chunks[i] for i in todo], executor, workers, settle)
        except KeyboardInterrupt:
            raise Interrupted(done[0], sum(sizes), unit,
                              None if store is None else store.path) from None
    return [item for r in results for item in r]


def _dispatch(fn, chunks, executor, workers: int, settle) -> None:
    """Run the chunks where ``executor`` says; on Ctrl-C or SIGTERM the local pool's workers
    are killed and a Dask run's tasks cancelled before the interruption propagates."""
    if executor is None and (workers == 1 or len(chunks) <= 1):
        for i, c in enumerate(chunks):
            settle(i, lambda c=c: fn(c))
    elif is_dask_client(executor):
        from distributed import as_completed as dask_completed

        futures = executor.map(fn, list(chunks), pure=False)
        index = {f.key: i for i, f in enumerate(futures)}
        try:
            # the client's own loop: a client made by connect() is not the default one
            for f in dask_completed(futures, loop=executor.loop):
                settle(index[f.key], f.result)
        except KeyboardInterrupt:
            executor.cancel(futures)
            raise
    elif executor is None:
        pool = ProcessPoolExecutor(max_workers=workers, initializer=_worker_init)
        try:
            _run_pool(pool, fn, chunks, settle)
        except BaseException:
            _kill_pool(pool)
            raise
        pool.shutdown(wait=True)
    elif isinstance(executor, Executor):
        _run_pool(executor, fn, chunks, settle)
    else:
        raise NumericsError(f"executor must be None, a concurrent.futures.Executor or a "
                            f"dask.distributed Client, got {type(executor).__name__}")


def _run_pool(pool: Executor, fn, chunks, settle) -> None:
    futures = {pool.submit(fn, c): i for i, c in enumerate(chunks)}
    try:
        for f in as_completed(futures):
            settle(futures[f], f.result)
    except KeyboardInterrupt:
        for f in futures:
            f.cancel()
        raise
