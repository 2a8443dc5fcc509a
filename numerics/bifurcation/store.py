"""Keeping the paths of a diagram on disk, so that a long run can be stopped and resumed
(``kbm diagram --store DIR --resume``).

A run is named by the SHA-256 of its definition (model, fixed parameters, axes, ranges,
settings); each continued path (one direction from one seed) and each scan is a JSON file
``DIR/<run>/<key>.json`` written after every accepted point (atomically: a temporary file
renamed).  With ``resume`` a finished path is read back as it is and an interrupted one is
continued from its last point and tangent
(:func:`numerics.bifurcation.curve.continue_curve` with ``resume=``); without it a folder
that already holds this run is refused.
"""

from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path

from numerics.store import StoreError

__all__ = ["PathStore"]


class PathStore:
    """The paths of one run in ``folder`` (``None``: nothing is kept)."""

    def __init__(self, folder: str | os.PathLike | None, definition: str, resume: bool = False):
        self.resume = resume
        self.key = hashlib.sha256(definition.encode()).hexdigest()[:16]
        self.dir = None
        if folder is None:
            return
        self.dir = Path(folder) / self.key
        if self.dir.exists() and any(self.dir.iterdir()) and not resume:
            raise StoreError(f"{folder} holds this diagram's run already ({self.key}): add "
                             "--resume to continue it, or name another folder")
        try:
            self.dir.mkdir(parents=True, exist_ok=True)
            (self.dir / "definition.txt").write_text(definition + "\n")
        except OSError as exc:
            raise StoreError(f"cannot write the store {folder}: {exc}") from None

    @staticmethod
    def _name(key: str) -> str:
        return hashlib.sha256(key.encode()).hexdigest()[:20] + ".json"

    def get(self, key: str) -> dict | None:
        """The stored record of ``key`` (``None``: not stored, or not resuming)."""
        if self.dir is None or not self.resume:
            return None
        path = self.dir / self._name(key)
        if not path.exists():
            return None
        return json.loads(path.read_text())

    def put(self, key: str, record: dict) -> None:
        """Write ``record`` under ``key`` (a temporary file renamed: never half written)."""
        if self.dir is None:
            return
        path = self.dir / self._name(key)
        tmp = path.with_suffix(".tmp")
        tmp.write_text(json.dumps({"key": key, **record}, sort_keys=True))
        os.replace(tmp, path)
