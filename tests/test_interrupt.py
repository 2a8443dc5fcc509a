"""Long runs stop at once on Ctrl-C (SIGINT) or SIGTERM and leave no worker behind (issue 21).

Each test starts a real ``kbm friction`` map (768 points, minutes of work) in a fresh
process, waits until its local pool's worker processes run, signals the parent and
checks: the exit status, the time to exit (< 2 s), the message (how many points were
finished) and that no worker outlives the parent (``/proc``; zombies count as gone).
"""

from __future__ import annotations

import signal
import sys
import time

import pytest
from _proc import alive as _alive, signal_and_wait, start_with_workers

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="uses /proc")

MAP = ["friction", "sedf_comoving", "-p", "beta=1", "--vary", "v=1e-3:3:log48", "--vary",
       "Delta=0.5:3:16", "--against", "cdc", "--json"]


def _start():
    return start_with_workers(MAP, 1.0, "the map's")


@pytest.mark.parametrize("sig, status, how", [(signal.SIGINT, 130, "Ctrl-C"),
                                              (signal.SIGTERM, 143, "SIGTERM")])
def test_a_signal_stops_the_map_within_2_s_and_no_worker_outlives_it(sig, status, how):
    proc, kids = _start()
    assert kids
    elapsed, err = signal_and_wait(proc, sig, "the signal")
    assert proc.returncode == status, err
    assert elapsed < 2.0
    last = err.strip().splitlines()[-1]
    assert last.startswith(f"kbm friction: interrupted ({how}): ") and " of 768 points were " \
        "finished" in last
    assert [k for k in kids if _alive(k)] == []


def test_workers_die_with_a_parent_that_is_killed():
    """SIGKILL cannot be handled: the workers go by PR_SET_PDEATHSIG."""
    proc, kids = _start()
    proc.kill()
    proc.communicate(timeout=10)
    deadline = time.monotonic() + 5
    while time.monotonic() < deadline and any(_alive(k) for k in kids):
        time.sleep(0.1)
    assert [k for k in kids if _alive(k)] == []


def test_interruption_inside_compiled_code_is_an_interruption(capsys):
    """Ctrl-C while numba's compiled flow runs surfaces as a SystemError ("returned a
    result with an exception set") whose context is the KeyboardInterrupt: the command
    still stops with the one-line message and status 130 (a continuation spends most of its
    time there); any other SystemError is not swallowed."""
    import argparse

    from kbm.cli import run_command

    def compiled_call_interrupted(args):
        try:
            raise KeyboardInterrupt
        except KeyboardInterrupt:
            raise SystemError("CPUDispatcher(flow) returned a result with an exception set")

    def other_failure(args):
        raise SystemError("a genuine internal error")

    for func, expect in ((compiled_call_interrupted, 130), (other_failure, None)):
        parser = argparse.ArgumentParser(prog="kbm")
        parser.set_defaults(func=func, command="branch")
        if expect is None:
            with pytest.raises(SystemError, match="genuine"):
                run_command(parser, [])
            continue
        assert run_command(parser, []) == expect
        err = capsys.readouterr().err.strip().splitlines()
        assert err == ["kbm branch: interrupted (Ctrl-C)"]
