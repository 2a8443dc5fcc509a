"""``kbm friction sedf-dimer|sedf-chain-N``: the friction law of a pulled chain of sliders
(per slider, against the stage velocity), on local processes or a Dask cluster."""

from __future__ import annotations

import argparse

from kbm.cli import cli_message
from kbm.cli._common import emit_json
from kbm.errors import ParameterError

#: a mean force per slider below this fraction of the potential's amplitude Delta is
#: called near zero in the note under the table
NEAR_ZERO = 0.05


def run_chain(args: argparse.Namespace) -> int:
    from numerics.cli.params.options import check_ensemble
    from numerics.cli.params.values import check, given, parse_vary
    from numerics.sliding.chain_friction import chain_friction_law
    from numerics.executor import connect
    from numerics.sliding.maps import axis_values

    given_params = given(args.param)
    varies = [parse_vary(t) for t in args.vary]
    if [v.name for v in varies] != ["v"]:
        raise ParameterError("a chain's friction law varies the stage velocity only: give one "
                             "--vary v=FROM:TO[:N|:logN]")
    names = check(args.model, given_params, ["v"])
    velocities = axis_values("v", varies[0].values())
    unused = [flag for flag, on in (("--against", args.against), ("--store", args.store),
                                    ("--netcdf", args.netcdf), ("--out", args.out),
                                    ("--engine scipy", args.engine != "compiled"),
                                    ("--trajectories", args.trajectories is not None),
                                    ("--wells", args.wells is not None),
                                    ("--budget", args.budget is not None))
              if on]
    if unused:
        raise ParameterError(f"{', '.join(unused)} apply to one slider; a chain's law takes "
                             "-p, --vary v, --seed, --workers, --scheduler and --json")
    check_ensemble(args)
    if args.seed is None:
        args.seed = 0
    if "v" in given_params:
        raise ParameterError("a chain's friction law varies the stage velocity: give it as "
                             "--vary v=..., not -p v")
    params = {"mu": "0.1", **given_params}
    _check_chain(given_params, velocities)
    client = connect(args.scheduler, args.scheduler_timeout) if args.scheduler else None
    try:
        points = chain_friction_law(args.model, params, velocities, seed=args.seed,
                                    executor=client, workers=args.workers,
                                    progress=not args.no_progress and not args.json)
    finally:
        if client is not None:
            client.close()
    if args.json:
        return emit_json({"model": args.model, "params_given": params, "seed": args.seed,
                          "points": [p.to_json() for p in points]})
    first = points[0]
    shown = _physical_header(names, first.params, given_params)
    print(f"{first.model}: friction per slider; {shown}")
    print(f"{'v':>10s} {'mean F':>12s} {'spread':>10s} {'wells':>6s} steady")
    for p in points:
        if p.error:
            print(f"{p.v:10.4g} {'':>12s} {'':>10s} {'':>6s} {cli_message(p.error)}")
        else:
            why = "" if p.steady else (
                f" (the halves of the last window of {p.wells} stage periods gave "
                f"{p.halves[0]:.6g} and {p.halves[1]:.6g}: they differ by more than 1 % "
                "(0.01 below a force of 1) in the longest window the run makes)")
            print(f"{p.v:10.4g} {p.mean_force:12.6g} {p.spread:10.3g} {p.wells:6d} "
                  f"{'yes' if p.steady else 'no'}{why}")
    Delta = first.params["delta"] * first.params["mu"]
    low = [p for p in points if not p.error and p.mean_force < NEAR_ZERO * Delta]
    if low:
        print(f"note: at {len(low)} of {len(points)} velocities the mean force per slider is "
              f"near zero (below {NEAR_ZERO:g} Delta) or negative: each slider's "
              "self-excitation (negative damping inside |x_i - v t| < 1/sqrt(beta)) pushes "
              "it ahead of the stage, so the chain feeds the stage instead of resisting it; "
              "the springs mu*kappa between neighbours keep the sliders out of step "
              "(spread), where one slider alone would stick and slip (docs/coupled.rst, friction of "
              "pulled chains)")
    return 0


def _check_chain(given_params: dict, velocities) -> None:
    """Refuse a period ``lam`` (or wavenumber ``k``) that is not positive, a negative
    strength ``Delta`` (or ``delta``), and stage velocities outside the friction laws'
    range, ``1e-4`` to ``1e3`` times ``Omega lam`` (``Omega = 1`` in a chain, ``lam``
    default 1), as for one slider: ``-p k=0`` was a ZeroDivisionError traceback, ``-p
    lam=-1`` and ``-p Delta=-3`` a ValueError (math domain error), and ``--vary
    v=1e-6,5000`` failed at the step limit after 25 s with exit status 0."""
    import math

    from kbm.parameters.values import parameter_value

    vals = {n: float(parameter_value(n, v)) for n, v in given_params.items()
            if n in ("lam", "k", "Delta", "delta")}
    for name, what in (("lam", "the period of the potential lam"),
                       ("k", "the wavenumber of the potential k = 2 pi/lam")):
        if name in vals and not vals[name] > 0:
            raise ParameterError(f"{what} must be > 0, got -p {name}={given_params[name]}")
    for name in ("Delta", "delta"):
        if name in vals and vals[name] < 0:
            raise ParameterError(f"the strength of the potential {name} must be >= 0, got -p "
                                 f"{name}={given_params[name]}")
    lam = vals["lam"] if "lam" in vals else 2 * math.pi / vals["k"] if "k" in vals else 1.0
    check_velocities({"Omega": 1.0, "lam": lam}, {"v": velocities})


def _physical_header(names, values: dict, typed: dict) -> str:
    """The chain's parameters in the physical names the user typed (``Delta = 3, lam = 1``
    for ``delta = 30, k = 2 pi``), then the others, the stage velocity left out."""
    from kbm.parameters.names import to_physical

    vals = {k: v for k, v in values.items() if k != "v"}
    scaled = [k for k in names.physical if k in vals and k not in typed]
    shown = to_physical(names, {"mu": vals["mu"], **{k: vals[k] for k in scaled}})
    out = {"mu": vals["mu"], **{k: float(v) for k, v in shown.items() if k != "mu"}}
    out.update({k: v for k, v in vals.items() if k not in names.physical and k != "mu"})
    out.update({k: v for k, v in vals.items() if k in typed})
    return ", ".join(f"{k} = {float(v):g}" for k, v in out.items())


def check_velocities(params: dict, axes: dict) -> None:
    """Refuse a stage velocity outside :data:`numerics.sliding.friction.V_RANGE` times
    ``Omega lam`` before the map (where ``Omega`` and ``lam`` are fixed), for one slider
    (:mod:`numerics.cli.friction`) and a chain (:func:`run_chain`): the points were
    printed as failed rows with exit status 0, and the runs with noise integrated without
    end (``--vary v=1e9 -p T=0.1``).

    Raises
    ------
    kbm.errors.ParameterError
        Naming the value and the range of ``--vary v``.
    """
    from numerics.sliding.friction import V_RANGE

    if "lam" in axes or "Omega" in axes:
        return
    scale = params["Omega"] * params["lam"]
    lo, hi = (bound * scale for bound in V_RANGE)
    speeds = list(axes.get("v", ())) + ([params["v"]] if "v" in params else [])
    bad = [v for v in speeds if not lo <= v <= hi]
    if bad:
        raise ParameterError(
            f"v = {bad[0]:g} is outside the range of the friction laws, {V_RANGE[0]:g} to "
            f"{V_RANGE[1]:g} times Omega lam = {scale:g} (below it one stage period lam/v "
            "spans more than 10^5 natural periods, the quasi-static limit; above it the "
            f"slider slides smoothly with F = mu v): give --vary v within {lo:g}:{hi:g}")
