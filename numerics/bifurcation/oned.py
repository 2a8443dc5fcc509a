"""The two-parameter diagram of an autonomous one-degree-of-freedom model (issue 38).

:func:`autonomous_diagram` finds the curves' starting points by scans and continues each
(:func:`numerics.bifurcation.curve.continue_curve`) in both directions to the box's edges:

- **Hopf curves** and **folds of equilibria**: sign changes of ``tr J`` and changes of the
  number of equilibria on a grid of the plane (:mod:`numerics.bifurcation.autonomous`);
- **homoclinic and heteroclinic curves**: roots of the manifolds' gap on the grid's lines
  (:mod:`numerics.bifurcation.connections`);
- **folds of cycles**: the zeros of ``int div f dt`` along the true families of cycles
  ``(x_max, T, b)`` at fixed ``a`` (started from the energy balance's cycles,
  :mod:`numerics.bifurcation.averaged`), and the averaged folds;
- **codim-2 points**: the test functions' zeros (Bogdanov–Takens, Bautin, cusp), the ends
  of homoclinic curves inside the box (on the fold of their saddle: ``saddle-node-loop``;
  elsewhere: ``saddle-change``, the loop's manifold meets another saddle), the ends of fold
  curves where the period diverges (``fold-homoclinic``).

A seed already on a curve found is skipped.  The paths are kept by a
:class:`numerics.bifurcation.store.PathStore` and resumed from it.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np

from numerics.bifurcation import connections as C
from numerics.bifurcation.autonomous import OneDof
from numerics.bifurcation.cycle_folds import families, fold_curves
from numerics.bifurcation.curve import CurvePath, continue_curve, correct
from numerics.bifurcation.result import Codim2Point, Curve, Diagram
from numerics.bifurcation.store import PathStore
from numerics.errors import NumericsError

__all__ = ["Settings", "Interrupted", "autonomous_diagram"]


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


class _Run:
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
            q = np.asarray(c.points) / self.scale
            if len(q) == 1:
                if np.linalg.norm(q[0] - p) < tol:
                    return True
                continue
            d = q[1:] - q[:-1]
            t = np.clip(np.einsum("ij,ij->i", p - q[:-1], d) / np.maximum(
                np.einsum("ij,ij->i", d, d), 1e-300), 0, 1)
            if np.min(np.linalg.norm(q[:-1] + t[:, None] * d - p, axis=1)) < tol:
                return True
        return False

    def add_codim2(self, kind, ab, detail):
        p = np.asarray(ab, dtype=float) / self.scale
        for c in self.codim2:
            if c.kind == kind and np.linalg.norm(np.asarray(c.point) / self.scale - p) < 1e-4:
                return
        self.codim2.append(Codim2Point(kind, (float(ab[0]), float(ab[1])), detail))

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


def _scale(run: _Run, n_state: int, state_scale=1.0) -> np.ndarray:
    return np.concatenate([np.full(n_state, state_scale), run.scale])


def _grid(run: _Run):
    (a0, a1), (b0, b1) = run.box
    na, nb = run.s.grid
    return np.linspace(a0, a1, na), np.linspace(b0, b1, nb)


def _equilibrium_curves(run: _Run) -> None:
    """Hopf curves and folds of equilibria from the grid's scan."""
    kit = run.kit
    A, B = _grid(run)
    table = {(i, j): kit.equilibria(a, b, run.s.L) for i, a in enumerate(A)
             for j, b in enumerate(B)}
    seeds_h, seeds_sn = [], []
    for (i, j), eq in table.items():
        for di, dj in ((1, 0), (0, 1)):
            other = table.get((i + di, j + dj))
            if other is None:
                continue
            a, b = A[i], B[j]
            a2, b2 = A[i + di], B[j + dj]
            if len(other) != len(eq):  # a fold of equilibria between the two
                more, (am, bm) = (eq, (a, b)) if len(eq) > len(other) else (other, (a2, b2))
                less = other if more is eq else eq
                for (x1, k1), (x2, k2) in zip(more, more[1:]):
                    if k1 != k2 and not any(abs(y - 0.5 * (x1 + x2)) < 0.5 * abs(x2 - x1)
                                            for y, _ in less):
                        seeds_sn.append((0.5 * (x1 + x2), am, bm))
                continue
            for (x1, _), (x2, _) in zip(eq, other):
                t1, d1 = kit.eigen(x1, a, b)
                t2, d2 = kit.eigen(x2, a2, b2)
                if d1 > 0 and d2 > 0 and t1 * t2 < 0:
                    s = t1 / (t1 - t2)
                    seeds_h.append((x1 + s * (x2 - x1), a + s * (a2 - a), b + s * (b2 - b)))
    for kind, seeds, system in (("hopf", seeds_h, kit.hopf), ("saddle-node", seeds_sn,
                                                               kit.saddle_node)):
        G, tests = system()
        for z0 in seeds:
            try:  # onto the curve at the seed's b first: a seed on a curve found is skipped
                row = np.array([0.0, 0.0, 1.0])
                z0 = tuple(correct(G, np.array(z0, dtype=float), row, z0[2], tol=1e-11)[0])
            except NumericsError:
                pass
            except np.linalg.LinAlgError:
                continue
            if run.covered(kind, z0[1:]) or not run.inside(z0[1:]):
                continue
            key = f"{kind}|{z0[0]:.6f},{z0[1]:.6f},{z0[2]:.6f}"
            try:
                pts, events, ends = run.follow(key, G, np.array(z0), [0.0, 1.0, 1.0],
                                               scale=_scale(run, 1, 1.0), tests=tests,
                                               tol=1e-11)
            except NumericsError as exc:
                run.failures.append(f"{kind} from {tuple(round(v, 6) for v in z0)}: {exc}")
                continue
            _equilibrium_result(run, kind, pts, events)  # interrupted: the points so far
            if run.interrupted:
                return


def _equilibrium_result(run: _Run, kind, pts, events):
    kit = run.kit
    if kind == "hopf":  # keep tr J = 0 with det J > 0: the neutral saddles are no Hopf points
        segs, cur = [], []
        for p in pts:
            if kit.eigen(p.z[0], p.z[1], p.z[2])[1] > 0:
                cur.append(p)
            elif cur:
                segs.append(cur)
                cur = []
        if cur:
            segs.append(cur)
    else:
        segs = [pts]
    for seg in segs:
        if len(seg) < 2:
            continue
        xs = [float(p.z[0]) for p in seg]
        if kind == "hopf":
            run.hopf.append((np.array([p.z for p in seg])))
        run.curves.append(Curve(kind, [tuple(p.z[1:]) for p in seg], "true", None, {
            "equilibrium_x": [xs[0], xs[-1]],
            "residual_max": max(p.residual for p in seg)}))
    for ev in events:
        x, a, b = ev.z
        if ev.name == "bautin" and kit.eigen(x, a, b)[1] <= 0:
            continue
        run.add_codim2(ev.name, (a, b), {"on": kind, "x": float(x), "test": ev.value})


def _homoclinic_curves(run: _Run, sn_curves) -> None:
    """Connections from the scans along the grid's rows and columns."""
    kit = run.kit
    A, B = _grid(run)
    lines = [[(a, b) for a in np.linspace(A[0], A[-1], 2 * len(A))] for b in B[1:-1:2]]
    lines += [[(a, b) for b in np.linspace(B[0], B[-1], 2 * len(B))] for a in A[2:-1:6]]
    seeds = []
    for line in lines:
        seeds += C.scan(kit, line, run.s.L)
        if run.progress is not None:
            run.progress("scan", line[-1])
    for loop0, z0 in seeds:
        label = loop0.label()
        if run.covered("homoclinic", z0, tol=0.01):
            continue
        loop = loop0.copy()
        visited = []

        def reset(z, loop=loop, loop0=loop0):
            loop.x_from, loop.x_to = loop0.x_from, loop0.x_to
            C.accept(kit, loop, z)

        def on_point(pt, loop=loop, visited=visited):
            C.accept(kit, loop, pt.z)
            visited.append(loop.visits())

        key = f"homoclinic|{z0[0]:.6f},{z0[1]:.6f}|{label}|{loop0.leave}"
        try:
            pts, events, ends = run.follow(key, C.gap_function(kit, loop), np.array(z0),
                                           [1.0, 0.0], scale=run.scale, on_point=on_point,
                                           tol=C.GAP_TOL, fd_step=1e-6, reset=reset,
                                           tests={"saddle-quantity": C.saddle_quantity(kit,
                                                                                       loop)})
        except NumericsError as exc:
            run.failures.append(f"homoclinic from {tuple(round(v, 6) for v in z0)}: {exc}")
            continue
        if len(pts) < 2:
            if run.interrupted:
                return
            continue
        gaps = [p.residual for p in pts]
        run.curves.append(Curve("homoclinic", [tuple(p.z) for p in pts], "true", None, {
            "label": label, "saddles": loop0.visits(), "leave": loop0.leave,
            "arrive": loop0.arrive,
            "loop": "homoclinic" if loop0.homoclinic else "heteroclinic cycle",
            "gap_max": max(gaps)}))
        for end, p in ((ends[0], pts[0]), (ends[1], pts[-1])):
            if end in ("bounds", "interrupted", "max_points"):
                continue
            on_sn = any(_near(run, p.z, c) for c in sn_curves())
            run.add_codim2("saddle-node-loop" if on_sn else "saddle-change", tuple(p.z), {
                "on": "homoclinic", "label": label, "gap": p.residual})
        for ev in events:  # located to convergence on the curve: a fold of cycles ends here
            run.add_codim2("neutral-saddle-loop", tuple(ev.z), {
                "on": "homoclinic", "label": label, "saddle_quantity": ev.value,
                "gap": ev.residual})
        if run.interrupted:  # the points so far are kept above
            return


def _near(run, ab, curve, tol=2e-3) -> bool:
    q = np.asarray(curve.points) / run.scale
    return bool(np.min(np.linalg.norm(q - np.asarray(ab) / run.scale, axis=1)) < tol * 10)


def _distances(run: _Run, averaged: list[Curve]) -> list[Curve]:
    """Each averaged curve with its distance to the nearest true curve of its kind."""
    from dataclasses import replace

    out = []
    for c in averaged:
        best = None
        for i, t in enumerate(run.curves):
            if t.kind != c.kind or t.method != "true" or len(t.points) < 2:
                continue
            d = _to_polyline(np.asarray(c.points), np.asarray(t.points))
            if best is None or np.median(d) < np.median(best[1]):
                best = (i, d)
        if best is not None:
            c = replace(c, detail={**c.detail, "distance_to": best[0],
                                   "distance_max": float(np.max(best[1])),
                                   "distance_median": float(np.median(best[1]))})
        out.append(c)
    return out


def _to_polyline(ps, q):
    d = q[1:] - q[:-1]
    out = []
    for p in ps:
        t = np.clip(np.einsum("ij,ij->i", p - q[:-1], d) / np.maximum(
            np.einsum("ij,ij->i", d, d), 1e-300), 0, 1)
        out.append(float(np.min(np.linalg.norm(q[:-1] + t[:, None] * d - p, axis=1))))
    return np.array(out)


def autonomous_diagram(model, params: Mapping, axes: tuple[str, str], ranges: Mapping, *,
                       settings: Settings = Settings(), store: PathStore | None = None,
                       progress: Callable | None = None, name: str | None = None) -> Diagram:
    """The diagram of ``model`` over ``ranges[axes[0]] x ranges[axes[1]]`` (module
    docstring).  Raises :class:`Interrupted` (with the partial diagram) on Ctrl-C."""
    from numerics.bifurcation import averaged as avg

    (a0, a1), (b0, b1) = ranges[axes[0]], ranges[axes[1]]
    kit = OneDof(model, params, axes, (0.5 * (a0 + a1), 0.5 * (b0 + b1)))
    run = _Run(kit, ranges, store or PathStore(None, ""), progress, settings)
    averaged, seeds, note = [], [], ""

    def finish() -> Diagram:
        curves = run.curves + _distances(run, averaged)
        return Diagram(name or getattr(model, "name", str(model)), dict(params), tuple(axes),
                       dict(ranges), tuple(curves), tuple(run.codim2), {
                           "averaged_note": note, "failures": list(run.failures),
                           "period_doubling": "none: the non-trivial "
                           "multiplier of a planar autonomous flow is exp(int div f) > 0"})

    try:
        _equilibrium_curves(run)
        if run.interrupted:
            raise Interrupted(finish())
        _homoclinic_curves(run, lambda: [c for c in run.curves if c.kind == "saddle-node"])
        if run.interrupted:
            raise Interrupted(finish())
        if settings.averaged:
            rec = run.store.get("averaged")
            if rec is not None:
                averaged = [Curve(c["kind"], c["points"], "averaged", c["order"],
                                  {k: v for k, v in c.items()
                                   if k not in ("kind", "points", "method", "order")})
                            for c in rec["curves"]]
                seeds, note = [tuple(s[:4]) + (tuple(s[4]),) for s in rec["seeds"]], rec["note"]
            else:
                if "mu" in axes:
                    averaged = avg.kbm_fold_curves(model, params, axes, ranges,
                                                   orders=settings.orders, progress=lambda: progress and progress(
                                                       "averaged", (a0, b0)))
                else:
                    averaged, note = avg.energy_balance_curves(
                        model, params, axes, ranges, n=_averaged_grid(settings), seeds=seeds,
                        progress=lambda: progress and progress("averaged", (a0, b0)))
                run.store.put("averaged", {"curves": [c.to_json() for c in averaged],
                                           "seeds": [list(s[:4]) + [list(s[4])] for s in seeds],
                                           "note": note})
        fold_seeds = families(run, seeds)
        if run.interrupted:
            raise Interrupted(finish())
        fold_seeds += _averaged_fold_seeds(kit, averaged)
        fold_curves(run, fold_seeds)
        if run.interrupted:
            raise Interrupted(finish())
    except KeyboardInterrupt:
        raise Interrupted(finish()) from None
    return finish()


def _averaged_grid(settings: Settings) -> int:
    """The averaged grid includes the family lines (every ``k``-th value)."""
    k = max(1, (settings.averaged_points - 1) // (settings.family_lines + 1))
    return k * (settings.family_lines + 1) + 1


def _averaged_fold_seeds(kit, averaged) -> list:
    """Fold seeds from the averaged folds: ``x_max`` from the energy (or amplitude) and the
    period ``2 pi/omega0``."""
    out = []
    for c in averaged:
        if c.kind != "fold" or not c.points:
            continue
        a, b = c.points[len(c.points) // 2]
        cm = kit.compiled(a, b)
        out.append((c.detail.get("amplitude", 1.0), 2 * math.pi / cm.omega0, a, b))
    return out
