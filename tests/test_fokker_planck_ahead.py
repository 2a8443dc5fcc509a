"""The stationary ladder's solves started ahead in a second process
(numerics/fokker_planck/_ahead.py; issue 36: "the Fokker-Planck route ... in seconds"):
the moments, ``P(E)`` and the stated changes are the same bits with one process
(``KBM_FP_WORKERS=1``, the sequential ladder) and two, and they are right.

Reference: for linear damping the stationary density is Boltzmann's ``exp(-H/kT)/Z``
(Gibbs; Risken, *The Fokker-Planck Equation*, sec. 10.1), so ``<x^2>`` is the quadrature
of ``x^2 exp(-G/kT)`` (:func:`numerics.escape.boltzmann_moment`) and ``<v^2> = kT``; the
CDC is solved here in the orthonormal Hermite functions (``basis="orthonormal"``, the
ladder of the nonlinear dampings), folded, whose ladder starts solves ahead.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import numerics.fokker_planck._ahead as ahead_mod
import numerics.fokker_planck._energy_density as ed
from kbm.errors import ParameterError
from kbm.model.conservative import split_conservative
from numerics.escape import boltzmann_moment
from numerics.fokker_planck import stationary_kramers
from numerics.fokker_planck._ahead import Ahead, Later, fp_workers
from numerics.fokker_planck._stationary_solve import orthonormal_stationary

CDC = {"mu": 0.15, "Delta": 2, "lam": 1.3, "Omega": 1}
D = 0.0525  # kT = 0.35


class _Counted:
    """Counts the solutions :class:`Ahead` collected from its processes."""

    def __init__(self, monkeypatch):
        self.collected = 0
        result = Ahead.result

        def counted(inner, key, *args, **kwargs):
            self.collected += inner.running(key)
            return result(inner, key, *args, **kwargs)

        monkeypatch.setattr(Ahead, "result", counted)


def _solve(monkeypatch, workers: int, max_cost: float):
    monkeypatch.setenv(ahead_mod.ENV, str(workers))
    return stationary_kramers("cdc", CDC, D, basis="orthonormal", max_cost=max_cost)


def _same(a, b) -> bool:
    """The same bits: coefficients, points, moments, stated changes and refinements."""
    pairs = len(a.refinements) == len(b.refinements) and all(
        np.array_equal(p.coef, q.coef) for pa, pb in zip(a.refinements, b.refinements)
        for p, q in zip(pa, pb))
    return (np.array_equal(a.coef, b.coef) and np.array_equal(a.x, b.x) and pairs
            and (a.x2, a.v2, a.residual, a.sigma) == (b.x2, b.v2, b.residual, b.sigma)
            and np.array_equal([a.hermite_change, a.chebyshev_change],
                               [b.hermite_change, b.chebyshev_change], equal_nan=True))


@pytest.mark.slow
def test_ladder_in_two_processes_is_the_sequential_ladder_and_boltzmann(monkeypatch):
    """CDC at kT = 0.35 in the orthonormal functions: with two processes the ladder takes
    solves from the second (counted), and the solution is the one-process solution to the
    bit; its ``<x^2>`` is Boltzmann's quadrature within the stated change and ``<v^2>``
    is ``kT``."""
    if fp_workers() < 2 and len(_affinity()) < 2:
        pytest.skip("one CPU: the ladder never starts a second process")
    counted = _Counted(monkeypatch)
    two = _solve(monkeypatch, 2, 5e6)
    assert counted.collected >= 1
    collected = counted.collected
    one = _solve(monkeypatch, 1, 5e6)
    assert counted.collected == collected  # none from the sequential ladder
    assert _same(one, two)
    ref = boltzmann_moment(split_conservative("cdc", CDC), D / CDC["mu"])
    stated = max(two.hermite_change, 1e-9)
    assert two.x2 == pytest.approx(ref, rel=10 * stated)
    assert two.v2 == pytest.approx(D / CDC["mu"], rel=10 * stated)


@pytest.mark.slow
def test_energy_density_grid_step_ahead_is_the_sequential_one(monkeypatch):
    """``P(E)``'s grid step (``sol.refine``) started beside the evaluation that decides it
    (here always: :data:`._energy_density.REFINE_AHEAD` 0) gives the report of the
    sequential run to the bit."""
    sol = _solve(monkeypatch, 1, 2e6)
    assert sol.refine is not None
    monkeypatch.setattr(ed, "REFINE_AHEAD", 0.0)
    monkeypatch.setattr(ed, "SIX_DIGITS", 0.0)  # the step is taken
    monkeypatch.setenv(ahead_mod.ENV, "1")
    seq = ed.energy_density_report(sol)
    fresh = _solve(monkeypatch, 1, 2e6)  # no cached P: the refine solved again
    monkeypatch.setenv(ahead_mod.ENV, "2")
    counted = _Counted(monkeypatch)
    par = ed.energy_density_report(fresh)
    assert counted.collected == (1 if fp_workers() > 1 else 0)
    assert par == seq


def _affinity():
    try:
        import os

        return os.sched_getaffinity(0)
    except AttributeError:
        return {0}


def test_ahead_returns_the_direct_solution_and_stops_the_unused():
    """A solve collected from the second process is the direct call's to the bit (a small
    SEDF solve, 24 functions x 64 intervals); one not collected is stopped."""
    split = split_conservative("sedf", {"mu": 0.1, "Delta": 3, "beta": 1, "Omega": 1,
                                        "lam": 1})
    G = split.numpy_functions()[2]
    args = (split, 0.05, 0.4, 6.0, 24, 64, G, 1.0)
    direct = orthonormal_stationary(*args)
    with Ahead(orthonormal_stationary, workers=2, G=G) as ahead:
        assert ahead.start("a", *args)
        assert not ahead.start("b", *args)  # one worker beside this process
        got = ahead.result("a", *args)
        assert ahead.start("c", *args)
        proc = ahead._jobs["c"].proc
    assert not proc.is_alive() and not ahead.running("c")
    assert np.array_equal(got.coef, direct.coef) and got.residual == direct.residual
    assert got.G is G and math.isfinite(got.x2)


def test_workers_setting(monkeypatch):
    """``KBM_FP_WORKERS``: 1 starts nothing; never more than the affinity's CPUs; a bad
    value is refused with what to give."""
    monkeypatch.setenv(ahead_mod.ENV, "1")
    assert fp_workers() == 1
    assert not Ahead(orthonormal_stationary).start("a")
    monkeypatch.setenv(ahead_mod.ENV, "64")
    monkeypatch.setattr(ahead_mod.os, "sched_getaffinity", lambda pid: {0}, raising=False)
    assert fp_workers() == 1
    for bad in ("0", "two", "-1"):
        monkeypatch.setenv(ahead_mod.ENV, bad)
        with pytest.raises(ParameterError, match="KBM_FP_WORKERS"):
            fp_workers()


def _workers_in_pool_worker(_):
    return fp_workers()


def test_no_second_process_from_a_daemonic_worker(monkeypatch):
    """A :class:`multiprocessing.pool.Pool` worker is daemonic and may not start children
    (``AssertionError: daemonic processes are not allowed to have children``): the ladder
    there solves in its own process."""
    import multiprocessing

    monkeypatch.setenv(ahead_mod.ENV, "2")
    monkeypatch.setattr(ahead_mod.os, "sched_getaffinity", lambda pid: {0, 1}, raising=False)
    assert fp_workers() == 2
    with multiprocessing.get_context("fork").Pool(1) as pool:
        assert pool.map(_workers_in_pool_worker, [0]) == [1]


def test_workers_bound_the_processes(monkeypatch):
    """``workers`` (``kbm noise --workers``) bounds the processes of the ladder and of P(E)'s
    grid step: with 1 nothing is started (the sequential ladder's bits), with the default
    the second process is used (two CPUs here)."""
    monkeypatch.setenv(ahead_mod.ENV, "2")
    monkeypatch.setattr(ahead_mod.os, "sched_getaffinity", lambda pid: {0, 1}, raising=False)
    assert fp_workers(1) == 1 and fp_workers(8) == 2 and fp_workers() == 2
    made = []
    init = Ahead.__init__

    def recorded(self, func, workers=None, **local):
        init(self, func, workers, **local)
        made.append(self.workers)

    monkeypatch.setattr(Ahead, "__init__", recorded)
    one = stationary_kramers("cdc", CDC, D, basis="orthonormal", max_cost=4e5, workers=1)
    assert made and set(made) == {1}
    made.clear()
    two = stationary_kramers("cdc", CDC, D, basis="orthonormal", max_cost=4e5)
    assert set(made) == {2} and _same(one, two)


@dataclasses.dataclass
class _Big:
    values: np.ndarray


def _slow_big():
    import time

    time.sleep(0.6)
    return _Big(np.zeros(300_000))  # 2.4 MB: more than a pipe holds


def test_interrupt_while_waiting_stops_the_child():
    """Ctrl-C while :meth:`Ahead.result` waits: the exception reaches the caller at once and
    the forked solve is stopped.  (It hung: the child blocked writing its 2.4 MB solution into
    the pipe, which it held open itself, while the parent's ``join`` waited for it.)"""
    import signal
    import time

    class _Ctrl(Exception):
        pass

    class _Hung(Exception):
        pass

    calls = []

    def interrupt(signum, frame):  # first Ctrl-C, then (5 s on) the end of a hang
        calls.append(signum)
        if len(calls) == 1:
            signal.setitimer(signal.ITIMER_REAL, 5.0)
            raise _Ctrl
        raise _Hung

    ahead = Ahead(_slow_big, workers=2)
    if not ahead.start("big"):
        pytest.skip("no second process here")
    proc = ahead._jobs["big"].proc
    old = signal.signal(signal.SIGALRM, interrupt)
    t0 = time.monotonic()
    try:
        signal.setitimer(signal.ITIMER_REAL, 0.2)
        with pytest.raises(_Ctrl):
            ahead.result("big")
        assert time.monotonic() - t0 < 5
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)
        ahead.cancel()
    proc.join(5)
    assert not proc.is_alive()


def _small_solve_and_step():
    """``(G, args, step, direct)``: a small SEDF solve's arguments (mu = 0.1, Delta = 3,
    D = 0.05, 24 functions x 64 intervals), its grid step's (80 intervals) and that
    step's direct solution (this process, one call)."""
    split = split_conservative("sedf", {"mu": 0.1, "Delta": 3, "beta": 1, "Omega": 1,
                                        "lam": 1})
    G = split.numpy_functions()[2]
    args = (split, 0.05, 0.4, 6.0, 24, 64, G, 1.0)
    step = args[:5] + (80,) + args[6:]
    return G, args, step, orthonormal_stationary(*step)


def test_solve_for_later_handed_on_is_the_direct_solution():
    """A process goes on with a solve for later (``then``; the ladder's grid step of P(E)):
    handed on (:meth:`Ahead.hand_on`) and adopted by another :class:`Ahead` (as
    :func:`._energy_density.energy_density_report` does), its solution is the direct
    call's to the bit; a new start needing the worker stops a solve for later, and one
    handed on but never adopted is stopped with its holder."""
    G, args, step, direct = _small_solve_and_step()
    with Ahead(orthonormal_stationary, workers=2, G=G) as ahead:
        if not ahead.start("a", *args, then=[("later", step, {})]):
            pytest.skip("no second process here")
        first = ahead.result("a", *args)
        assert ahead.running("later")
        handed = ahead.hand_on("later")
        assert not ahead.running("later")
    assert handed.job.proc.is_alive() or handed.job.proc.exitcode == 0  # not stopped
    with Ahead(lambda: orthonormal_stationary(*step), workers=2, G=G) as other:
        assert other.adopt("refine", handed) and not other.adopt("again", handed)
        got = other.result("refine")
    assert np.array_equal(got.coef, direct.coef) and got.residual == direct.residual
    assert np.array_equal(first.coef, orthonormal_stationary(*args).coef)
    with Ahead(orthonormal_stationary, workers=2, G=G) as ahead:
        assert ahead.start("a", *args, then=[("later", step, {})])
        ahead.result("a", *args)
        proc = ahead._jobs["later"].proc
        assert ahead.start("b", *args)  # the solve for later gives way
        assert not proc.is_alive() and not ahead.running("later")
        ahead.result("b", *args)
        assert ahead.start("c", *args, then=[("later", step, {})])
        ahead.result("c", *args)
        kept = Later(lambda: None, ahead.hand_on("later"))
        proc = kept.handed.job.proc
    del kept  # never adopted: stopped
    proc.join(5)
    assert not proc.is_alive()


def test_solve_started_for_later_alone_gives_way_and_is_handed_on_whole():
    """A solve started alone as one for later (``later=True``: the ladder's grid step of
    P(E), begun before the climb's other solves, which this process makes): its solution,
    handed on and adopted, is the direct call's to the bit (the same function of the same
    numbers), and a new start needing the worker stops it as it stops the solves of
    ``then``."""
    G, args, step, direct = _small_solve_and_step()
    with Ahead(orthonormal_stationary, workers=2, G=G) as ahead:
        if not ahead.start("later", *step, later=True):
            pytest.skip("no second process here")
        here = orthonormal_stationary(*args)  # this process's solve beside it
        handed = ahead.hand_on("later")
    with Ahead(lambda: orthonormal_stationary(*step), workers=2, G=G) as other:
        assert other.adopt("refine", handed)
        got = other.result("refine")
    assert np.array_equal(got.coef, direct.coef) and got.residual == direct.residual
    assert np.array_equal(here.coef, orthonormal_stationary(*args).coef)
    with Ahead(orthonormal_stationary, workers=2, G=G) as ahead:
        assert ahead.start("later", *step, later=True)
        proc = ahead._jobs["later"].proc
        assert ahead.start("b", *args)  # the solve for later gives way
        assert not proc.is_alive() and not ahead.running("later")
        assert np.array_equal(ahead.result("b", *args).coef, here.coef)


@pytest.mark.slow
def test_grid_step_of_p_started_in_the_ladder_is_the_sequential_report(monkeypatch):
    """SEDF at rest, Delta = 3, mu = 0.01, D = 0.005, kbm noise's budget (the ladder
    climbs to 258 x 1040): with ``refine_ahead`` and two processes the climb's largest
    grid's process goes on with P(E)'s grid step (258 x 1302), handed on in ``refine`` and
    collected by the report, which is the one-process report to the bit, with the grid
    step taken (the stated change of the peak below six digits only with it, 2.9e-7 of
    the moments; :func:`._energy_density.energy_density_report`)."""
    if len(_affinity()) < 2:
        pytest.skip("one CPU: the ladder never starts a second process")
    from numerics.noise.budget import FP_BUDGET

    params = {"mu": 0.01, "Delta": 3.0, "beta": 1.0, "Omega": 1.0, "lam": 1.0}
    monkeypatch.setenv(ahead_mod.ENV, "2")
    two = stationary_kramers("sedf", params, 0.005, basis="orthonormal", max_cost=FP_BUDGET,
                             refine_ahead=True)
    assert two.refine.handed is not None and two.refine.handed.job is not None
    par = ed.energy_density_report(two)
    assert two.refine.handed.job is None  # collected
    monkeypatch.setenv(ahead_mod.ENV, "1")
    one = stationary_kramers("sedf", params, 0.005, basis="orthonormal", max_cost=FP_BUDGET,
                             refine_ahead=True)
    assert one.refine.handed is None and _same(one, two)
    assert ed.energy_density_report(one) == par
    assert par["change_peak"] < 1e-5
