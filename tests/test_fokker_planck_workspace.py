"""The buffer that the element ladder's solves of one process share
(numerics/fokker_planck/_workspace.py): a solve whose large arrays are views of pages that
an earlier solve of another size wrote (the interface LU's blocks, which are accumulated
into and must start at zero, and the interiors' blocks) is the same bits as the solve on
fresh arrays, whole in the buffer or only in part (the rest fresh); and a forked process
does not draw from the buffer it inherits.  The same bits whatever the history of the
process: the developers' guide."""

from __future__ import annotations

import multiprocessing
import os

import numpy as np
import pytest

from numerics.fokker_planck import _workspace
from numerics.fokker_planck._elements_solve import element_kramers

SEDF = {"mu": 0.1, "Delta": 3, "beta": 1, "lam": 1, "Omega": 1}
#: the velocity scale and range of the solves (given: no pilot solve)
SIGMA, HALF = 1.0, 5.0


def _solve(n: int, elements: int):
    return element_kramers("sedf", SEDF, 0.05, n_hermite=n, elements=elements, degree=13,
                           sigma=SIGMA, L=HALF)


@pytest.mark.parametrize("nbytes", [64e6, 2e6])
def test_solve_in_a_used_buffer_is_the_fresh_solve(nbytes):
    """64 Hermite functions x 56 elements after 90 x 48 in the same buffer (64 MB: every
    large array in it; 2 MB: the first ones, the rest fresh) against the same solve outside
    any buffer: the coefficients and moments the same bits."""
    fresh = _solve(64, 56)
    with _workspace.workspace(nbytes) as buf:
        with _workspace.solve():
            other = _solve(90, 48)
        used = buf.next
        with _workspace.solve():
            again = _solve(64, 56)
        assert buf.data is not None and used > 0 and buf.next > 0
    assert other.coef.shape != again.coef.shape
    assert again.coef.tobytes() == fresh.coef.tobytes()
    assert (again.x2, again.v2, again.residual) == (fresh.x2, fresh.v2, fresh.residual)
    assert np.all(np.isfinite(again.coef))


def _child(out) -> None:
    arr = _workspace.zeros((4, 4))
    out.value = int(_workspace._CURRENT.next)  # 0: the array was fresh
    arr += 1.0


def test_a_forked_process_does_not_draw_from_the_buffer():
    """The buffer's owner takes views; a forked copy gets fresh arrays (the buffer is not
    inherited), and the owner's offsets are its own."""
    if "fork" not in multiprocessing.get_all_start_methods():
        pytest.skip("no fork here")
    ctx = multiprocessing.get_context("fork")
    with _workspace.workspace(1e6) as buf:
        a = _workspace.zeros((8, 8))
        assert a.base is not None and buf.next == _workspace.PAGE
        assert (a.__array_interface__["data"][0] - _workspace.OFFSET) % _workspace.PAGE == 0
        seen = ctx.Value("q", -1)
        proc = ctx.Process(target=_child, args=(seen,))
        proc.start()
        proc.join()
        assert proc.exitcode == 0 and seen.value == _workspace.PAGE
        assert os.getpid() == buf.pid
