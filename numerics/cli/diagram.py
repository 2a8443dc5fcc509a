"""``kbm diagram``: bifurcation diagrams in two parameters (issue 38).

The codim-1 curves continued in the plane of two ``--vary`` parameters, their codim-2
points, and the averaged curves beside them (:mod:`numerics.bifurcation`).  Autonomous
models of one degree of freedom are drawn here (:func:`numerics.bifurcation.oned.autonomous_diagram`);
forced and coupled systems by :func:`numerics.cli._diagram_driven.run_driven`, with the same
arguments (``args.model``, ``param``, ``vary``, ``json``, ``out``, ``store``, ``resume``,
``order``).
"""

from __future__ import annotations

import argparse
import sys

from kbm.cli._common import emit_json, model_spec, write_json
from kbm.errors import ParameterError
from numerics.cli.params.options import command, options


def register(sub) -> None:
    p = command(sub, "diagram", "Continue the codim-1 bifurcation curves in the plane of two "
                "parameters (Hopf points and folds of equilibria, folds of cycles, homoclinic and "
                "heteroclinic connections; forced and coupled systems: folds, period doublings, "
                "Neimark-Sacker curves), locate their codim-2 points (Bogdanov-Takens, Bautin, "
                "cusp, ends of curves on others) and draw the averaged curves on the same axes.  "
                "Every point of a true curve is converged (a homoclinic point: the manifolds' gap "
                "below 1e-10).", "param", "vary", "order",
                models="sedf, vdp, ... or --rhs; forced: duffing-forced, ...; coupled: "
                       "coupled-vdp, ...", coupled=True, vary=dict(
        help="the two axes and their ranges, e.g. --vary Delta=0:6 --vary beta=0.3:1.6 (the "
             "first is the horizontal axis)"), order=dict(
        help="highest averaged order (one degree of freedom with mu an axis: KBM orders 1..N, "
             "default 3; the energy balance is order 1)"))
    p.add_argument("--grid", default="25,9", metavar="NA,NB",
                   help="points of the scans for the curves' starts on each axis (default "
                        "25,9)")
    p.add_argument("--x-range", type=float, default=8.0, metavar="L",
                   help="equilibria and saddles are looked for in |x| <= L (default 8)")
    options(p, "max_points", max_points=dict(
        help="points per direction of each curve at most (default 400)"))
    p.add_argument("--no-averaged", action="store_true", help="leave out the averaged curves")
    options(p, "json", "out", "store", "resume", out=dict(
        help="write diagram.json and the figure diagram-MODEL.png into DIR"), store=dict(
        metavar="DIR", help="keep every curve's points in DIR as they are found (a stopped run "
                            "can be resumed)"), resume=dict(
        help="with --store: continue the stored run (finished curves are read back, an "
             "interrupted one continued from its last point)"))
    p.set_defaults(func=run)


def _driven(args) -> bool:
    """Forced or coupled: a forced built-in, a coupled system, or an ``--rhs`` in ``t``."""
    from kbm.cli.derive import is_coupled

    if is_coupled(args):
        return True
    if args.model and not args.rhs:
        from kbm.model.forced_builtins import FORCED_MODELS

        return args.model in FORCED_MODELS
    return False


def _axes(args):
    from numerics.cli.params.values import parse_vary

    if len(args.vary) != 2:
        raise ParameterError(f"kbm diagram draws a plane of two parameters: give two --vary "
                             f"NAME=FROM:TO (got {len(args.vary)}), e.g. --vary Delta=0:6 "
                             "--vary beta=0.3:1.6")
    varies = [parse_vary(t) for t in args.vary]
    ranges = {}
    for v in varies:
        ranges[v.name] = v.interval("a diagram", points=False)
    if varies[0].name == varies[1].name:
        raise ParameterError(f"--vary {varies[0].name} is given twice: vary two parameters")
    return (varies[0].name, varies[1].name), ranges


def _defined(model, params, ranges) -> None:
    """Refuse a ``-p`` value at which a scaled parameter of an axis is undefined for every
    value of the axis (``-p mu=0`` with ``--vary Delta=0:6``: ``delta = Delta/mu``), naming
    the values typed (the message named the plane's centre, ``Delta = 3``, never typed)."""
    import sympy as sp
    from kbm.model.builtins import parameter_value

    for scaled, expr in getattr(model, "physical", {}).items():
        needs = {s.name for s in expr.free_symbols}
        on = [n for n in ranges if n in needs]
        fixed = {n: parameter_value(n, params[n]) for n in needs if n in params}
        if not on or not fixed:
            continue
        value = sp.sympify(expr).subs({sp.Symbol(n): v for n, v in fixed.items()})
        if value.has(sp.zoo, sp.nan, sp.oo, -sp.oo):
            zero = [n for n, v in fixed.items() if v == 0]
            span = ", ".join(f"{n} = {ranges[n][0]:g}:{ranges[n][1]:g}" for n in on)
            raise ParameterError(f"{scaled} = {expr} is undefined for "
                                 + ", ".join(f"{n} = {params[n]}" for n in sorted(fixed))
                                 + f" at every {span} of --vary"
                                 + (f": give {' and '.join(zero)} != 0" if zero else ""))


def _grid(text: str) -> tuple[int, int]:
    try:
        na, nb = (int(s) for s in text.split(","))
    except ValueError:
        raise ParameterError(f"--grid takes NA,NB (two integers), got {text!r}") from None
    if not (3 <= na <= 400 and 3 <= nb <= 400):
        raise ParameterError(f"--grid NA,NB must be 3 to 400 each, got {text!r}")
    return na, nb


def run(args: argparse.Namespace) -> int:
    if args.resume and not args.store:
        raise ParameterError("--resume continues a diagram kept by --store DIR: give the folder")
    from numerics.cli.params.options import nothing_to_resume

    nothing_to_resume(args.store, args.resume)  # a fresh run started without a word
    if _driven(args):
        from numerics.cli._diagram_driven import run_driven

        return run_driven(args)
    from kbm.parameters.names import lookup
    from numerics.cli.params.values import check, given, within

    params = given(args.param)
    axes, ranges = _axes(args)
    spec = model_spec(args)
    model = lookup(spec, ("one",), rhs=True) if isinstance(spec, str) else spec
    check(model, params, list(axes))
    if not model.is_autonomous:
        from numerics.cli._diagram_driven import run_driven

        return run_driven(args)
    if "mu" not in params and "mu" not in axes:
        raise ParameterError("give the small parameter: -p mu=VALUE (or vary it)")
    _defined(model, params, ranges)
    within(args.max_points, "--max-points", 2, 100000)
    if not 0 < args.x_range <= 1e4:
        raise ParameterError(f"--x-range must be positive (at most 1e4), got {args.x_range}")
    order = 3 if args.order is None else args.order
    within(order, "--order", 1, 4)
    return _run_autonomous(args, model, params, axes, ranges, order)


def _run_autonomous(args, model, params, axes, ranges, order) -> int:
    from numerics.bifurcation.oned import autonomous_diagram
    from numerics.bifurcation.run import Interrupted, Settings
    from numerics.bifurcation.store import PathStore

    settings = Settings(L=args.x_range, grid=_grid(args.grid), max_points=args.max_points,
                        averaged=not args.no_averaged, orders=tuple(range(1, order + 1)))
    definition = repr((model.name, str(getattr(model, "F", "")), sorted(params.items()), axes,
                       sorted(ranges.items()), settings.text()))
    store = PathStore(args.store, definition, args.resume)
    from tqdm.auto import tqdm

    bar = tqdm(total=None, file=sys.stderr, unit="pt", desc="kbm diagram", disable=None,
               leave=False)

    def progress(kind, ab):
        bar.set_description(f"{kind} at ({ab[0]:.4g}, {ab[1]:.4g})", refresh=False)
        bar.update(1)

    interrupted = False
    try:
        d = autonomous_diagram(model, params, axes, ranges, settings=settings, store=store,
                               progress=progress, name=model.name)
    except Interrupted as exc:
        d, interrupted = exc.diagram, True
    finally:
        bar.close()
    _write(args, d)
    if interrupted:
        print("kbm diagram: interrupted; the curves above are what was found"
              + (f"; run again with --store {args.store} --resume to continue" if args.store
                 else " (give --store DIR to keep the points of a long run)"), file=sys.stderr)
        return 130
    return 0


def _write(args, d) -> None:
    from kbm.output.files import output_folder

    data = d.to_json()
    if args.out:
        folder = output_folder(args.out)
        write_json(folder / "diagram.json", data)
        d.plot(folder / f"diagram-{d.model}.png")
    if args.json:
        emit_json(data)
        return
    a, b = d.axes
    fixed = ", ".join(f"{k}={v}" for k, v in d.params.items())
    fixed = f" ({fixed})" if fixed else ""  # every parameter an axis: no empty "()"
    print(f"bifurcation diagram of {d.model}{fixed} over {a} in [{d.ranges[a][0]:g}, "
          f"{d.ranges[a][1]:g}] and {b} in [{d.ranges[b][0]:g}, {d.ranges[b][1]:g}]")
    for c in d.curves:
        src = "true" if c.method == "true" else f"averaged order {c.order}"
        (p0, q0), (p1, q1) = c.points[0], c.points[-1]
        extra = c.detail.get("label") or c.detail.get("source") or ""
        dist = c.detail.get("distance_median")
        print(f"  {c.kind:<12s} {src:<18s} {len(c.points):4d} points from ({p0:.8g}, {q0:.8g}) "
              f"to ({p1:.8g}, {q1:.8g})" + (f"  {extra}" if extra else "")
              + (f"  (median distance to true: {dist:.3g})" if dist is not None else ""))
    for p in d.codim2:
        print(f"  {p.kind:<18s} at {a} = {p.point[0]:.10g}, {b} = {p.point[1]:.10g}"
              f"  (on {p.detail.get('on', '?')})")
    if not d.codim2:
        print("  no codim-2 point in the box")
    if args.out:
        print(f"wrote {args.out}/diagram.json and {args.out}/diagram-{d.model}.png")
