"""``kbm slide``: the paper's driven slider (SEDF eq. 3 or CDC eq. 12) pulled at velocity v."""

from __future__ import annotations

import argparse

from kbm.cli._common import emit_json
from numerics.cli.params.options import command


def register(sub) -> None:
    p = command(sub, "slide", "Simulate x'' + D(x, x') + Delta sin(2 pi x/lam) + Omega^2 (x - v "
                "t) = 0 from x = x' = 0 and analyse the stick-slip motion (slips, static and "
                "kinetic friction, dissipation, energy audit).  Defaults as in the paper: mu = "
                "0.1, Omega = 1, lam = 1.", "model", "param", "t_end", "rtol", "json",
                model=dict(nargs=None, choices=["sedf", "cdc", "sedf_comoving"],
                           help="sedf (eq. 3), cdc (eq. 12) or sedf_comoving (self-excitation "
                                "attached to the stage)"),
                t_end=dict(required=True, help="final time T > 0"))
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from numerics import analyze, slide

    from kbm.errors import ParameterError
    from kbm.model.builtins import parameter_value

    from numerics.cli.params.values import check, given, physical

    typed = given(args.param)
    names = check(args.model, typed, extra=("v",))
    if "v" not in typed:  # ran quietly at v = 0, a stage at rest: zero force, 0 slips
        raise ParameterError("give the stage velocity -p v=VALUE (v > 0 pulls the stage, "
                             "e.g. -p v=0.01; -p v=0 leaves it at rest)")
    fixed, _ = physical(names, typed, {}, None)
    params = {k: float(parameter_value(k, v)) for k, v in fixed.items()}
    res = slide(args.model, params, args.t_end, rtol=args.rtol)
    a = analyze(res)
    data = a.to_json()
    if args.json:
        return emit_json(data)
    print(f"{args.model} pulled at v = {res.params.get('v', 0):g} up to t = {args.t_end:g} "
          f"({', '.join(f'{k}={v:g}' for k, v in sorted(res.params.items()))})")
    print(f"  peak force {a.peak_force:.6g}, mean (kinetic) force {a.kinetic_friction:.6g}")
    print(f"  Gamma = {a.gamma:.6g} (Gamma+ {a.gamma_plus:.6g}, Gamma- {a.gamma_minus:.6g}); "
          f"energy audit residual {a.energy_residual:.2e}")
    print(f"  quasi-static slip energy Delta W = "
          f"{'none (no stick-slip: Delta k <= Omega^2)' if a.delta_W is None else f'{a.delta_W:.6g}'}")
    print(f"  {len(a.slips)} slips ({a.criterion}):")
    for s in a.slips:
        print(f"    t = {s.t_start:9.3f} .. {s.t_end:9.3f}  wells {s.wells:+d}  "
              f"peak force {s.peak_force:.5g}  dissipated {s.energy_dissipated:.5g}"
              + ("" if s.complete else "  (still slipping at the end)"))
    return 0
