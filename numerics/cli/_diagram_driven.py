"""``kbm diagram`` for forced and coupled models: :func:`run_driven`.

A forced built-in (``duffing-forced``, ``vdp-forced``, ...) over the detuning ``sigma`` and
one other parameter: the true fold, period-doubling and Neimark–Sacker curves of its
periodic responses with their codim-2 points, and the slow flow's curves at orders
``1..--order`` (default 3) beside them (:mod:`numerics.bifurcation.forced`).  A coupled
built-in with a locked state (``coupled-vdp``) over the detuning and the coupling (or
``mu``): the locking tongue as the fold curves of the locked cycle, and the averaged tongue
at orders ``1..--order`` (default 2) (:mod:`numerics.bifurcation.coupled`).

The output is the :class:`numerics.bifurcation.result.Diagram` (``--json``: its JSON, keys
``curves`` and ``codim2``; else a summary); ``--out DIR`` writes the figure; the progress
(points of the true curves) goes to stderr.  With ``--store DIR`` every finished part is
kept (JSON files in a folder of the run), and the true curves' paths as they are when
Ctrl-C stops the run; ``--resume`` continues them from their last points.
"""

from __future__ import annotations

import argparse
import json
import sys

import numpy as np

from kbm.errors import ParameterError

__all__ = ["run_driven", "is_driven"]

_DEFAULT_ORDER = {"forced": 3, "coupled": 2}


def is_driven(name: str | None) -> str | None:
    """``"forced"``, ``"coupled"`` or ``None`` for a model name."""
    from kbm.model.coupled_builtins import COUPLED_MODELS
    from kbm.model.forced_builtins import FORCED_MODELS

    if name in FORCED_MODELS:
        return "forced"
    if name in COUPLED_MODELS:
        return "coupled"
    return None


def _curve(rec: dict, plane):
    """A stored curve, its points in the user's names (``plane``)."""
    from numerics.bifurcation.result import Curve

    rest = {k: v for k, v in rec.items() if k not in ("kind", "points", "method", "order")}
    return Curve(rec["kind"], [plane.point(p) for p in rec["points"]], rec["method"],
                 rec["order"], rest)


def _line(rec: dict, plane) -> dict:
    """A seed line's record (:func:`numerics.bifurcation.coupled.coupled_true_folds`) in the
    user's names and values (``plane``)."""
    i = plane.axes.index(rec["along"])
    (o_name, o), = rec["at"].items()
    along, other = plane.back[i], plane.back[1 - i]
    ends = sorted(along(x) for x in rec["to"])
    return {**rec, "at": {plane.user[1 - i]: other(o)}, "along": plane.user[i],
            "from": along(rec["from"]), "to": ends, "folds": [along(f) for f in rec["folds"]]}


def _point(rec: dict, plane):
    from numerics.bifurcation.result import Codim2Point

    return Codim2Point(rec["kind"], plane.point(rec["point"]),
                       {k: v for k, v in rec.items() if k not in ("kind", "point")})


def _setup(args: argparse.Namespace, kind: str):
    from numerics.cli.params.values import check, given, parse_vary

    if kind == "forced":
        from kbm.model.forced_builtins import get_forced_model

        model = get_forced_model(args.model)
    elif getattr(args, "rhs", None):
        from kbm.cli.derive import coupled_model

        model = coupled_model(args)
    else:
        from kbm.model.coupled_builtins import get_coupled_model

        model = get_coupled_model(args.model)
    name = model.name
    params = given(getattr(args, "param", None) or [])
    texts = list(getattr(args, "vary", None) or [])
    if len(texts) != 2:
        raise ParameterError(f"kbm diagram {name} takes two --vary, P1=A:B and P2=C:D "
                             f"(e.g. --vary sigma=-1:3 --vary "
                             f"{'h=0.02:0.5' if kind == 'forced' else 'c=0.05:0.6'}); got "
                             f"{len(texts)}")
    varies = [parse_vary(t) for t in texts]
    check(model, params, [v.name for v in varies],
          extra=("sigma",) if kind == "forced" else ())
    if "mu" not in params and "mu" not in [v.name for v in varies]:
        raise ParameterError("give the small parameter: -p mu=VALUE (e.g. -p mu=0.1)")
    if kind == "coupled":  # as kbm lock: mu <= 0 drew an empty tongue
        from numerics.cli.lock import coupled_mu

        coupled_mu(params, "the locking tongue is that")
    ranges = {v.name: v.interval("a two-parameter diagram", points=False) for v in varies}
    axes = (varies[0].name, varies[1].name)
    if kind == "forced" and "sigma" not in axes:
        raise ParameterError(f"a forced diagram varies the detuning and one other parameter: "
                             f"--vary sigma=FROM:TO --vary {axes[0]}=FROM:TO")
    from numerics.cli.params.plane import Plane

    # a physical axis (Delta) is computed as its scaled one (delta = Delta/mu), as -p binds it
    plane = Plane.of(model, params, axes, ranges)
    axes, ranges = plane.axes, dict(plane.ranges)
    mids = {a: 0.5 * (lo + hi) for a, (lo, hi) in plane.user_ranges.items()}
    resolved = model.resolve({**params, **mids})
    try:
        values = {k: float(v) for k, v in resolved.items() if k not in axes}
    except TypeError:
        raise ParameterError(f"give a number to every parameter of {name} "
                             f"({', '.join(sorted(resolved))})") from None
    order = getattr(args, "order", None)
    order = _DEFAULT_ORDER[kind] if order is None else order
    top = 3 if kind == "forced" else 4
    if not 1 <= order <= top:
        raise ParameterError(f"--order must be 1 to {top} for {name}, got {order}")
    return model, params, values, plane, order


class _Progress:
    """tqdm on stderr: the points of the true curves."""

    def __init__(self):
        from tqdm import tqdm

        self.bar = tqdm(desc="true curve points", unit="pt", file=sys.stderr, leave=False,
                        disable=None)

    def __call__(self, point, path):
        self.bar.update(1)

    def close(self):
        self.bar.close()


class _Records:
    """``get(key)``/``put(key, record)`` of the run's parts and paths in ``--store DIR``
    (:class:`numerics.bifurcation.store.PathStore`: one folder per run, one JSON file per
    key written atomically; ``get`` answers only with ``--resume``)."""

    def __init__(self, folder, resume: bool, definition: str):
        from numerics.bifurcation.store import PathStore

        if resume and not folder:
            raise ParameterError("--resume continues a diagram kept by --store DIR: give the "
                                 "folder")
        from numerics.cli.params.options import nothing_to_resume

        nothing_to_resume(folder, resume)
        self.store = PathStore(folder, definition, resume)

    def get(self, key: str):
        rec = self.store.get(key)
        return None if rec is None else rec["value"]

    def put(self, key: str, record) -> None:
        self.store.put(key, {"value": record})

    def close(self) -> None:
        pass


def _forced_parts(model, values, axes, ranges, order, store, progress, max_points=400):
    """The forced diagram's parts, each kept in ``store`` when finished (``true``,
    ``averaged``), and the paths of true task ``k`` (``task-k``) as they are when it ends or
    Ctrl-C stops it."""
    from numerics.bifurcation.path import CurvePath
    from numerics.bifurcation.forced import DrivenProblem, forced_seeds, forced_true_curves
    from numerics.bifurcation.forced_averaged import averaged_fold_curves

    from numerics.bifurcation.twoway import seed_levels

    prob = DrivenProblem(model, values, axes)
    o_name = axes[1 - axes.index("sigma")]
    lo, hi = ranges[o_name]
    others = seed_levels(lo, hi, 3)[::-1]  # inside the range: a seed on its edge is lost
    parts = {"true": store.get("true"), "averaged": store.get("averaged"),
             "interrupted": False}
    if parts["true"] is None:
        stored = {}
        for k in range(1000):
            rec = store.get(f"task-{k}")
            if rec is None:
                break
            stored[k] = [CurvePath.from_records(r) for r in rec]

        def on_task(idx, task):
            store.put(f"task-{idx}", [p.to_records() for p in task.paths])
            if any(p.end == "interrupted" for p in task.paths):
                parts["interrupted"] = True

        seeds = forced_seeds(prob, tuple(ranges["sigma"]), others)
        dropped: list = []
        _, curves, points = forced_true_curves(prob, ranges, seeds, progress=progress,
                                               on_task=on_task, stored=stored,
                                               max_points=max_points, dropped=dropped)
        parts["true"] = [[c.to_json() for c in curves], [p.to_json() for p in points],
                         {"dropped": dropped}]
        if parts["interrupted"]:
            return parts
        store.put("true", parts["true"])
    if parts["averaged"] is None:
        dropped = []
        curves, points = averaged_fold_curves(prob.forced, prob.values, axes, ranges,
                                              tuple(range(1, order + 1)), others,
                                              max_points=max_points, dropped=dropped)
        parts["averaged"] = [[c.to_json() for c in curves], [p.to_json() for p in points],
                             {"dropped": dropped}]
        store.put("averaged", parts["averaged"])
    return parts


def _coupled_parts(model, values, axes, ranges, order, store, progress, max_points=300):
    from numerics.bifurcation.coupled import (_seed_axis, coupled_averaged_folds,
                                              coupled_true_folds)
    from numerics.bifurcation.twoway import seed_levels

    o_name = axes[1 - _seed_axis(axes)]
    lo, hi = ranges[o_name]
    others = seed_levels(lo, hi, 2)
    parts = {"true": store.get("true"), "averaged": store.get("averaged"),
             "interrupted": False}
    if parts["true"] is None:
        dropped, lines = [], []
        curves, points = coupled_true_folds(model, values, axes, ranges, others,
                                            progress=progress, max_points=max_points,
                                            dropped=dropped, lines=lines)
        parts["true"] = [[c.to_json() for c in curves], [p.to_json() for p in points],
                         {"dropped": dropped, "seed_lines": lines}]
        if any("interrupted" in c.detail.get("ends", ()) for c in curves):
            parts["interrupted"] = True
            return parts
        store.put("true", parts["true"])
    if parts["averaged"] is None:
        dropped = []
        curves = coupled_averaged_folds(model, values, axes, ranges,
                                        tuple(range(1, order + 1)), others,
                                        max_points=max_points, dropped=dropped)
        parts["averaged"] = [[c.to_json() for c in curves], [], {"dropped": dropped}]
        store.put("averaged", parts["averaged"])
    return parts


def run_driven(args: argparse.Namespace) -> int:
    """``kbm diagram MODEL`` for a forced or coupled built-in (the module docstring).

    Returns the exit status: 0, or 130 when Ctrl-C stopped the run (what was found is
    printed, and kept with ``--store``).

    Raises
    ------
    kbm.errors.ParameterError
        For a model that is neither, a wrong parameter name, not two ``--vary``, or no
        ``sigma`` among a forced model's axes.
    """
    from numerics.bifurcation.twoway import distances, merged
    from numerics.bifurcation.result import Diagram
    from numerics.cli.params.values import within

    kind = "coupled" if getattr(args, "rhs", None) else is_driven(getattr(args, "model", None))
    if kind is None:
        raise ParameterError(f"{getattr(args, 'model', None)!r} is neither a forced nor a "
                             "coupled built-in (e.g. duffing-forced, vdp-forced, coupled-vdp)")
    model, params, values, plane, order = _setup(args, kind)
    axes, ranges = plane.axes, plane.ranges
    max_points = int(getattr(args, "max_points", None) or 400)
    within(max_points, "--max-points", 2, 100000)
    averaged = not getattr(args, "no_averaged", False)
    definition = json.dumps({"command": "diagram", "model": model.name,
                             "F": [str(f) for f in getattr(model, "F", ())] if kind == "coupled"
                             else str(getattr(model, "F", "")), "values": values, "axes": axes,
                             "ranges": ranges, "order": order, "max_points": max_points,
                             "averaged": averaged}, sort_keys=True)
    store = _Records(getattr(args, "store", None), bool(getattr(args, "resume", False)),
                     definition)
    progress = _Progress()
    parts_fn = _forced_parts if kind == "forced" else _coupled_parts
    try:
        parts = parts_fn(model, values, axes, ranges, order if averaged else 0, store,
                         progress, max_points)
    except (KeyboardInterrupt, SystemError) as exc:
        # inside compiled code (numba) Ctrl-C surfaces as a SystemError over the interrupt
        if isinstance(exc, SystemError) and not isinstance(exc.__context__, KeyboardInterrupt):
            raise
        parts = {"true": store.get("true"), "averaged": store.get("averaged"),
                 "interrupted": True}
    finally:
        progress.close()
        store.close()
    tc, tp, t_more = (list(parts["true"] or ([], [])) + [{}])[:3]
    ac, ap, a_more = (list(parts["averaged"] or ([], [])) + [{}])[:3]
    true_c, av_c = [_curve(c, plane) for c in tc], [_curve(c, plane) for c in ac]
    true_p, av_p = [_point(p, plane) for p in tp], [_point(p, plane) for p in ap]
    dropped = [{**d, "seed": None if d.get("seed") is None else list(plane.point(d["seed"]))}
               for d in [*t_more.get("dropped", ()), *a_more.get("dropped", ())]]
    diagram = Diagram(model.name, values, plane.user, plane.user_ranges, tuple(true_c + av_c),
                      tuple(merged(true_p + av_p)),
                      {"distance": distances(true_c, av_c, true_p, av_p),
                       "complete": not parts["interrupted"], "dropped": dropped,
                       **({"seed_lines": [_line(r, plane) for r in t_more["seed_lines"]]}
                          if "seed_lines" in t_more else {})})
    if getattr(args, "out", None):
        from kbm.cli._common import write_json
        from kbm.output.files import output_folder

        folder = output_folder(args.out)
        write_json(folder / "diagram.json", diagram.to_json())
        path = diagram.plot(folder / f"diagram-{diagram.model}.png")
        if not args.json:
            print(f"wrote {folder / 'diagram.json'} and {path}")
    if getattr(args, "json", False):
        from kbm.cli._common import emit_json

        emit_json(diagram.to_json())
    else:
        _summary(diagram)
    if parts["interrupted"]:
        print("stopped by Ctrl-C: the curves above are what was found"
              + (f"; run again with --resume to continue ({args.store})"
                 if getattr(args, "store", None) else " (keep them with --store DIR)"),
              file=sys.stderr)
        return 130
    return 0


def _summary(d) -> None:
    a, b = d.axes
    fixed = ", ".join(f"{k}={v:g}" for k, v in d.params.items())
    print(f"{d.model}: two-parameter diagram over {a} in {list(d.ranges[a])}, {b} in "
          f"{list(d.ranges[b])} ({fixed})")
    for c in d.curves:
        p = np.array(c.points)
        tag = "true" if c.method == "true" else f"averaged order {c.order}"
        extra = f", max residual {c.detail['residual_max']:.1e}" \
            if "residual_max" in c.detail else ""
        print(f"  {c.kind} ({tag}): {len(p)} points, {a} {p[:, 0].min():.6g}..{p[:, 0].max():.6g}"
              f", {b} {p[:, 1].min():.6g}..{p[:, 1].max():.6g}{extra}")
    for q in d.codim2:
        tag = "true" if q.detail.get("method") == "true" else \
            f"averaged order {q.detail.get('order')}"
        print(f"  {q.kind} ({tag}) at {a} = {q.point[0]:.8f}, {b} = {q.point[1]:.8f}")
    for kind, per in d.detail.get("distance", {}).items():
        for n, v in per.items():
            print(f"  distance true-averaged order {n} ({kind}): {v:.3e}")
    for rec in d.detail.get("dropped", ()):
        tag = "true" if rec["method"] == "true" else f"averaged order {rec['order']}"
        at = "" if rec.get("seed") is None else \
            f" from the seed at {a} = {rec['seed'][0]:.6g}, {b} = {rec['seed'][1]:.6g}"
        print(f"  no {rec['kind']} curve ({tag}){at}: {rec['reason']}")
    if not any(c.method == "true" for c in d.curves):
        lines = d.detail.get("seed_lines", ())
        print("  no true curve in the box" + (": the folds were looked for on "
                                              f"{len(lines)} lines" if lines else ""))
        for rec in lines:
            (o, v), = rec["at"].items()
            where = f"    at {o} = {v:.6g}, along {rec['along']} from {rec['from']:.6g}"
            if rec.get("cycle"):
                print(f"{where}: no locked cycle to start from ({rec['cycle']})")
            elif not rec["folds"]:
                print(f"{where} to {rec['to'][0]:.6g} and to {rec['to'][1]:.6g}: no fold of "
                      f"the locked cycle (period {rec['period']:.6g} at the start; continued to"
                      " both ends, or lost without a fold)")
            else:
                print(f"{where}: folds at " + ", ".join(f"{f:.8g}" for f in rec["folds"]))
