"""``kbm predict``: every limit cycle an analysis predicts (energy balance or classical KBM)."""

from __future__ import annotations

import argparse

from kbm.cli._common import ONE_DOF, checked_params, describe_params, emit_json, model_spec
from numerics.cli.params.options import command, options


def register(sub) -> None:
    p = command(sub, "predict", "List every limit cycle predicted analytically: by averaging "
                "about the conservative orbit of x'' + g(x) = 0 with only the damping as "
                "perturbation (--method energy; order 1 is the energy balance Gamma(E) = 0, the "
                "paper's eq. 10), or by classical KBM (--method kbm). JSON key 'cycles': "
                "amplitude_max, amplitude_min, amplitude_first_harmonic, period, frequency, "
                "energy, stable, annulus.", models=ONE_DOF)
    p.add_argument("--potential", metavar="EXPR", default=None,
                   help="potential V(x) of the conservative part (energy method; default: "
                        "the x-only part of the force)")
    options(p, "param")
    p.add_argument("--method", choices=["energy", "kbm"], default="energy",
                   help="energy (averaging about the conservative orbit, default) or kbm")
    options(p, "order", "json", order=dict(default=1, help="order N >= 1 (default 1)"))
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from numerics.comparison import predict
    from numerics.comparison.predict import KBM_TERM_LIMIT

    spec = model_spec(args)
    given = checked_params(args.param, spec, ("one",))  # a forced or coupled one refused
    pred = predict(spec, given, method=args.method, order=args.order, potential=args.potential)
    if args.json:
        return emit_json({**pred.to_json(), "params_given": given})
    pars = describe_params(spec, given, pred.params)
    print(f"{pred.model} ({pars}): {len(pred.cycles)} cycle(s) predicted by "
          f"{'energy averaging' if args.method == 'energy' else 'classical KBM'}, order "
          f"{pred.order}")
    if not pred.cycles:
        print(f"  {pred.reason}")
    if pred.warning:
        print(f"  WARNING: {pred.warning}")
    for c in pred.cycles:
        print(f"  {'stable  ' if c.stable else 'unstable'}  x in [{c.amplitude_min:.8g}, "
              f"{c.amplitude_max:.8g}]  a1 {c.amplitude_first_harmonic:.8g}  T {c.period:.8g}"
              f"  E {c.energy:.8g}  multiplier {c.floquet_multiplier:.6g}  ({c.annulus})")
        if c.term_size > KBM_TERM_LIMIT:
            print(f"            KBM corrections {c.term_size:.2g} of the leading terms: not "
                  "to be trusted")
        if getattr(c, "period_sensitivity", 0.0) > 1:
            print(f"            period sensitivity {c.period_sensitivity:.2g} > 1: the energy "
                  "swing of one cycle reaches a separatrix; orders > 1 are not reliable here")
    return 0
