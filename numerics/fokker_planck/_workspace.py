"""The large arrays of the element solves (the interiors' blocks of :mod:`._elements`, the
interface LU's blocks and the condensation's work arrays of :mod:`._elements_lu`) taken
from one buffer of the process (:func:`workspace`, :func:`solve`, :func:`empty`,
:func:`zeros`), which the element ladder (:mod:`._elements_ladder`) holds while it runs.

Why (measured on this machine, a 2-core VM).  Fresh large arrays cost system time where
they are first written: numpy's (``malloc``'s ``mmap``, advised into huge pages) 0.6-3 s
per GB, a private anonymous mapping without advice about 0.5 s per GB (0.5 GB written in a
fresh process: 0.32-1.55 s against 0.24-0.26 s), and pages given back cost as much again a
second or two later.  One solve of :func:`._elements_solve.element_stationary`, SEDF at
rest, Delta = 3, mu = 0.005, folded, fresh arrays against the buffer (user + system CPU,
interleaved, load 2.5): 362 x 200 elements 6.4 + 2.5 s against 5.6 + 0.5 s; then 362 x 240
in the same process 7.9 + 1.4 s against 7.6 + 0.1 s (the first solve's pages again);
512 x 240 alone 14.9 + 4.3 s against 15.2 + 1.3 s, peak 1.80 against 1.86 GB (``y`` and
``z`` of :mod:`._elements_lu` stay in the buffer).

The buffer is one reservation (pages never touched cost nothing) from which each solve
takes its arrays in order from the start; what does not fit is fresh.  The arrays are views
at multiples of 4096 bytes from 16 bytes into it, the offset in a page of numpy's fresh
large arrays, and every value is written before it is read (:func:`zeros` writes its
zeros): the same bits as fresh arrays (tests/test_fokker_planck_workspace.py).  A forked
process (:mod:`._ahead`) does not inherit it (``MADV_DONTFORK``: else this process's
writes after the fork would copy its pages) and its solve reserves its own.  Outside
:func:`workspace` the arrays are fresh.
"""

from __future__ import annotations

import contextlib
import mmap
import os

import numpy as np

__all__ = ["workspace", "solve", "empty", "zeros"]

#: the arrays' spacing in the buffer (a page), and their offset in a page: that of a fresh
#: large array (``malloc``'s header before the data of its ``mmap``)
PAGE = 4096
OFFSET = 16


class _Buffer:
    """The reservation of :func:`workspace` and the offset of its next array."""

    def __init__(self, nbytes: int):
        self.pid, self.data, self.next = os.getpid(), None, 0
        self.nbytes = int(min(max(nbytes, 0.0), 2.0**60))

    def take(self, shape) -> np.ndarray | None:
        """A float array of ``shape`` at the next free page, ``None`` when past the end."""
        n = int(np.prod(shape, dtype=np.int64)) * 8
        if os.getpid() != self.pid or self.next + n > self.nbytes:
            return None
        if self.data is None:
            try:
                self.data = _reserve(self.nbytes + PAGE)
            except (OSError, ValueError, OverflowError):  # no room: fresh arrays
                self.nbytes = 0
                return None
        at = OFFSET + self.next
        out = self.data[at:at + n].view(np.float64).reshape(shape)
        self.next += -(-n // PAGE) * PAGE
        return out


def _reserve(nbytes: int) -> np.ndarray:
    """``nbytes`` of private anonymous memory (no advice: huge pages only where the system
    makes them unasked), not inherited by a forked process (were it, this process's first
    write to each page after the fork would copy it; the forked process keeps the object,
    never its pages: :func:`solve`)."""
    mm = mmap.mmap(-1, nbytes, flags=mmap.MAP_PRIVATE | mmap.MAP_ANONYMOUS)
    with contextlib.suppress(AttributeError, OSError):
        mm.madvise(mmap.MADV_DONTFORK)
    return np.frombuffer(mm, dtype=np.uint8)


_CURRENT: _Buffer | None = None


@contextlib.contextmanager
def workspace(nbytes: float):
    """Within, the element solves of this process take their large arrays from one buffer of
    ``nbytes`` (reserved at the first, given back on exit; what does not fit is fresh)."""
    global _CURRENT
    outer, _CURRENT = _CURRENT, _Buffer(nbytes)
    try:
        yield _CURRENT
    finally:
        _CURRENT = outer


@contextlib.contextmanager
def solve():
    """One solve: its arrays from the start of this process's buffer (the previous solve's
    are dead); in a forked process, from a buffer of its own of the same size for this
    solve (the inherited object kept: its pages are not there, and unmapping its addresses
    could unmap this process's own)."""
    if _CURRENT is not None and _CURRENT.pid != os.getpid():
        with workspace(_CURRENT.nbytes):
            yield
        return
    if _CURRENT is not None:
        _CURRENT.next = 0
    yield


def empty(shape) -> np.ndarray:
    """``numpy.empty(shape)``, from the buffer of :func:`workspace` when there is room."""
    out = None if _CURRENT is None else _CURRENT.take(shape)
    return np.empty(shape) if out is None else out


def zeros(shape) -> np.ndarray:
    """``numpy.zeros(shape)``, from the buffer of :func:`workspace` when there is room."""
    out = None if _CURRENT is None else _CURRENT.take(shape)
    if out is None:
        return np.zeros(shape)
    out.fill(0.0)
    return out
