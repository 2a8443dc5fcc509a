"""``kbm branch``: branches of limit cycles in one parameter (continuation, folds, ends)."""

from __future__ import annotations

import argparse
import math

from kbm.cli._common import check_model_flags, emit_json, model_spec, single_well
from kbm.errors import ParameterError
from numerics.cli.params.options import command, options


def register(sub) -> None:
    p = command(sub, "branch", "Follow every limit cycle found at the start value through the "
                "range of one parameter by pseudo-arclength continuation of the shooting solution "
                "(stable and unstable cycles, Floquet multipliers at each point), with folds of "
                "cycles, Hopf ends and homoclinic ends located, next to the roots of the KBM "
                "amplitude equation and of the energy balance.", "param", "vary", "orders",
                models="vdp, rayleigh, sedf, cdc, ...; coupled: coupled-vdp, sedf-dimer, ...",
                coupled=True, vary=dict(
        required=True,
        help="the parameter and its range, e.g. --vary Delta=0:4; the branch starts at --param "
             "NAME=VALUE if given, else at FROM"), orders=dict(
        default="1", metavar="N,...",
        help="KBM orders of the analytic branches (default 1; 'none' for none)"))
    p.add_argument("--no-energy", action="store_true",
                   help="leave out the energy-balance branch")
    options(p, "max_points", "rtol", max_points=dict(
        help="bound on the points per direction of each branch (default 400)"),
        rtol=dict(help="integrator tolerance (1e-10)"))
    p.add_argument("--follow-period", type=float, default=None, metavar="FACTOR",
                   help="at a homoclinic end, follow the cycle in its period (multiple "
                        "shooting, the parameter free) until the period is FACTOR times the "
                        "start's (AUTO-07p's standard: 20); the points join the branch")
    options(p, "start", "json", start=dict(metavar="X1,..,XDOT1,.."))
    p.set_defaults(func=run)


def _checked(args: argparse.Namespace, params: dict, name: str):
    """The model of the command line (a built-in name or the ``--rhs`` model), its names
    and, with ``--follow-period``, its saddle checked."""
    from kbm.parameters.names import lookup
    from numerics.cli.params.values import check, wavenumber

    spec = model_spec(args)
    model = lookup(spec, ("one",)) if isinstance(spec, str) else spec
    check(model, params, [name], start=True)
    wavenumber(model, params)
    if args.follow_period is not None and single_well(model):
        raise ParameterError(f"--follow-period follows a branch to a homoclinic end, and "
                             f"{model.name} has none: its only equilibrium is the origin, "
                             "which is no saddle (F at x' = 0 does not depend on x); drop it")
    return spec


def run(args: argparse.Namespace) -> int:
    if len(args.vary) > 1:  # the last --vary silently replaced the others
        raise ParameterError(f"kbm branch follows one parameter: give one --vary (got "
                             f"{', '.join(v.split('=')[0] for v in args.vary)}); kbm diagram "
                             "draws a plane of two")
    args.vary = args.vary[0]
    from numerics.flow.aot import allow_builds

    allow_builds()  # start-up is what this command is waited for (issue 39)
    from numerics.flow.card import use_cards

    use_cards()  # the stored seeds of the start (numerics.cycles.seeds): no energy method
    try:
        return _run(args)
    finally:
        use_cards(False)  # this command's (a process may run others after)


def _checked_key(args: argparse.Namespace, params: dict) -> str | None:
    """The name of the record that a run of a built-in model with these ``-p`` values and
    this ``--vary`` (and ``--follow-period`` or not) passed the model's checks (the names,
    the kind of model, a saddle to follow), under the model card's key
    (:func:`numerics.flow.card.card_key`); ``None`` for a ``--rhs`` model."""
    from numerics.flow.card import card_key

    if getattr(args, "rhs", None) or not isinstance(args.model, str):
        return None
    from numerics.flow.line_card import source_digest

    code = source_digest("numerics/cli/branch.py", "numerics/cli/params/values.py")  # the checks
    return card_key(args.model, {**params, "--branch": f"{args.vary}|{code}|"
                                                       f"{args.follow_period is not None}"})


def _run(args: argparse.Namespace) -> int:
    from numerics.cli._coupled_branch import shown
    from numerics.cli.params.values import given, orders, parse_vary, within
    from numerics.comparison.diagram import branch_diagram
    from numerics.flow.template_cache import FORMAT, read_record, write_record

    from kbm.cli.derive import is_coupled

    vary = parse_vary(args.vary)
    lo, hi = vary.interval("a branch", points=False)
    name = vary.name
    params = given(args.param)
    key = _checked_key(args, params)
    checked = key is not None and read_record(key, "branch") is not None
    if args.model and not args.rhs and not checked:
        from kbm.parameters.names import lookup

        lookup(args.model, ("one", "coupled"), rhs=True)
    if is_coupled(args):
        from kbm.cli.derive import coupled_model
        from numerics.cli._coupled_branch import run_coupled_branch

        if args.orders != "1" or args.no_energy:
            raise ParameterError("--orders and --no-energy are for one degree of freedom; a "
                                 "coupled branch is the true one (compare kbm derive, kbm lock)")
        if args.follow_period is not None:
            raise ParameterError("--follow-period follows a homoclinic end of a branch of one "
                                 "degree of freedom; the coupled continuation locates no "
                                 "homoclinic ends, so there is nothing to follow: drop it")
        model = coupled_model(args)
        return run_coupled_branch(args, name, lo, hi, "branch", model=model)
    if args.follow_period is not None and not (math.isfinite(args.follow_period)
                                               and 1 < args.follow_period <= 100):
        raise ParameterError(f"--follow-period must be a factor between 1 and 100, got "
                             f"{args.follow_period}")
    if args.start is not None:
        raise ParameterError("--start is for coupled systems (a built-in such as coupled-vdp, "
                             "or several --rhs)")
    within(args.rtol, "--rtol", 1e-14, 1e-4)
    within(args.max_points, "--max-points", 2, 100000)
    if name == "mu":  # the library said "give mu != 0", which was never typed
        from numerics.shooting.arclength import start_value

        start = start_value("mu", params["mu"]) if "mu" in params else lo
        if start == 0:
            where = f"-p mu={params['mu']}" if "mu" in params else f"--vary {vary.text}"
            raise ParameterError(f"{where} starts the branch at mu = 0, where there is no "
                                 "perturbation and no isolated cycle: start it at mu != 0, "
                                 "with -p mu=VALUE inside the range or a range with FROM "
                                 "!= 0")
    if checked:  # checked by an earlier run: no symbolic model (issue 39)
        check_model_flags(args)
        spec = args.model
    else:
        spec = _checked(args, params, name)
        if key is not None:
            write_record(key, {"format": FORMAT, "key": key}, "branch")
    d = branch_diagram(spec, params, name, (lo, hi),
                       orders=orders(args.orders, none=True), energy=not args.no_energy,
                       rtol=args.rtol, max_points=args.max_points,
                       follow_period=args.follow_period)
    followed = any(s.kind == "homoclinic" for b in d.branches for s in b.special)
    if args.follow_period is not None and not followed:
        import sys

        print(f"kbm branch: note: --follow-period had nothing to follow: no branch of "
              f"{d.model} ends at a homoclinic orbit in {name} from {lo:g} to {hi:g}",
              file=sys.stderr)
    if args.json:
        return emit_json(d.to_json())
    print(f"{len(d.branches)} branch(es) of limit cycles of {d.model}, {name} from {lo:g} "
          f"to {hi:g}")
    for i, b in enumerate(d.branches):
        print(f"\nbranch {i}: {len(b.points)} points, {b.evaluations} integrations of a period"
              + (f"; {b.dropped} more passed but not printed (trivial multiplier off 1 by more "
                 "than 1e-5: not converged)" if b.dropped else ""))
        print(f"  {name:>14s} {'amplitude_max':>14s} {'period':>12s} {'multiplier':>12s}")
        for p in shown(b.points):
            print(f"  {p.parameter:14.8g} {p.amplitude_max:14.8g} {p.period:12.8g} "
                  f"{p.multipliers[1].real:12.4e} {'stable' if p.stable else 'UNSTABLE'}")
        for s in b.special:
            if s.kind == "homoclinic":
                print(f"  homoclinic end near {name} = {s.parameter:.6g} (the error bar and "
                      "how it was found: the end line below)")
                continue
            print(f"  {s.kind}: {name} = {s.parameter:.10g}, amplitude {s.amplitude:.6g}")
        for r in b.reasons:
            print(f"  end: {r}")
    for c in d.analytic:
        folds = ", ".join(f"{name} = {f.parameter:.10g} (a = {f.amplitude:.6g})"
                          for f in c.folds) or "none"
        print(f"\n{c.method} order {c.order}: {len(c.points)} predicted cycles on the grid; "
              f"folds: {folds}")
    for f in d.failures:
        print(f"\nnot continued: {f}")
    return 0
