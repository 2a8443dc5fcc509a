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
  of homoclinic curves inside the box (on the fold of their saddle: ``saddle-node-loop``,
  located on the fold curve as the zero of the saddle-node's manifolds' gap,
  :func:`numerics.bifurcation.saddle_node_loop.locate_saddle_node_loop`;
  elsewhere ``saddle-change`` where the loop's (or a symmetric heteroclinic cycle's)
  manifold meets the next saddle, located as
  the zero of both connections' gaps, :func:`numerics.bifurcation.connections.saddle_change`;
  an end neither is ``connection-end``), the zeros of the saddle quantity along homoclinic
  curves (``neutral-saddle-loop``), the ends of fold
  curves where the period diverges (``fold-homoclinic``).

A seed already on a curve found is skipped.  The paths are kept by a
:class:`numerics.bifurcation.store.PathStore` and resumed from it.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping

import numpy as np

from numerics.bifurcation import connections as C
from numerics.bifurcation.autonomous import OneDof
from numerics.bifurcation.corrector import correct
from numerics.bifurcation.cycle_folds import families, fold_curves
from numerics.bifurcation.result import Curve, Diagram
from numerics.bifurcation.run import Interrupted, Run, Settings, distances, near, runs
from numerics.bifurcation.store import PathStore
from numerics.errors import NumericsError

__all__ = ["autonomous_diagram"]


def _scale(run: Run, n_state: int, state_scale=1.0) -> np.ndarray:
    return np.concatenate([np.full(n_state, state_scale), run.scale])


def _grid(run: Run):
    (a0, a1), (b0, b1) = run.box
    na, nb = run.s.grid
    return np.linspace(a0, a1, na), np.linspace(b0, b1, nb)


def _equilibrium_curves(run: Run) -> None:
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


def _equilibrium_result(run: Run, kind, pts, events):
    kit = run.kit
    if kind == "hopf":  # keep tr J = 0 with det J > 0: the neutral saddles are no Hopf points
        segs = runs(pts, lambda p: kit.eigen(p.z[0], p.z[1], p.z[2])[1] > 0)
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


def _homoclinic_curves(run: Run, sn_curves) -> None:
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
        at = {}  # the saddles at each accepted point (a curve's end is located from them)

        def reset(z, loop=loop, loop0=loop0):
            loop.x_from, loop.x_to = loop0.x_from, loop0.x_to
            C.accept(kit, loop, z)

        def on_point(pt, loop=loop, visited=visited, at=at):
            C.accept(kit, loop, pt.z)
            visited.append(loop.visits())
            at[tuple(float(v) for v in pt.z)] = (loop.x_from, loop.x_to)

        key = f"homoclinic|{z0[0]:.6f},{z0[1]:.6f}|{label}|{loop0.leave}"
        found = run.attempt("homoclinic", z0, key, C.gap_function(kit, loop), [1.0, 0.0],
                            scale=run.scale, on_point=on_point, tol=C.GAP_TOL, fd_step=1e-6,
                            reset=reset, tests={"saddle-quantity": C.saddle_quantity(kit,
                                                                                     loop)})
        if found is None:
            if run.interrupted:
                return
            continue
        pts, events, ends = found
        gaps = [p.residual for p in pts]
        run.curves.append(Curve("homoclinic", [tuple(p.z) for p in pts], "true", None, {
            "label": label, "saddles": loop0.visits(), "leave": loop0.leave,
            "arrive": loop0.arrive,
            "loop": "homoclinic" if loop0.homoclinic else "heteroclinic cycle",
            "gap_max": max(gaps)}))
        for end, p in ((ends[0], pts[0]), (ends[1], pts[-1])):
            if end in ("bounds", "interrupted", "max_points"):
                continue
            here = loop0.copy()
            here.x_from, here.x_to = at.get(tuple(float(v) for v in p.z),
                                            (loop0.x_from, loop0.x_to))
            if any(near(run, p.z, c, tol=5e-3) for c in sn_curves()) and \
                    _saddle_node_loop(run, here, label, p):
                continue
            _saddle_change(run, here, label, p)
        for ev in events:  # located to convergence on the curve: a fold of cycles ends here
            run.add_codim2("neutral-saddle-loop", tuple(ev.z), {
                "on": "homoclinic", "label": label, "saddle_quantity": ev.value,
                "gap": ev.residual})
        if run.interrupted:  # the points so far are kept above
            return


def _saddle_node_loop(run: Run, loop0, label: str, p) -> bool:
    """The end ``p`` of a homoclinic curve near a fold of equilibria: the saddle-node loop
    located on the fold curve (:func:`numerics.bifurcation.saddle_node_loop.
    locate_saddle_node_loop`: the fold conditions and the saddle-node's manifolds' gap at
    most ``GAP_TOL``, the parameter along the fold to ``1e-10``) and reported when within
    5 % of the box of ``p``; ``False`` where it is not located."""
    from numerics.bifurcation.saddle_node_loop import locate_saddle_node_loop

    loop = loop0.copy()
    try:
        C.accept(run.kit, loop, p.z)
    except C._FAIL:
        return False
    found = locate_saddle_node_loop(run.kit, loop, p.z, scale=run.scale)
    if found is None or np.linalg.norm((np.asarray(found["point"]) - p.z) / run.scale) > 0.05:
        return False
    run.add_codim2("saddle-node-loop", found["point"], {
        "on": "homoclinic", "label": label, "gap": found["gap"], "x": found["x"],
        "fold_residual": found["fold_residual"], "parameter_step": found["parameter_step"],
        "along": found["along"], "last_curve_point": [float(v) for v in p.z],
        "note": "located on the fold of equilibria: f = f_x = 0 and the saddle-node's "
        "centre and strong manifolds' gap zero; last_curve_point: the homoclinic curve's "
        "last point"})
    return True


def _saddle_change(run: Run, loop0, label: str, p) -> None:
    """The end ``p`` of a homoclinic curve away from a fold: the saddle change located
    (:func:`numerics.bifurcation.connections.saddle_change`, both legs' gaps at most
    ``GAP_TOL``) within 5 % of the box from ``p``, else an unnamed ``connection-end``."""
    loop = loop0.copy()
    found = None
    try:
        C.accept(run.kit, loop, p.z)
        found = C.saddle_change(run.kit, loop, p.z, run.s.L, scale=run.scale)
    except C._FAIL:
        pass
    last = [float(v) for v in p.z]
    if found is not None and np.linalg.norm(
            (np.asarray(found["point"]) - p.z) / run.scale) < 0.05:
        run.add_codim2("saddle-change", found["point"], {
            "on": "homoclinic", "label": label, "gap": max(abs(g) for g in found["gaps"]),
            "saddles": found["saddles"], "gaps": found["gaps"], "last_curve_point": last,
            "note": "the heteroclinic cycle of the saddles located (both connections' "
            "section gaps zero); last_curve_point: the homoclinic curve's last point"})
        return
    bt = [c.point for c in run.codim2 if c.kind == "bogdanov-takens" and np.linalg.norm(
        (np.asarray(c.point) - p.z) / run.scale) < 0.01]
    run.add_codim2("connection-end", tuple(p.z), {
        "on": "homoclinic", "label": label, "gap": p.residual,
        "note": "the curve's end inside the box, at no located saddle-node loop or saddle "
        "change" + (f"; within 1 % of the box of the Bogdanov-Takens point {tuple(bt[0])}, "
                    "where a homoclinic curve shrinks into its equilibrium" if bt else "")})


def autonomous_diagram(model, params: Mapping, axes: tuple[str, str], ranges: Mapping, *,
                       settings: Settings = Settings(), store: PathStore | None = None,
                       progress: Callable | None = None, name: str | None = None) -> Diagram:
    """The diagram of ``model`` over ``ranges[axes[0]] x ranges[axes[1]]`` (module
    docstring).  Raises :class:`Interrupted` (with the partial diagram) on Ctrl-C."""
    from numerics.bifurcation import averaged as avg

    (a0, a1), (b0, b1) = ranges[axes[0]], ranges[axes[1]]
    kit = OneDof(model, params, axes, (0.5 * (a0 + a1), 0.5 * (b0 + b1)))
    run = Run(kit, ranges, store or PathStore(None, ""), progress, settings)
    averaged, seeds, note = [], [], ""

    def finish() -> Diagram:
        curves = run.curves + distances(run, averaged)
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
