"""The state of a one-degree-of-freedom diagram's run
(:func:`numerics.bifurcation.oned.autonomous_diagram`): its :class:`Settings`, the
:class:`Run` that follows each curve both ways from its seed (through the store) and
keeps the curves, codim-2 points and failures, and the geometry they share (distances to
polylines, runs of a sequence where a condition holds).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass

import numpy as np

from numerics.bifurcation.curve import continue_curve
from numerics.bifurcation.path import CurvePath
from numerics.bifurcation.result import Codim2Point, Curve, Diagram
from numerics.bifurcation.store import PathStore
from numerics.errors import NumericsError

__all__ = ["Settings", "Interrupted", "Run", "runs", "polyline_distance", "near", "distances"]


def runs(items: Iterable, keep: Callable) -> list[list]:
    """The maximal runs of consecutive ``items`` for which ``keep(item)`` holds."""
    out, cur = [], []
    for p in items:
        if keep(p):
            cur.append(p)
        elif cur:
            out.append(cur)
            cur = []
    if cur:
        out.append(cur)
    return out


@dataclass(frozen=True)
class Settings:
    """``L``: equilibria are looked for on ``[-L, L]``; ``grid``: the scans' points per
    axis; ``family_lines``: values of ``a`` where families of cycles are followed;
    ``ds_max``: the largest step (the box scaled to the unit square); ``max_points`` per
    direction; ``averaged_points``: grid values of the averaged curves; ``t_max``: a fold
    curve ends where the period exceeds it."""

    L: float = 8.0
    grid: tuple[int, int] = (25, 9)
    family_lines: int = 7
    ds_max: float = 0.04
    max_points: int = 400
    averaged_points: int = 25
    t_max: float = 300.0
    averaged: bool = True
    orders: tuple[int, ...] = (1, 2, 3)

    def text(self) -> str:
        return repr(self)


class Interrupted(Exception):
    """Ctrl-C: ``diagram`` holds what was found (the paths are in the store)."""

    def __init__(self, diagram: Diagram):
        super().__init__("interrupted")
        self.diagram = diagram


class Run:
    """The state of one diagram's run: the box, the curves and codim-2 points found, the
    store, the failures and the Hopf curves' points."""

    def __init__(self, kit: OneDof, ranges, store: PathStore, progress, settings: Settings):
        self.kit, self.store, self.progress, self.s = kit, store, progress, settings
        a, b = kit.axes
        self.box = (tuple(ranges[a]), tuple(ranges[b]))
        self.scale = np.array([self.box[0][1] - self.box[0][0], self.box[1][1] - self.box[1][0]])
        self.curves: list[Curve] = []
        self.codim2: list[Codim2Point] = []
        self.interrupted = False
        self.failures: list[str] = []
        #: the Hopf curves' points ``(x, a, b)``: starts of families of small cycles
        self.hopf: list[np.ndarray] = []

    # -- bookkeeping ----------------------------------------------------------------------
    def inside(self, ab) -> bool:
        """Whether ``ab`` lies in the box."""
        (a0, a1), (b0, b1) = self.box
        return bool(a0 <= ab[0] <= a1 and b0 <= ab[1] <= b1)

    def covered(self, kind: str, ab, label: str | None = None, tol: float = 0.01) -> bool:
        """Whether ``ab`` lies on a curve of ``kind`` found already (scaled distance)."""
        p = np.asarray(ab, dtype=float) / self.scale
        for c in self.curves:
            if c.kind != kind or c.method != "true" or (label and c.detail.get("label") != label):
                continue
            if polyline_distance(p[None, :], np.asarray(c.points) / self.scale)[0] < tol:
                return True
        return False

    def add_codim2(self, kind, ab, detail):
        """Add a codim-2 point unless one of its kind lies within ``1e-7`` of the box (one
        located point reached from two curves), or within ``1e-4`` with the same label (the
        loop's saddles; two saddle-node loops of different connections can be ``2e-6``
        apart)."""
        p = np.asarray(ab, dtype=float) / self.scale
        for c in self.codim2:
            d = np.linalg.norm(np.asarray(c.point) / self.scale - p)
            if c.kind == kind and (d < 1e-7 or (
                    d < 1e-4 and c.detail.get("label") == detail.get("label"))):
                return
        self.codim2.append(Codim2Point(kind, (float(ab[0]), float(ab[1])), detail))

    def attempt(self, kind: str, z0, key: str, G, tangent, **kw):
        """:meth:`follow` from the seed ``z0``; ``None`` when the seed does not converge
        (the failure kept) or gives fewer than two points."""
        try:
            pts, events, ends = self.follow(key, G, np.asarray(z0, dtype=float), tangent, **kw)
        except NumericsError as exc:
            self.failures.append(f"{kind} from {tuple(round(float(v), 6) for v in z0)}: {exc}")
            return None
        return (pts, events, ends) if len(pts) >= 2 else None

    # -- one curve, both directions -----------------------------------------------------------
    def follow(self, key: str, G, z0, tangent, *, scale, tests=None, on_point=None,
               stop=None, tol=1e-10, fd_step=1e-7, reset: Callable | None = None):
        """The path through ``z0`` in both directions, joined (``(points, events, ends)``)."""
        n = len(z0)
        bounds = {n - 2: self.box[0], n - 1: self.box[1]}
        paths = []
        first = None
        for sign in (1, -1):
            k = f"{key}|{sign}"
            rec = self.store.get(k)
            resume = None
            if rec is not None:
                path = CurvePath.from_records(rec["path"])
                if rec.get("done"):
                    paths.append(path)
                    if first is None and path.points:
                        first = path.points[0]
                    continue
                resume = path if path.points else None
            if reset is not None:
                reset(resume.points[-1].z if resume else (first.z if first else z0))
            start = first.z if (first is not None and resume is None) else z0
            t0 = (-first.tangent if first is not None else np.asarray(tangent) * sign) \
                if resume is None else None

            def point(pt, path=None, k=k):
                if on_point is not None:
                    on_point(pt)

            def prog(pt, path, k=k, kind=key.split("|")[0]):
                self.store.put(k, {"path": path.to_records(), "done": False})
                if self.progress is not None:
                    self.progress(kind, pt.z[-2:])

            path = continue_curve(G, start, tangent=t0, ds=0.2 * self.s.ds_max,
                                  ds_max=self.s.ds_max, bounds=bounds,
                                  max_points=self.s.max_points, tol=tol, tests=tests,
                                  stop=stop, progress=prog, on_point=point, resume=resume,
                                  scale=scale, fd_step=fd_step)
            if path.end == "interrupted":
                self.interrupted = True
                paths.append(path)
                break
            self.store.put(k, {"path": path.to_records(), "done": True})
            paths.append(path)
            if first is None and path.points:
                first = path.points[0]
        plus = paths[0]
        minus = paths[1] if len(paths) > 1 else CurvePath()
        pts = list(reversed(minus.points[1:])) + plus.points
        return pts, plus.events + minus.events, (minus.end, plus.end)


def near(run, ab, curve, tol=2e-3) -> bool:
    """Whether ``ab`` lies within ``10 tol`` (scaled) of a point of ``curve``."""
    q = np.asarray(curve.points) / run.scale
    return bool(np.min(np.linalg.norm(q - np.asarray(ab) / run.scale, axis=1)) < tol * 10)


def distances(run: Run, averaged: list[Curve]) -> list[Curve]:
    """Each averaged curve with its distance to the nearest true curve of its kind."""
    from dataclasses import replace

    out = []
    for c in averaged:
        best = None
        for i, t in enumerate(run.curves):
            if t.kind != c.kind or t.method != "true" or len(t.points) < 2:
                continue
            d = polyline_distance(np.asarray(c.points), np.asarray(t.points))
            if best is None or np.median(d) < np.median(best[1]):
                best = (i, d)
        if best is not None:
            c = replace(c, detail={**c.detail, "distance_to": best[0],
                                   "distance_max": float(np.max(best[1])),
                                   "distance_median": float(np.median(best[1]))})
        out.append(c)
    return out


def polyline_distance(ps, q) -> np.ndarray:
    """The distance of each point of ``ps`` to the polyline through the rows of ``q``."""
    ps, q = np.atleast_2d(ps), np.atleast_2d(q)
    if len(q) == 1:
        return np.linalg.norm(ps - q[0], axis=1)
    d = q[1:] - q[:-1]
    out = []
    for p in ps:
        t = np.clip(np.einsum("ij,ij->i", p - q[:-1], d) / np.maximum(
            np.einsum("ij,ij->i", d, d), 1e-300), 0, 1)
        out.append(float(np.min(np.linalg.norm(q[:-1] + t[:, None] * d - p, axis=1))))
    return np.array(out)
