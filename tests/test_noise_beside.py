"""The averaging and the step pilot of ``kbm noise`` beside its Fokker-Planck solve
(numerics/thermal/_beside.py; issue 36, "six digits in seconds"): the results and the
errors are those of the calls made one after the other in this process (the reference:
``KBM_FP_WORKERS=1``, the order of before), a failure in the forked process stops this
one's work at once (:class:`Alarm`) and comes back whole, and the averaged density
tabulated there is the one on the ensemble's histogram."""

from __future__ import annotations

import dataclasses
import os
import subprocess
import sys
import time

import numpy as np
import pytest

import numerics.fokker_planck._ahead as ahead_mod
from kbm.errors import ParameterError
from numerics.fokker_planck._ahead import Ahead, Alarm, Alarmed
from numerics.thermal._beside import Tabulated, beside, histogram_edges


@dataclasses.dataclass(frozen=True)
class _Value:
    value: float


def _square_later(x: float, wait: float = 0.0) -> _Value:
    time.sleep(wait)
    return _Value(x * x)


def _refuse(calls: list, wait: float = 0.2):
    calls.append("called")
    time.sleep(wait)
    raise ParameterError("mu = -1: give mu > 0")


def _busy(done: list, seconds: float = 20.0):
    """Work of this process that only an alarm ends early (a bound against a hang)."""
    t0 = time.monotonic()
    while time.monotonic() - t0 < seconds:
        time.sleep(0.01)
    done.append("ran out")
    return "solved"


def test_a_failure_beside_stops_this_process_and_comes_back_whole(monkeypatch):
    """The forked call raises: this process's work is interrupted (``Alarmed``) long before
    it would end, and :meth:`Ahead.result` raises the forked call's exception, the same
    class and message, without calling it again here (``calls`` is this process's)."""
    calls, done = [], []
    with Alarm() as alarm, Ahead(_refuse, 2, alarm=alarm.signum, raises=True) as ahead:
        if alarm.signum is None or not ahead.start("averaged", [], 0.2):
            pytest.skip("no second process or no SIGUSR1 here")
        with pytest.raises(Alarmed):
            _busy(done)
        alarm.disarm()
        with pytest.raises(ParameterError, match=r"mu = -1: give mu > 0"):
            ahead.result("averaged", calls)
    assert done == [] and calls == []


def test_ready_reads_the_pipe_without_waiting():
    """``ready`` is false while the forked call runs and true once its value is back; the
    value is the direct call's (3^2)."""
    with Ahead(_square_later, 2) as ahead:
        if not ahead.start("x", 3.0, 0.5):
            pytest.skip("no second process here")
        assert not ahead.ready("x")
        t0 = time.monotonic()
        while not ahead.ready("x") and time.monotonic() - t0 < 30:
            time.sleep(0.02)
        assert ahead.result("x", 3.0) == _Value(9.0)
    assert not ahead.ready("never started")


@pytest.mark.parametrize("workers", [1, 2])
def test_beside_gives_the_calls_results_and_the_averagings_refusal_first(workers):
    """``beside(solve, averaged, pilot)``: the three results as the direct calls give them
    with one process or two; when ``averaged`` refuses, its error is raised (before
    ``pilot`` and ``solve`` are made with one process; ``solve`` stopped with two)."""
    out = beside(lambda: "solved", lambda: _square_later(2.0, 0.1),
                 lambda: _square_later(5.0), workers)
    assert out == ("solved", _Value(4.0), _Value(25.0))
    calls, done = [], []
    with pytest.raises(ParameterError, match=r"give mu > 0"):
        beside(lambda: _busy(done), lambda: _refuse(calls), lambda: _square_later(1.0),
               workers)
    assert done == []
    assert calls == (["called"] if workers == 1 or not _forks() else [])


def _forks() -> bool:
    with Ahead(_square_later, 2) as ahead:
        return ahead.start("probe", 1.0)


def test_tabulated_density_is_on_the_ensembles_histogram():
    """:func:`histogram_edges` are the edges :func:`numerics.noise.ensemble.
    stationary_ensemble` histograms (``n`` equal bins on ``[lo, hi)``, from 0 for the
    amplitude); :class:`Tabulated` refuses other edges."""
    from numerics.noise.ensemble import stationary_ensemble
    from numerics.thermal.averaged import averaged_stationary

    avg, _ = averaged_stationary("vdp", {"mu": 0.1}, 0.05, 1.0)
    edges = histogram_edges(avg, 40)
    ens = stationary_ensemble("vdp", {"mu": 0.1}, 0.05, trajectories=8, t_end=2.0,
                              burn_in=1.0, dt=0.05, seed=0, variable="a",
                              bins=(0.0, avg.support[1], 40), workers=1)
    assert np.array_equal(edges, ens.edges)
    table = Tabulated(edges, np.asarray(avg.bins(edges)))
    assert np.array_equal(table(ens.edges), avg.bins(ens.edges))
    with pytest.raises(ValueError, match="tabulated on the histogram's edges"):
        table(edges[:-1])


def _kbm(args: list, workers: int) -> subprocess.CompletedProcess:
    env = dict(os.environ, **{ahead_mod.ENV: str(workers)})
    return subprocess.run([sys.executable, "-m", "numerics.cli", *args], capture_output=True,
                          text=True, timeout=600, env=env)


@pytest.mark.slow
def test_noise_beside_the_solve_gives_the_bytes_and_the_refusal_of_one_process():
    """``kbm noise`` with the averaging and the pilot beside the solve (two processes)
    prints the bytes of one process (the CDC at rest with its Fokker-Planck moments), and
    the SEDF at beta = -1 (positive energy drift: no stationary state) the same refusal."""
    args = ["noise", "cdc", "-p", "mu=0.1", "-p", "Delta=3", "-p", "D=0.05",
            "--trajectories", "8", "--t-end", "50", "--seed", "5", "--json"]
    one, two = _kbm(args, 1), _kbm(args, 2)
    assert one.returncode == two.returncode == 0, (one.stderr, two.stderr)
    assert one.stdout == two.stdout
    bad = ["noise", "sedf", "-p", "mu=0.1", "-p", "Delta=3", "-p", "beta=-1", "-p", "D=0.05"]
    one, two = _kbm(bad, 1), _kbm(bad, 2)
    assert one.returncode == two.returncode == 2
    assert one.stderr == two.stderr and "no stationary state" in one.stderr
