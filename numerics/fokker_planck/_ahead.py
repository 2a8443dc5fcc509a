"""Solves of the stationary ladder started ahead in a second process (:class:`Ahead`): where
the ladders of :mod:`._stationary_orthonormal` and :mod:`._stationary_climb` will need two
solves that do not depend on each other (the check of a Hermite rung beside the next grid,
the climb's largest grid beside its coarser one and the rung above, the grid step of ``P(E)``
beside the evaluation of the others, :mod:`._energy_density`), the one is computed in a
forked copy of this process while this process computes the other.  The solves and their
order are those of the sequential ladder, the forked copy computes the same function of the
same numbers with the same libraries on one BLAS thread, and its solution comes back whole
(pickled), so the results are the same bits whatever the number of processes; a solve started
ahead that the ladder does not use is stopped.  A process may go on with a solve for later
after its first (``then`` of :meth:`Ahead.start`), or begin with one (``later``): the ladder
begins the climb's largest grid's step for ``P(E)`` so (the grid itself solved in the first
process), hands it on (:meth:`Ahead.hand_on`, in ``sol.refine``, :class:`Later`) and
:func:`._energy_density.energy_density_report` collects it (:meth:`Ahead.adopt`) or stops it;
a solve for later gives way to any solve the ladder starts after it.  The element ladder's
predicted answer comes back with its ``P(E)`` (``keep`` of :class:`Ahead`).

Why processes, not threads (measured, 2-core AMD EPYC, scipy 1.17, OpenBLAS 0.3.30):
``scipy.linalg.inv`` (the order-by-order factorisation's ``S^-1``, :mod:`._pentadiagonal`)
holds the GIL for the whole call, as do the f2py ``lapack.dgetri`` and ``blas.dgemm``
(``getrf``, ``getrs`` and numpy's products release it); two solves on two threads
(SEDF mu = 0.02, 90 x 300 and 90 x 360) took 20-30 s against 0.9 s one after the other,
their coefficients 1e-16 apart, under :func:`._blocks.one_blas_thread` (OpenBLAS limited
at run time; one solve alone in a second thread gives the same bits: the concurrent calls
differ); with ``OPENBLAS_NUM_THREADS=1`` from the start the same bits but 0.9-1.0 s, no
overlap.  The data a forked solve moves is its solution, ``N m`` numbers (2 MB at
258 x 1041), against seconds of work.

Not only solves: ``kbm noise`` computes its averaging and step pilot beside the whole
Fokker-Planck solve (:mod:`numerics.thermal._beside`), with an :class:`Alarm` (a failure
there stops this process's solve at once), ``raises`` (the exception comes back whole
instead of a second call here) and :meth:`Ahead.ready` (whether a result is back, without
waiting).

``KBM_FP_WORKERS`` (environment) sets the processes: 1 keeps every solve in this process
(the sequential ladder); default 2; never more than the CPUs this process may run on
(:func:`os.sched_getaffinity`), and 1 where ``fork`` is not available or in a daemonic
process (a :mod:`multiprocessing` pool's worker, which may not have children); a process
that cannot be started (out of memory or processes) leaves the solve to this process.
"""

from __future__ import annotations

import dataclasses
import multiprocessing
import os
import pickle
import signal
import threading
import warnings

from kbm.errors import ParameterError

__all__ = ["Ahead", "Alarm", "Alarmed", "ENV", "Handed", "Later", "fp_workers"]

#: the environment variable of the number of processes of the Fokker-Planck solves
ENV = "KBM_FP_WORKERS"
#: the fields of a solution that stay in this process (the potential is the caller's; the
#: refinements and caches are not the solve's)
_LOCAL = ("G", "refinements", "refine", "_cache")


def fp_workers(limit: int | None = None) -> int:
    """The processes the stationary ladder may use: ``$KBM_FP_WORKERS`` (default 2), at most
    the CPUs of this process's affinity and ``limit`` (a command's ``--workers``), 1
    without ``fork`` or in a daemonic process.

    Raises
    ------
    kbm.errors.ParameterError
        ``KBM_FP_WORKERS`` is not a whole number ``>= 1``.
    """
    raw = os.environ.get(ENV, "").strip()
    n = 2
    if raw:
        try:
            n = int(raw)
        except ValueError:
            n = 0
        if n < 1:
            raise ParameterError(f"{ENV}={raw!r}: give a whole number of processes >= 1 "
                                 "(1: every Fokker-Planck solve in this process)")
    if limit is not None:
        n = min(n, max(1, int(limit)))
    try:
        cpus = len(os.sched_getaffinity(0))
    except AttributeError:  # no affinity on this platform
        cpus = os.cpu_count() or 1
    if "fork" not in multiprocessing.get_all_start_methods() \
            or multiprocessing.current_process().daemon:  # a pool's worker: no children
        return 1
    return max(1, min(n, cpus))


class _Job:
    """One forked process: the keys of its solves, in the order it sends them, and the
    solutions read from its pipe before their key was asked for."""

    def __init__(self, proc, recv):
        self.proc, self.recv, self.got = proc, recv, {}

    def take(self, key):
        """``(status, cls, fields)`` of ``key``, reading the pipe in order."""
        while key not in self.got:
            k, *msg = self.recv.recv()
            self.got[k] = msg
        return self.got.pop(key)

    def stop(self) -> None:
        """End the process (at once when still solving) and close the pipe."""
        if self.proc.is_alive():
            self.proc.terminate()
        self.proc.join()
        self.recv.close()


class Handed:
    """A solve started by one :class:`Ahead` and handed on (:meth:`Ahead.hand_on`) for
    another to collect (:meth:`Ahead.adopt`): the ladder's grid step of ``P(E)``, started in
    the ladder's second process and collected by :func:`._energy_density.energy_density_report`.
    Stopped when adopted by none (:meth:`stop`; a daemonic process ends with this one)."""

    def __init__(self, job: _Job, key):
        self.job, self.key = job, key

    def claim(self):
        """This once the job (``None`` after: its solution is collected once)."""
        job, self.job = self.job, None
        return job

    def stop(self) -> None:
        job = self.claim()
        if job is not None:
            job.stop()

    def __del__(self):
        try:
            self.stop()
        except Exception:  # at interpreter exit the process may be gone already
            pass


class Later:
    """``func()`` (a solve for later, ``sol.refine``) with the process that may be solving
    it already (:class:`Handed`, or ``None``); called, it solves here (the same call)."""

    def __init__(self, func, handed: Handed | None = None):
        self.func, self.handed = func, handed

    def __call__(self):
        return self.func()


class Ahead:
    """Calls of ``func`` (returning a :class:`.KramersSolution`) started ahead in forked
    processes, at most ``workers - 1`` at a time, and collected by key.

    A process may go on with further calls after the first (``then`` of :meth:`start`,
    solves for later), or a call may be one for later itself (``later`` of :meth:`start`:
    the grid step of ``P(E)`` of the climb's largest grid); those give way to a new
    :meth:`start` and may be handed on to another :class:`Ahead` (:meth:`hand_on`,
    :meth:`adopt`).

    Parameters
    ----------
    func : callable
        The solve (any call that returns a dataclass).
    workers : int, optional
        Default :func:`fp_workers`; 1 starts nothing (:meth:`result` calls ``func``).
    alarm : int, optional
        A signal the forked process sends this one when its call raises
        (:class:`Alarm`: this process stops what it is doing and asks for the result).
    raises : bool
        :meth:`result` raises the forked call's exception, sent back (pickled), instead
        of calling ``func`` again here (where it does not survive pickling, the call is
        made again).
    keep : tuple
        The solution's cache entries sent back with it: keys ``(name, ...)``, ``name`` in it.
    **local
        The fields of the solution that are not sent back (the potential ``G``).
    """

    def __init__(self, func, workers: int | None = None, *, alarm: int | None = None,
                 raises: bool = False, keep: tuple = (), **local):
        self.func = func
        self.workers = fp_workers() if workers is None else int(workers)
        self.local = local
        self.alarm, self.raises, self.keep = alarm, raises, tuple((k,) for k in keep)
        self._jobs: dict = {}  # key -> _Job (a process may hold several keys)
        self._later: set = set()  # the keys for later (``then``, ``later``: they give way)
        self._names: dict = {}  # key -> the key its process sends it under (adopted)

    def _busy(self) -> int:
        return len({id(j) for j in self._jobs.values()})

    def start(self, key, *args, replace: bool = False, then=(), later: bool = False,
              **kwargs) -> bool:
        """``func(*args, **kwargs)`` in a forked process under ``key``, when a worker is
        free (``replace``: the other keys' processes stopped first; a process left with
        solves for later alone is stopped) and ``key`` is not running; whether it
        started.  ``then``: ``(key, args, kwargs)`` of calls the process makes after,
        for later (each sent as it is solved, while the next is solved); ``later``:
        ``key`` itself is a solve for later (it gives way to a new start as those do)."""
        if replace:
            for k in [k for k in self._jobs if k != key]:
                self.cancel(k)
        if self.workers < 2 or key in self._jobs:
            return False
        for job in {id(j): j for j in self._jobs.values()}.values():
            if self._busy() >= self.workers - 1 and \
                    all(k in self._later for k, j in self._jobs.items() if j is job):
                self._drop(job)  # solves for later give way to one needed now
        if self._busy() >= self.workers - 1:
            return False
        ctx = multiprocessing.get_context("fork")
        recv, send = ctx.Pipe(duplex=False)
        func, alarm, raises, keep = self.func, self.alarm, self.raises, self.keep
        calls = [(key, args, kwargs), *then]

        def child():
            # stopped by the parent alone: SIGTERM ends it at once (not the parent's handler,
            # kbm's CLI turns it into KeyboardInterrupt), Ctrl-C reaches the parent, which
            # stops it (as numerics.executor's workers)
            signal.signal(signal.SIGTERM, signal.SIG_DFL)
            signal.signal(signal.SIGINT, signal.SIG_IGN)
            recv.close()  # the parent's end: were it held here too, a write would never fail
            sender = None
            for k, a, kw in calls:
                failed = False
                try:
                    sol = func(*a, **kw)
                    out = (k, "ok", type(sol), {f.name: getattr(sol, f.name)
                                                for f in dataclasses.fields(sol)
                                                if f.name not in _LOCAL})
                    if keep:  # the cache's entries asked for (a key's first item in keep)
                        out[3]["_cache"] = {c: sol._cache[c] for c in sol._cache if c[:1] in keep}
                except BaseException as exc:  # the caller solves again here and raises
                    out, failed = (k, "error", repr(exc), _portable(exc) if raises else None), True
                if sender is not None:
                    sender.join()
                # sent beside the next call: the pipe holds less than a solution, and the
                # parent reads it only when it asks for it
                sender = threading.Thread(target=send.send, args=(out,), daemon=True)
                sender.start()
                if failed and alarm is not None:
                    sender.join()  # the error is in the pipe before the parent is told
                    os.kill(os.getppid(), alarm)
                    break  # the calls after it are the parent's to make or not
            sender.join()
            send.close()

        proc = ctx.Process(target=child, daemon=True)
        with warnings.catch_warnings():  # Python >= 3.12 warns of fork with threads alive
            warnings.simplefilter("ignore", DeprecationWarning)
            try:
                proc.start()
            except (OSError, AssertionError):  # no process to be had: solved here instead
                recv.close()
                send.close()
                return False
        send.close()
        job = _Job(proc, recv)
        for k, _, _ in calls:
            self._jobs[k] = job
        self._later.update(k for k, _, _ in then)
        if later:
            self._later.add(key)
        return True

    def running(self, key) -> bool:
        """Whether ``key`` was started and not collected."""
        return key in self._jobs

    def ready(self, key) -> bool:
        """Whether the solution of ``key`` (started, not collected) has come back: the
        pipe read as far as it holds, without waiting."""
        job = self._jobs.get(key)
        if job is None:
            return False
        name = self._names.get(key, key)
        try:
            while name not in job.got and job.recv.poll():
                k, *msg = job.recv.recv()
                job.got[k] = msg
        except (EOFError, OSError):  # the process is gone: result() calls here
            return True
        return name in job.got

    def result(self, key, *args, **kwargs):
        """The solution of ``key``: from its process when started (waiting for it), else
        ``func(*args, **kwargs)`` here (also when the process failed: the same call, so
        the same solution or exception)."""
        job = self._jobs.pop(key, None)
        self._later.discard(key)
        name = self._names.pop(key, key)
        if job is not None:
            try:
                status, cls, fields = job.take(name)
            except (EOFError, OSError):
                status = "lost"
            except BaseException:  # Ctrl-C while waiting: the child may be writing into a
                self._drop(job)    # full pipe, which a join alone would wait on for ever
                raise
            if job not in self._jobs.values():
                job.stop()  # done: its last solution read
            if status == "ok":
                return cls(**fields, **self.local)
            if status == "error" and isinstance(fields, BaseException):
                raise fields
        return self.func(*args, **kwargs)

    def hand_on(self, key) -> Handed | None:
        """The process solving ``key`` (its other keys dropped), no longer this one's to
        stop, for another :class:`Ahead` to :meth:`adopt`; ``None`` when not running."""
        job = self._jobs.get(key)
        if job is None:
            return None
        name = self._names.get(key, key)
        self._forget(job)
        return Handed(job, name)

    def adopt(self, key, handed: Handed | None) -> bool:
        """Collect ``handed`` (:meth:`hand_on`) as ``key``: :meth:`result` waits for it,
        :meth:`cancel` stops it; whether there was one (it is collected once)."""
        job = None if handed is None or key in self._jobs else handed.claim()
        if job is None:
            return False
        self._jobs[key] = job
        self._names[key] = handed.key
        return True

    def _forget(self, job: _Job) -> None:
        """Every key of ``job`` removed (its process left running)."""
        for k in [k for k, j in self._jobs.items() if j is job]:
            del self._jobs[k]
            self._later.discard(k)
            self._names.pop(k, None)

    def _drop(self, job: _Job) -> None:
        self._forget(job)
        job.stop()

    def cancel(self, key=None) -> None:
        """Stop the process of ``key`` (and its solves for later; default: every one)."""
        for k in [key] if key is not None else list(self._jobs):
            job = self._jobs.get(k)
            if job is not None:
                self._drop(job)

    def __enter__(self) -> Ahead:
        return self

    def __exit__(self, *exc) -> None:
        self.cancel()


def _portable(exc: BaseException) -> BaseException | None:
    """``exc`` when it comes back whole through pickle (its class and message), else
    ``None`` (:meth:`Ahead.result` then calls again)."""
    try:
        back = pickle.loads(pickle.dumps(exc))
    except Exception:
        return None
    return exc if type(back) is type(exc) and str(back) == str(exc) else None


class Alarmed(Exception):
    """Raised in this process by :class:`Alarm` when a forked call failed: the caller
    stops its own work and collects the failure (:meth:`Ahead.result`)."""


class Alarm:
    """``SIGUSR1`` from a forked call that failed (:class:`Ahead`'s ``alarm``), raised
    as :class:`Alarmed` here while armed, ignored once :meth:`disarm` is called (the
    caller is collecting the result).  A context manager: ``signum`` is ``None`` (no
    alarm) outside the main thread or without ``SIGUSR1``; the previous handler comes
    back on exit, after the :class:`Ahead` inside it has stopped its processes."""

    def __init__(self):
        self.signum, self.armed, self._old = None, True, None

    def __enter__(self) -> Alarm:
        signum = getattr(signal, "SIGUSR1", None)
        if signum is not None and threading.current_thread() is threading.main_thread():
            self._old = signal.signal(signum, self._handler)
            self.signum = signum
        return self

    def _handler(self, signum, frame) -> None:
        if self.armed:
            self.armed = False
            raise Alarmed("a call started ahead failed")

    def disarm(self) -> None:
        self.armed = False

    def __exit__(self, *exc) -> None:
        if self.signum is not None:
            signal.signal(self.signum, signal.SIG_DFL if self._old is None else self._old)
