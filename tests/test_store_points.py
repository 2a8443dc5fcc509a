"""``PointStore.finished_points``: the points a store keeps, counted by hand.

The reference is arithmetic on the chunks written: a run cut into chunks of ``size`` points
(:func:`numerics.executor.chunk`) that stops after ``k`` whole chunks keeps ``k size``
points (each chunk is one transaction, :mod:`numerics.store`), and two runs in one file
keep the sum of theirs.
"""

from __future__ import annotations

import pytest

from numerics.executor import Interrupted, chunk, map_chunks
from numerics.store import PointStore


def _square(c):
    return [x * x for x in c]


class _StopAt:
    """Squares chunks, and raises ``KeyboardInterrupt`` (Ctrl-C) on the chunk holding
    ``stop``: the chunks before it are committed, that one and the later ones are not."""

    def __init__(self, stop: int):
        self.stop = stop

    def __call__(self, c):
        if self.stop in c:
            raise KeyboardInterrupt
        return _square(c)


def test_an_empty_store_keeps_no_points(tmp_path):
    with PointStore(tmp_path / "s.sqlite") as st:
        assert st.finished_points() == 0


def test_a_run_interrupted_midway_keeps_its_whole_chunks_and_resumes_to_all(tmp_path):
    """23 points in chunks of 4 (5 of 4 and one of 3), Ctrl-C on the chunk of point 13
    (the fourth chunk, 12..15): 3 chunks x 4 = 12 points kept; the resumed run adds the
    other 11, and a second run of 7 points in the same file adds 7 (23 + 7 = 30)."""
    path = tmp_path / "s.sqlite"
    parts = chunk(list(range(23)), size=4)
    assert [len(c) for c in parts] == [4, 4, 4, 4, 4, 3]
    with PointStore(path) as st:
        with pytest.raises(Interrupted) as stop:
            map_chunks(_StopAt(13), parts, workers=1, store=st, definition="squares",
                       sizes=[len(c) for c in parts])
        assert stop.value.finished == 12
        assert st.finished_points() == 12
    with PointStore(path, resume=True) as st:
        assert st.finished_points() == 12  # what a new process sees in the file
        out = map_chunks(_square, parts, workers=1, store=st, definition="squares")
        assert out == [i * i for i in range(23)]
        assert st.finished_points() == 23
        map_chunks(_square, chunk(list(range(7)), size=4), workers=1, store=st,
                   definition="another run")
        assert st.finished_points() == 30
