"""The records of a continuation (:func:`numerics.bifurcation.curve.continue_curve`): its
converged points (:class:`PathPoint`), the located zeros of its test functions
(:class:`TestEvent`) and the path with why it ended (:class:`CurvePath`), each JSON-able
for the store and resume.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

__all__ = ["PathPoint", "TestEvent", "CurvePath"]


@dataclass
class PathPoint:
    """One converged point: ``z``, the unit tangent there, the residual ``max|G(z)|``, the
    Newton steps it took and the test functions' values."""

    z: np.ndarray
    tangent: np.ndarray
    residual: float
    steps: int = 0
    tests: dict = field(default_factory=dict)

    def record(self) -> dict:
        """A JSON-able dict (:meth:`CurvePath.to_records`)."""
        return {"z": [float(v) for v in self.z], "tangent": [float(v) for v in self.tangent],
                "residual": float(self.residual), "steps": int(self.steps),
                "tests": {k: float(v) for k, v in self.tests.items()}}

    @classmethod
    def from_record(cls, rec: Mapping) -> "PathPoint":
        return cls(np.asarray(rec["z"], dtype=float), np.asarray(rec["tangent"], dtype=float),
                   float(rec["residual"]), int(rec.get("steps", 0)),
                   {k: float(v) for k, v in rec.get("tests", {}).items()})


@dataclass
class TestEvent:
    """A zero of the test function ``name`` on the curve, at the converged point ``z``
    (``value`` the test there, ``after`` the index of the path point before it,
    ``bracket`` the final bracket's width relative to the chord)."""

    name: str
    z: np.ndarray
    value: float
    after: int
    bracket: float
    residual: float

    def record(self) -> dict:
        return {"name": self.name, "z": [float(v) for v in self.z], "value": float(self.value),
                "after": int(self.after), "bracket": float(self.bracket),
                "residual": float(self.residual)}

    @classmethod
    def from_record(cls, rec: Mapping) -> "TestEvent":
        return cls(rec["name"], np.asarray(rec["z"], dtype=float), float(rec["value"]),
                   int(rec["after"]), float(rec["bracket"]), float(rec["residual"]))


@dataclass
class CurvePath:
    """The points of one continuation, the located zeros of the test functions and why it
    ended: ``"bounds"`` (on the box's edge), ``"max_points"``, ``"closed"`` (back at its
    start), ``"step"`` (``ds`` below ``ds_min``), ``"stopped"`` (a stop test), or
    ``"interrupted"`` (Ctrl-C)."""

    points: list[PathPoint] = field(default_factory=list)
    events: list[TestEvent] = field(default_factory=list)
    end: str = ""
    ds: float = float("nan")
    message: str = ""

    def array(self) -> np.ndarray:
        """The points' ``z`` as rows."""
        return np.array([p.z for p in self.points]) if self.points else np.zeros((0, 0))

    def to_records(self) -> dict:
        """A JSON-able dict of the path (points, events, end, the last step)."""
        return {"points": [p.record() for p in self.points],
                "events": [e.record() for e in self.events], "end": self.end,
                "ds": float(self.ds), "message": self.message}

    @classmethod
    def from_records(cls, rec: Mapping) -> "CurvePath":
        return cls([PathPoint.from_record(r) for r in rec.get("points", [])],
                   [TestEvent.from_record(r) for r in rec.get("events", [])],
                   rec.get("end", ""), float(rec.get("ds", float("nan"))),
                   rec.get("message", ""))
