"""``kbm derive``: the KBM expansion of a model to a given order."""

from __future__ import annotations

import argparse

from ._common import add_param_option, check_model_flags, emit_json, parse_params


def register(sub) -> None:
    p = sub.add_parser("derive", help="KBM expansion A_n, B_n, u_n to a given order",
                       description="Derive the Krylov-Bogoliubov-Mitropolsky expansion of "
                                   "x'' + omega0^2 x = mu F(x, x') to order N.")
    p.add_argument("model", nargs="?", help="built-in model (vdp, duffing, rayleigh, "
                   "linear_damping, linear_stiffness, sedf, cdc)")
    p.add_argument("--rhs", metavar="EXPR", help="your own F (in x, xdot and parameters) "
                   "instead of a built-in model")
    p.add_argument("--omega0", default=None, help="linear frequency for --rhs (default 1)")
    p.add_argument("--order", "-n", type=int, required=True, help="order N >= 1")
    add_param_option(p)
    fmt = p.add_mutually_exclusive_group()
    fmt.add_argument("--json", action="store_true", help="print JSON (strings sympy can parse)")
    fmt.add_argument("--latex", action="store_true", help="print LaTeX")
    p.set_defaults(func=run)


def model_from_args(args: argparse.Namespace):
    """The model named on the command line (with ``--param`` values), or the user's ``--rhs``."""
    from ..models import custom_model, get_model

    params = parse_params(args.param)
    check_model_flags(args)
    if getattr(args, "rhs", None):
        model = custom_model(args.rhs, omega0=1 if args.omega0 is None else args.omega0)
        return model.substitute(params) if params else model
    return get_model(args.model, params)


def run(args: argparse.Namespace) -> int:
    from ..averaging import derive

    res = derive(model_from_args(args), args.order)
    if args.json:
        emit_json(res.to_json())
    elif args.latex:
        print(res.latex())
    else:
        print(res.pretty())
    return 0
