"""``kbm friction sedf-dimer|sedf-chain-N``: the friction law of a pulled chain of sliders
(per slider, against the stage velocity), on local processes or a Dask cluster."""

from __future__ import annotations

import argparse

from kbm.cli._common import emit_json, parse_params


def run_chain(args: argparse.Namespace) -> int:
    from kbm.errors import ParameterError
    from numerics.cli._axes import parse_axis
    from numerics.coupled.friction import chain_friction_law
    from numerics.executor import connect

    axes = [parse_axis(text) for text in args.vary]
    if len(axes) != 1 or axes[0][0] != "v":
        raise ParameterError("a chain's friction law varies the stage velocity only: give one "
                             "--vary v=FROM:TO[:N|:logN]")
    unused = [flag for flag, on in (("--against", args.against), ("--store", args.store),
                                    ("--netcdf", args.netcdf), ("--out", args.out),
                                    ("--engine scipy", args.engine != "compiled"))
              if on]
    if unused:
        raise ParameterError(f"{', '.join(unused)} apply to one slider; a chain's law takes "
                             "-p, --vary v, --seed, --workers, --scheduler and --json")
    if args.workers is not None and not 1 <= args.workers <= 1024:
        raise ParameterError(f"--workers must be between 1 and 1024, got {args.workers}")
    if args.seed < 0:
        raise ParameterError(f"--seed must be >= 0, got {args.seed}")
    params = {"mu": "0.1", **parse_params(args.param)}
    client = connect(args.scheduler, args.scheduler_timeout) if args.scheduler else None
    try:
        points = chain_friction_law(args.model, params, axes[0][1], seed=args.seed,
                                    executor=client, workers=args.workers,
                                    progress=not args.no_progress and not args.json)
    finally:
        if client is not None:
            client.close()
    if args.json:
        emit_json({"model": args.model, "params_given": params, "seed": args.seed,
                   "points": [p.to_json() for p in points]})
        return 0
    first = points[0]
    print(f"{first.model}: friction per slider; " + ", ".join(
        f"{k} = {v:g}" for k, v in first.params.items() if k != "v"))
    print(f"{'v':>10s} {'mean F':>12s} {'spread':>10s} {'wells':>6s} steady")
    for p in points:
        if p.error:
            print(f"{p.v:10.4g} {'':>12s} {'':>10s} {'':>6s} {p.error}")
        else:
            print(f"{p.v:10.4g} {p.mean_force:12.6g} {p.spread:10.3g} {p.wells:6d} "
                  f"{'yes' if p.steady else 'no'}")
    return 0
