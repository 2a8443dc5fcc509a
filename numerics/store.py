"""A crash-safe store of finished points, so that a long run can be stopped and resumed.

A run (a sweep, a friction map) is cut into chunks by the data alone
(:func:`numerics.executor.chunk`), so the same run always has the same chunks.  Each
finished chunk is written to an SQLite file (the standard library's :mod:`sqlite3`) in
one transaction, under the run's *definition* (a text naming the function, the model,
the fixed parameters, the settings and every chunk's points) and the chunk's index.  A
run stopped at any moment (Ctrl-C, SIGTERM, a crash, a power cut) keeps every chunk that
was committed; run again with ``resume=True`` (``--resume``), it computes only the
missing chunks and returns the same results as an uninterrupted run, byte for byte
(the stored results are the pickled result objects themselves).

A store may hold several runs (the two maps of a slider comparison); a definition that
differs in anything (one parameter, one point, the settings) is another run.
"""

from __future__ import annotations

import hashlib
import os
import pickle
import sqlite3
from dataclasses import dataclass
from pathlib import Path

from numerics.errors import NumericsError

__all__ = ["PointStore", "StoreError", "RunRecord"]


class StoreError(NumericsError):
    """The store file cannot be used as asked (it holds this run already without
    ``resume``, it is not a store, or it cannot be written)."""


_SCHEMA = """
CREATE TABLE IF NOT EXISTS runs (run TEXT PRIMARY KEY, definition TEXT NOT NULL,
                                 chunks INTEGER NOT NULL);
CREATE TABLE IF NOT EXISTS chunks (run TEXT NOT NULL, idx INTEGER NOT NULL,
                                   points INTEGER NOT NULL, payload BLOB NOT NULL,
                                   PRIMARY KEY (run, idx));
"""


class PointStore:
    """The SQLite file ``path`` of finished chunks.

    Parameters
    ----------
    path
        The file (created if missing).
    resume
        Continue the runs already in the file: their stored chunks are not computed
        again.  Without it, a run that already has chunks in the file is refused
        (:class:`StoreError`), so that nothing is silently mixed or overwritten.
    """

    def __init__(self, path: str | os.PathLike, *, resume: bool = False):
        self.path = Path(path)
        self.resume = resume
        try:
            self._db = sqlite3.connect(self.path, isolation_level=None)
            self._db.executescript(_SCHEMA)
        except sqlite3.DatabaseError as exc:
            raise StoreError(f"{self.path} cannot be used as a store of finished points: "
                             f"{exc}") from None

    def run(self, definition: str, chunks: int) -> "RunRecord":
        """The record of one run of ``chunks`` chunks with this ``definition``."""
        key = hashlib.sha256(definition.encode()).hexdigest()
        done = self._db.execute("SELECT COUNT(*) FROM chunks WHERE run = ?", (key,)).fetchone()[0]
        if done and not self.resume:
            raise StoreError(f"{self.path} already holds {done} finished chunks of this run: "
                             "pass --resume (resume=True) to continue it, or name a new file")
        self._db.execute("INSERT OR IGNORE INTO runs VALUES (?, ?, ?)", (key, definition, chunks))
        return RunRecord(self, key)

    def finished_points(self) -> int:
        """Points kept in the file, over all its runs."""
        return self._db.execute("SELECT COALESCE(SUM(points), 0) FROM chunks").fetchone()[0]

    def close(self) -> None:
        self._db.close()

    def __enter__(self) -> "PointStore":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def __repr__(self) -> str:
        return f"PointStore({str(self.path)!r}, resume={self.resume})"


@dataclass(frozen=True)
class RunRecord:
    """The finished chunks of one run in a :class:`PointStore`."""

    store: PointStore
    key: str

    def load(self) -> dict[int, list]:
        """``{chunk index: results}`` of the chunks already finished."""
        rows = self.store._db.execute("SELECT idx, payload FROM chunks WHERE run = ?",
                                      (self.key,)).fetchall()
        try:
            return {idx: pickle.loads(payload) for idx, payload in rows}
        except (ImportError, AttributeError) as exc:  # a class moved or renamed since
            raise StoreError(f"{self.store.path} holds chunks of this run written by another "
                             f"version of kbm ({exc}): run it again without --resume, "
                             "into a new store file") from None

    def save(self, idx: int, results: list) -> None:
        """Commit one finished chunk (one transaction: all of it or nothing)."""
        payload = pickle.dumps(results, protocol=pickle.HIGHEST_PROTOCOL)
        db = self.store._db
        db.execute("BEGIN IMMEDIATE")
        try:
            db.execute("INSERT OR REPLACE INTO chunks VALUES (?, ?, ?, ?)",
                       (self.key, idx, len(results), payload))
            db.execute("COMMIT")
        except BaseException:
            db.execute("ROLLBACK")
            raise
