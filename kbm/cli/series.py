"""``kbm series``: exact mu-series of the limit-cycle frequency and amplitude."""

from __future__ import annotations

import argparse

from ._common import add_param_option, emit_json


def register(sub) -> None:
    p = sub.add_parser("series", help="exact mu-series of the limit cycle (polynomial F)",
                       description="Expand the limit-cycle frequency omega* and first-harmonic "
                                   "amplitude a* of the averaged equations in powers of mu, "
                                   "with exact rational coefficients.")
    p.add_argument("model", nargs="?", help="built-in model with polynomial F (e.g. vdp)")
    p.add_argument("--rhs", metavar="EXPR", help="your own polynomial F")
    p.add_argument("--omega0", default=None, help="linear frequency for --rhs (default 1)")
    p.add_argument("--order", "-n", type=int, required=True, help="highest power of mu")
    p.add_argument("--root", default=None, help="first-order amplitude a0 if A_1 has several "
                   "positive roots")
    add_param_option(p)
    p.add_argument("--json", action="store_true", help="print JSON (rationals as strings)")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..series import limit_cycle_series
    from .derive import model_from_args

    model = model_from_args(args)
    s = limit_cycle_series(model, args.order, root=args.root)
    if args.json:
        emit_json({"model": model.name, "order": s.order,
                   "omega": [str(c) for c in s.omega],
                   "amplitude": [str(c) for c in s.amplitude]})
    else:
        print(f"omega* = {s.omega_expr()} + O(mu**{s.order + 1})")
        print(f"a*     = {s.amplitude_expr()} + O(mu**{s.order + 1})")
    return 0
