"""``kbm compare``: KBM predictions of several orders next to the true limit cycle."""

from __future__ import annotations

import argparse

from kbm.cli._common import (ONE_DOF, checked_params, describe_params, emit_json, model_spec,
                             parse_params, show)
from kbm.errors import ModelError, ParameterError
from numerics.cli.params.options import command, options


def register(sub) -> None:
    p = command(sub, "compare", "Compare the limit cycle predicted by the KBM expansion of each "
                "order (first-harmonic amplitude, maximum of x, frequency, third harmonic, "
                "Floquet multiplier, dissipation over the reconstructed cycle) with the cycle "
                "computed by shooting.", "param", "orders", models=ONE_DOF,
                orders=dict(help="comma-separated KBM orders (default 1,2)"))
    p.add_argument("--energy-orders", default=None, metavar="N,...",
                   help="orders of the averaging about the conservative orbit shown next to "
                        "KBM (default 1,2; 'none' to leave them out)")
    p.add_argument("--paper", action="store_true",
                   help="add the paper's eqs. (5)-(9) as printed (sedf only)")
    options(p, "x_start", x_start=dict(
        help="start of the transient if Newton from the KBM cycle fails"))
    for flag, text in STUDIES.items():
        p.add_argument(flag, help=text, **(dict(metavar=VALUES[flag]) if flag in VALUES else
                                           dict(action="store_true")))
    options(p, "json")
    p.set_defaults(func=run)


#: the separate studies of ``kbm compare`` (one at a time): flag -> help
STUDIES = {
    "--convergence": "convergence study: errors of each order for these values of mu, with the "
                     "other parameters (scaled names, e.g. delta) fixed; prints fitted log-log "
                     "slopes and predicted orders",
    "--errata": "numerical evidence for the errata of the paper's eqs. (6)-(9) (sedf; small "
                "Delta/mu case and the paper's Fig. 3 case)",
    "--validity": "sedf validity map of KBM orders 1, 2 over the default (mu, Delta, beta) grid "
                  "(a sweep on all cores, a few minutes)",
    "--fixed-delta": "sedf at these fixed Delta (beta = 1, 0.5, 0.25; mu from 0.2 to 0.005): "
                     "errors of the energy method's orders and of classical KBM against the "
                     "true cycles, with fitted log-log slopes",
    "--methods-map": "sedf map over (mu, Delta, beta): where classical KBM and the energy method "
                     "are within 1 %% and 1e-3 of the true cycle (a sweep on all cores, about a "
                     "minute)",
}
#: the studies that take values (the others are on/off): flag -> metavar
VALUES = {"--convergence": "MU1,MU2,...", "--fixed-delta": "DELTA1,..."}


def _check_modes(args: argparse.Namespace, params: dict) -> None:
    """Refuse flags the chosen mode would ignore (no silently dropped option)."""
    from numerics.cli.params.values import within

    within(args.x_start, "--x-start")
    modes = [f for f in ("--errata", "--validity", "--convergence", "--fixed-delta",
                         "--methods-map") if getattr(args, f[2:].replace("-", "_"))]
    if len(modes) > 1:
        raise ParameterError(f"{' and '.join(modes)} are separate studies; give one")
    if not modes:
        return
    mode = modes[0]
    ignored = {"--paper": args.paper, "--energy-orders": args.energy_orders is not None}
    if mode in ("--errata", "--validity", "--fixed-delta", "--methods-map"):
        ignored.update({"--rhs": args.rhs, "--omega0": args.omega0, "--param": params,
                        "--x-start": args.x_start is not None,
                        "a model other than sedf": args.model not in (None, "sedf")})
    if mode in ("--errata", "--fixed-delta", "--methods-map"):
        ignored["--orders"] = args.orders != "1,2"
    used = [name for name, on in ignored.items() if on]
    if used:
        what = ("the paper's fixed sedf cases" if mode == "--errata" else
                "a built-in model" if mode == "--convergence" else "the default sedf grid")
        raise ParameterError(f"{mode} runs on {what} and would ignore {', '.join(used)}; "
                             f"leave {'it' if len(used) == 1 else 'them'} out")


def _fixed_scaled(model: str, params: dict) -> dict:
    """The ``-p`` values of ``--convergence``: the scaled parameters held fixed while
    ``mu`` takes the listed values (a physical name such as ``Delta`` would move the
    scaled ``delta = Delta/mu`` with ``mu``, and ``-p mu`` would be overridden).

    Raises
    ------
    kbm.errors.ParameterError
        For ``-p mu`` or a physical name, naming the scaled one to give instead.
    """
    from kbm.parameters.names import names_of

    if "mu" in params:
        raise ParameterError("--convergence gives the values of mu (MU1,MU2,...); leave "
                             "-p mu out")
    names = names_of(model)
    for scaled, expr in names.physical.items():
        phys = sorted(s.name for s in expr.free_symbols if s.name != "mu")
        given = [p for p in phys if p in params]
        if given:
            raise ParameterError(f"--convergence holds the scaled parameters fixed while mu "
                                 f"varies; give -p {scaled}=VALUE ({scaled} = {expr}) "
                                 f"instead of -p {given[0]}")
    return params


def run(args: argparse.Namespace) -> int:
    from numerics.cli.params.values import numbers, orders
    from numerics.comparison import compare, energy_prediction
    from numerics.paper import paper_prediction

    params = parse_params(args.param)
    _check_modes(args, params)
    kw = {} if args.x_start is None else {"x_start": args.x_start}
    if args.errata:
        from numerics.paper.errata import errata_evidence, evidence_table

        rows = errata_evidence()
        if args.json:
            emit_json([r.to_json() for r in rows])
        else:
            print(evidence_table(rows))
        return 0
    if args.validity:
        from numerics.paper.validity import validity_map

        return show(args, validity_map(orders=orders(args.orders)))
    if args.fixed_delta:
        from numerics.comparison.fixed_delta import fixed_delta_convergence

        deltas = numbers(args.fixed_delta, "--fixed-delta")
        if not deltas or not all(0 < d < 100 for d in deltas):
            raise ModelError(f"--fixed-delta takes values 0 < Delta < 100, got "
                             f"{args.fixed_delta!r}")
        return show(args, fixed_delta_convergence(deltas))
    if args.methods_map:
        from numerics.paper.methods import methods_map

        return show(args, methods_map())
    if args.convergence:
        from numerics.comparison.convergence import convergence_study

        if not args.model:
            raise ModelError("--convergence needs a built-in model name")
        params = _fixed_scaled(args.model, checked_params(args.param, args.model))
        eps = numbers(args.convergence, "--convergence")
        return show(args, convergence_study(args.model, eps, orders=orders(args.orders),
                                            fixed=params, **kw))
    extra = [paper_prediction] if args.paper else []
    energy_orders = "1,2" if args.energy_orders is None else args.energy_orders
    if energy_orders.strip().lower() != "none":
        extra += [energy_prediction(n) for n in orders(energy_orders, "--energy-orders")]
    # a forced or coupled built-in: refused, no traceback and no words of the Python API
    params = checked_params(args.param, model_spec(args), ("one",))
    from numerics.cli.params.values import wavenumber

    wavenumber(model_spec(args), params)
    comp = compare(model_spec(args), params, orders=orders(args.orders), extra=extra, **kw)
    if args.json:
        emit_json({**comp.to_json(), "params_given": params})
    else:
        lines = comp.table().splitlines()
        lines[0] = f"{comp.model}  {describe_params(model_spec(args), params, comp.params)}"
        print("\n".join(lines))
    return 0
