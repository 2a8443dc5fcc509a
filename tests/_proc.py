"""The process table read from ``/proc`` (Linux), for the tests that signal a run and check
that no worker outlives it (not tests themselves)."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import pytest


def children(pid: int) -> list[int]:
    """The processes whose parent is ``pid``."""
    kids = []
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                stat = open(f"/proc/{entry}/stat").read()
            except OSError:
                continue
            if int(stat.rsplit(")", 1)[1].split()[1]) == pid:
                kids.append(int(entry))
    return kids


def alive(pid: int) -> bool:
    """Whether ``pid`` runs (a zombie counts as gone)."""
    try:
        return open(f"/proc/{pid}/stat").read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


def _default_sigint() -> None:
    """In the child before it runs: SIGINT back to its default (Python then installs its
    KeyboardInterrupt handler)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def start_with_workers(argv: list[str], settle: float, what: str):
    """``kbm argv`` started, once it has worker processes (within 60 s) and ``settle``
    seconds more: ``(process, its children)``; the test fails when none start."""
    # Ctrl-C's default disposition in the command, however the test run was started: a
    # background job of a non-interactive shell (a CI script's `cmd &`) ignores SIGINT,
    # and an ignored SIGINT is inherited, so Python would never raise KeyboardInterrupt
    proc = subprocess.Popen([sys.executable, "-m", "numerics.cli", *argv],
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                            preexec_fn=_default_sigint)
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and proc.poll() is None:
        if children(proc.pid):
            time.sleep(settle)  # let the workers take their first chunks
            return proc, children(proc.pid)
        time.sleep(0.2)
    proc.kill()
    pytest.fail(f"{what} worker processes did not start within 60 s")


def signal_and_wait(proc, sig, what: str) -> tuple[float, str]:
    """Send ``sig`` to ``proc`` and wait for it (the test fails past 10 s), then half a second
    for its workers to go: ``(seconds it took to stop, its standard error)``."""
    t0 = time.monotonic()
    proc.send_signal(sig)
    try:
        _, err = proc.communicate(timeout=10)
    except subprocess.TimeoutExpired:
        proc.kill()
        pytest.fail(f"the command did not stop within 10 s of {what}")
    elapsed = time.monotonic() - t0
    time.sleep(0.5)
    return elapsed, err
