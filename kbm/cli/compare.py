"""``kbm compare``: KBM predictions of several orders next to the true limit cycle."""

from __future__ import annotations

import argparse

from ._common import add_param_option, emit_json, parse_params


def register(sub) -> None:
    p = sub.add_parser(
        "compare", help="KBM predictions (any order) against the numerical limit cycle",
        description="Compare the limit cycle predicted by the KBM expansion of each order "
                    "(first-harmonic amplitude, maximum of x, frequency, third harmonic, "
                    "Floquet multiplier, dissipation over the reconstructed cycle) with the "
                    "cycle computed by shooting.")
    p.add_argument("model", nargs="?", help="built-in model (vdp, rayleigh, sedf, cdc, ...)")
    p.add_argument("--rhs", metavar="EXPR", help="your own F (in x, xdot and parameters)")
    p.add_argument("--omega0", default="1", help="linear frequency for --rhs (default 1)")
    add_param_option(p)
    p.add_argument("--orders", default="1,2", help="comma-separated KBM orders (default 1,2)")
    p.add_argument("--paper", action="store_true",
                   help="add the paper's eqs. (5)-(9) as printed (sedf only)")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=run)


def _orders(text: str) -> list[int]:
    from ..errors import OrderError

    try:
        out = [int(s) for s in text.split(",") if s.strip()]
    except ValueError:
        raise OrderError(f"--orders takes comma-separated integers, got {text!r}") from None
    if not out or min(out) < 1:
        raise OrderError(f"--orders must list orders >= 1, got {text!r}")
    return out


def run(args: argparse.Namespace) -> int:
    from ..errors import ModelError
    from ..models import custom_model
    from numerics.compare import compare

    params = parse_params(args.param)
    if args.model and args.rhs:
        raise ModelError("give either a model name or --rhs, not both")
    if args.rhs:
        model = custom_model(args.rhs, omega0=args.omega0)
    elif args.model:
        model = args.model
    else:
        raise ModelError("name a model (e.g. vdp) or give --rhs EXPR")
    comp = compare(model, params, orders=_orders(args.orders), paper=args.paper)
    if args.json:
        emit_json(comp.to_json())
    else:
        print(comp.table())
    return 0
