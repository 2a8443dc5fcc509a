"""Shared machinery of the two-parameter curves of :mod:`numerics.bifurcation.forced` and
:mod:`numerics.bifurcation.coupled`: a curve continued both ways from its seed
(:func:`both_ways`, on :func:`numerics.bifurcation.curve.continue_curve`), the paths
joined into one polyline, seeds already on a found curve skipped, the located test zeros
named as codim-2 points (merged across curves), and the distances between true and
averaged curves in the parameter plane.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from numerics.bifurcation.curve import continue_curve
from numerics.bifurcation.path import CurvePath
from numerics.bifurcation.result import Codim2Point, Curve

__all__ = ["interruptible", "FD_STEP", "Task", "both_ways", "joined", "trimmed",
           "curve_distance", "distances", "merged", "on_known", "codim2_points",
           "seed_levels", "dropped_seed"]


def interruptible(fn: Callable) -> Callable:
    """``fn`` with a Ctrl-C inside compiled code (numba: a :class:`SystemError` over the
    :class:`KeyboardInterrupt`) raised as the :class:`KeyboardInterrupt` itself, which
    :func:`~numerics.bifurcation.curve.continue_curve` turns into an interrupted path."""
    def wrapped(*args, **kwargs):
        try:
            return fn(*args, **kwargs)
        except SystemError as exc:
            if isinstance(exc.__context__, KeyboardInterrupt):
                raise KeyboardInterrupt from None
            raise
    return wrapped


#: the central-difference step of the defining systems' Jacobians (relative)
FD_STEP = 1e-6


@dataclass
class Task:
    """One curve to continue: its kind, method (``"true"``/``"averaged"``), order, the
    seed ``z0`` and the paths found (both directions)."""

    kind: str
    method: str
    order: int | None
    z0: np.ndarray
    paths: list = field(default_factory=list)
    problem: object = None


def seed_levels(lo: float, hi: float, n: int) -> list[float]:
    """``n`` values strictly inside ``(lo, hi)``, equally spaced (``lo + k (hi - lo)/(n +
    1)``, ``k = 1..n``): the lines the seeds of the curves are looked for on.  Never the
    ends: a seed on the box's edge corrects to either side of it."""
    return [float(x) for x in np.linspace(lo, hi, n + 2)[1:-1]]


def dropped_seed(kind: str, method: str, order, point, reason: str) -> dict:
    """The record of a seed that gave no curve (``detail["dropped"]`` of a diagram): its
    kind, method, order, parameter point and why."""
    return {"kind": kind, "method": method, "order": order,
            "seed": [float(point[0]), float(point[1])], "reason": reason}


def why_short(paths) -> str:
    """Why the paths from a seed hold fewer than two points: their ends and messages."""
    ends = [f"{p.end}: {p.message}" if p.message else p.end for p in paths]
    return "; ".join(ends) if ends else "no path"


def both_ways(G, z0, *, jac=None, bounds, scale=None, ds=0.02, ds_max=0.1, max_points=400,
              tests=None, stop=None, progress=None, tol=1e-10, resume=()
              ) -> list[CurvePath]:
    """The curve through ``z0`` continued in both directions (the second path not started
    when the first closed on itself); ``resume`` the stored paths (continued)."""
    out = []
    first_tangent = None
    for k, sign in enumerate((1.0, -1.0)):
        old = resume[k] if k < len(resume) else None
        if old is not None and old.end not in ("interrupted", ""):
            out.append(old)
            if old.end == "closed":
                break
            continue
        tangent = None if first_tangent is None else sign * first_tangent
        path = continue_curve(G, z0, jac=jac, tangent=tangent, ds=ds, ds_max=ds_max,
                              bounds=bounds, max_points=max_points, tol=tol, tests=tests,
                              stop=stop, progress=progress, scale=scale, resume=old)
        out.append(path)
        if path.points and first_tangent is None:
            first_tangent = np.asarray(path.points[0].tangent, dtype=float)
        if path.end in ("closed", "interrupted"):
            break
    return out


def joined(paths: Sequence[CurvePath]) -> np.ndarray:
    """The points of two paths from one seed as one array (the second reversed first)."""
    if not paths or not paths[0].points:
        return np.zeros((0, 0))
    a = [p.z for p in paths[0].points]
    b = [p.z for p in paths[1].points[1:]] if len(paths) > 1 else []
    return np.array(list(reversed(b)) + a)


def trimmed(paths: Sequence[CurvePath], ok: Callable) -> np.ndarray:
    """:func:`joined` without the end points where ``ok(z)`` fails (a Neimark–Sacker path
    stopped one point past its Bogdanov–Takens end), that end's located test zero put in
    their place."""
    kept = []
    for path in paths:
        pts = [p.z for p in path.points]
        if pts and not ok(pts[-1]):
            pts = pts[:-1]
            ends = [e.z for e in path.events if e.name == "bogdanov-takens"]
            if ends:
                pts.append(np.asarray(ends[-1]))
        kept.append(pts)
    if not kept or not kept[0]:
        return np.zeros((0, 0))
    rest = kept[1][1:] if len(kept) > 1 else []
    return np.array(list(reversed(rest)) + kept[0])


def _near_polyline(pt: np.ndarray, line: np.ndarray) -> float:
    """Distance from ``pt`` to the polyline through the rows of ``line``."""
    if len(line) == 0:
        return math.inf
    if len(line) == 1:
        return float(np.linalg.norm(pt - line[0]))
    a, b = line[:-1], line[1:]
    d = b - a
    den = np.maximum(np.einsum("ij,ij->i", d, d), 1e-300)
    s = np.clip(np.einsum("ij,ij->i", pt - a, d) / den, 0.0, 1.0)
    return float(np.min(np.linalg.norm(a + s[:, None] * d - pt, axis=1)))


def curve_distance(a: Sequence, b: Sequence) -> float:
    """The largest distance from a point of the curve ``a`` to the polyline ``b`` (both in
    the parameter plane): the directed Hausdorff distance."""
    A, B = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    if len(A) == 0 or len(B) == 0:
        return math.nan
    return max(_near_polyline(p, B) for p in A)


def on_known(z0: np.ndarray, tasks: Sequence[Task], kind: str, scale: np.ndarray,
              tol: float) -> bool:
    for t in tasks:
        if t.kind == kind:
            pts = joined(t.paths)
            if len(pts) and _near_polyline(z0 / scale, pts / scale) < tol:
                return True
    return False


def codim2_points(task: Task, axes_idx: tuple[int, int], jac, scale) -> list[Codim2Point]:
    """The located test-function zeros of a task's paths as named points (a ``cusp`` only
    where both parameter components, ``axes_idx``, of the tangent vanish: the null vector
    of ``jac(z)`` divided by ``scale`` and normalised, both below 1e-3)."""
    def flat(z) -> bool:
        t = np.linalg.svd(jac(z))[2][-1] / scale
        t /= np.linalg.norm(t)
        return abs(t[i]) < 1e-3 and abs(t[j]) < 1e-3

    out = []
    i, j = axes_idx
    for path in task.paths:
        for ev in path.events:
            kind = ev.name
            if kind == "cusp" and not flat(ev.z):
                continue
            p = (float(ev.z[i]), float(ev.z[j]))
            if any(o.kind == kind and math.hypot(o.point[0] - p[0], o.point[1] - p[1]) < 1e-6
                   for o in out):
                continue
            out.append(Codim2Point(kind, p, {"on": task.kind, "method": task.method,
                                             "order": task.order, "test": float(ev.value),
                                             "residual": float(ev.residual)}))
    return out


def distances(true: Sequence[Curve], averaged: Sequence[Curve], tp: Sequence[Codim2Point],
              ap: Sequence[Codim2Point]) -> dict:
    """``{kind: {order: d}}``: for a curve kind, the largest distance from a point of the
    true curves of that kind to the averaged ones of the order (the parameter plane); for
    a codim-2 kind (``cusp``, ``bogdanov-takens``, ...), the largest distance from a true
    point to the nearest averaged point of that kind and order."""
    out: dict = {}
    for kind in sorted({c.kind for c in true}):
        tpts = [p for c in true if c.kind == kind for p in c.points]
        for n in sorted({c.order for c in averaged if c.kind == kind}):
            apts = [c for c in averaged if c.kind == kind and c.order == n]
            d = max((min(curve_distance([p], c.points) for c in apts) for p in tpts),
                    default=math.nan)
            out.setdefault(kind, {})[str(n)] = d
    for kind in sorted({p.kind for p in tp}):
        orders = sorted({a.detail.get("order") for a in ap if a.kind == kind})
        for n in orders:
            near = [a.point for a in ap if a.kind == kind and a.detail.get("order") == n]
            d = max(min(math.dist(t.point, q) for q in near) for t in tp if t.kind == kind)
            out.setdefault(kind, {})[str(n)] = d
    return out


def merged(points: Sequence[Codim2Point], tol: float = 1e-6) -> list[Codim2Point]:
    """The codim-2 points with the copies found on two curves (a Bogdanov–Takens point
    ends both a fold and a Neimark–Sacker curve) merged, their curves listed in ``on``."""
    out: list[Codim2Point] = []
    for p in points:
        same = next((q for q in out if q.kind == p.kind and
                     q.detail.get("method") == p.detail.get("method") and
                     q.detail.get("order") == p.detail.get("order") and
                     math.dist(q.point, p.point) < tol * (1 + math.hypot(*p.point))), None)
        if same is None:
            out.append(p)
            continue
        on = sorted({*str(same.detail.get("on", "")).split(","), str(p.detail.get("on", ""))})
        out[out.index(same)] = Codim2Point(same.kind, same.point,
                                           {**dict(same.detail), "on": ",".join(on)})
    return out
