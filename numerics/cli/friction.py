"""``kbm friction``: friction laws and maps of the driven sliders, on local processes or Dask."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from kbm.cli._common import table_cell
from kbm.errors import ModelError, ParameterError
from numerics.cli.params.options import command, options
from numerics.cli.params.values import MAX_POINTS
from numerics.noise.budget import BUDGET_TEXT

__all__ = ["register", "run"]


def register(sub) -> None:
    p = command(sub, "friction", "The steady sliding state of a slider pulled at velocity v at "
                "every point of a grid: mean spring force (kinetic friction), static friction, "
                "dissipation per unit distance (which equals the mean force in steady state), "
                "fraction of time stuck, wells per slip, regime; against the Prandtl-Tomlinson "
                "eta = 2 pi Delta/(Omega^2 lam).  Runs on local processes, or on a Dask cluster "
                "with --scheduler.  With thermal noise sqrt(2 D) xi (-p D=VALUE, or --vary D=... "
                "or T=... with kT = D/mu) an ensemble of Langevin trajectories per point gives "
                "the mean and slip forces with standard errors.  Defaults: mu = 0.1, Omega = 1, "
                "lam = 1 (the paper's).", "model", "param", "vary", model=dict(
        nargs=None, help="sedf_comoving (SEDF with the self-excitation attached to the stage; "
                         "has steady states), cdc (eq. 12) or sedf (the paper's eq. 3, whose "
                         "damping grows with the distance slid: runaway); or a chain of "
                         "sedf_comoving sliders coupled by springs mu*kappa: sedf-dimer, "
                         "sedf-chain-N (friction per slider, --vary v only)"), vary=dict(
        required=True, default=None, metavar="NAME=FROM:TO[:N|:logN]",
        help="an axis (repeatable, the last varies fastest): v=1e-3:3:log24 (24 log-spaced), "
             "Delta=0.5:3:6 (6 equally spaced), or a list beta=0.5,1,2"))
    p.add_argument("--against", choices=["sedf_comoving", "cdc", "sedf"],
                   help="a second slider on the same grid (ratios in the JSON and figures)")
    p.add_argument("--slips", type=int, default=20, metavar="N",
                   help="slips averaged over in stick-slip (default 20)")
    p.add_argument("--engine", choices=["compiled", "scipy"], default="compiled",
                   help="numba-compiled DOP853 (default) or scipy's solve_ivp (reference)")
    options(p, "workers", workers=dict(
        help="local processes (default: the number of CPUs)"))
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="run on the Dask scheduler at ADDRESS (e.g. tcp://host:8786; needs "
                        "pip install 'kbm[dask]')")
    p.add_argument("--scheduler-timeout", type=float, default=None, metavar="SECONDS",
                   help="how long to wait for the scheduler (default 10)")
    options(p, "store", "resume", store=dict(
        help="keep every finished chunk of points in the SQLite file FILE, so that an "
             "interrupted map can be resumed"), resume=dict(
        help="with --store: continue the map kept in FILE (only the missing points are "
             "computed; the result is the same as an uninterrupted run)"))
    p.add_argument("--netcdf", metavar="FILE",
                   help="also save the map(s) as a netCDF file (xarray.open_dataset(FILE) "
                        "reads it back; with --against a dimension 'slider' holds both); "
                        "needs pip install 'kbm[xarray]'")
    options(p, "trajectories", trajectories=dict(
        help="with noise (-p D=... or --vary D=/T=...): Langevin trajectories per point "
             "(default 16)"))
    p.add_argument("--wells", type=float, default=None, metavar="N",
                   help="with noise: stage periods lam/v averaged over per trajectory "
                        "(default 50)")
    options(p, "seed", "budget", seed=dict(
        default=None, help="with noise: root seed (one SeedSequence child per trajectory; "
                           "default 0); a chain's initial spread"), budget=dict(
        default=None, help="with noise: largest number of integration steps of the run "
                           f"(default {BUDGET_TEXT}); a larger run is refused before it "
                           "starts"))
    options(p, "json", "out", out=dict(help="write the figures into DIR"))
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.set_defaults(func=run)


def _save_netcdf(path: str, first, second) -> None:
    """The map(s) as one netCDF file (netCDF3 through scipy: no compiled netCDF library)."""
    ds = first.to_xarray()
    if second is not None:
        import xarray as xr

        other = second.to_xarray()
        ds = xr.concat([ds.drop_attrs(), other.drop_attrs()], dim="slider",
                       combine_attrs="drop")
        ds = ds.assign_coords(slider=[first.model, second.model])
        ds.attrs = {"source": "kbm friction (numerics.sliding.maps)",
                    **{f"param_{k}": float(v) for k, v in first.params.items()}}
    ds.to_netcdf(path, engine="scipy")
    print(f"wrote {path}", file=sys.stderr)


SLIDERS = ("sedf_comoving", "cdc", "sedf")


def _check_outputs(args: argparse.Namespace) -> None:
    """``--out`` and ``--netcdf``'s folder writable before the map is computed (an
    unwritable one failed after the whole map: "cannot access '/proc/x'")."""
    from pathlib import Path

    from kbm.output.files import output_folder

    if args.out:
        output_folder(args.out, "--out")
    if args.netcdf:
        path = Path(args.netcdf)
        if path.is_dir():
            raise ParameterError(f"--netcdf {args.netcdf} is a folder; name a file")
        output_folder(path.parent, "--netcdf's folder")


def run(args: argparse.Namespace) -> int:
    from kbm.model.builtins import parameter_value
    from kbm.parameters.names import noise_intensity
    from kbm.parameters.values import closest
    from numerics.cli.params.noise import noise_axis
    from numerics.cli.params.options import check_ensemble, stored
    from numerics.cli.params.values import check, given, parse_vary, physical
    from numerics.executor import connect
    from numerics.sliding.friction_records import FrictionSettings
    from numerics.sliding.maps import axis_values, friction_map

    from numerics.cli.params.values import positive

    positive(args.scheduler_timeout, "--scheduler-timeout")  # nan: a KeyError of dask
    if args.scheduler_timeout is None:
        args.scheduler_timeout = 10.0
    elif not args.scheduler:  # was ignored without a word
        raise ParameterError("--scheduler-timeout is the wait for --scheduler ADDRESS: give "
                             "--scheduler, or leave out --scheduler-timeout")
    if args.model.startswith(("sedf-dimer", "sedf-chain")):
        from numerics.cli._chain_friction import run_chain

        return run_chain(args)
    if args.model not in SLIDERS:
        near = closest(args.model, SLIDERS + ("sedf-dimer", "sedf-chain-8"))
        raise ModelError(f"unknown slider {args.model!r}"
                         + (f" (did you mean {near}?)" if near else "")
                         + ": sedf_comoving, cdc, sedf, or a chain sedf-dimer, sedf-chain-N")
    params = given(args.param)
    varies = [parse_vary(text) for text in args.vary]
    if len(varies) > 2:
        raise ParameterError(f"--vary takes at most two axes (a map), got "
                             f"{', '.join(v.name for v in varies)}")
    if args.out and not {"D", "T"} & (set(params) | {v.name for v in varies}):
        _check_figures([v.name for v in varies], args.against)  # before the names' checks
    models = (args.model,) + ((args.against,) if args.against else ())
    names = check(models, params, [v.name for v in varies], extra=("v",), noise=True)
    # a noise axis is checked as typed (T = D/mu is converted later); D = 0, T = 0 are the
    # deterministic slider
    axes = {v.name: noise_axis(v) if v.name in ("D", "T") else v.values() for v in varies}
    if "D" in params:
        noise_intensity(params["D"])
    if "T" in params and (t := float(parameter_value("T", params["T"]))) < 0:
        raise ParameterError(f"T = {t:g} is negative; the temperature kT = D/mu must be "
                             ">= 0 (T = 0 is the deterministic slider)")
    fixed, axes = physical(names, params, axes, "0.1")
    axes = {k: axis_values(k, v) for k, v in axes.items()}
    from numerics.cli._thermal_friction import emit_maps, run_thermal, wanted

    noisy = wanted(fixed, axes)
    if not noisy:
        _check_noise_flags(args)
    size = int(np.prod([len(v) for v in axes.values()]))
    if size > MAX_POINTS:
        raise ParameterError(f"the grid has {size} points; the limit is {MAX_POINTS}")
    params = {k: float(parameter_value(k, v)) for k, v in fixed.items()}
    params = {"mu": 0.1, "lam": 1.0, "Omega": 1.0, **params}
    from numerics.cli._chain_friction import check_velocities
    from numerics.sliding.driven import physical_values

    physical_values(params)  # lam, Omega <= 0 were blamed on v, Delta < 0 passed with noise
    check_velocities(params, axes)
    settings = FrictionSettings(slips=args.slips)
    check_ensemble(args)
    _check_outputs(args)
    with stored(args, "map") as store:
        client = connect(args.scheduler, args.scheduler_timeout) if args.scheduler else None
        kw = dict(settings=settings, engine=args.engine, executor=client, workers=args.workers,
                  progress=not args.no_progress and not args.json, store=store)
        try:
            if noisy:
                return run_thermal(args, params, axes, store, client)
            # a default of mu, lam or Omega is no fixed value where it is an axis (the map
            # refused it: "lam is both fixed and an axis", though typed once)
            params = {k: v for k, v in params.items() if k not in axes}
            first = friction_map(args.model, params, axes, **kw)
            second = friction_map(args.against, params, axes, **kw) if args.against else None
        finally:
            if client is not None:
                client.close()
    if args.netcdf:
        _save_netcdf(args.netcdf, first, second)
    return emit_maps(args, first, second, _print, _figures, _ratios)


def _ratios(first, second) -> dict:
    """The ``--against`` ratios of the JSON (:class:`numerics.sliding.maps.SliderComparison`)."""
    from numerics.sliding.maps import SliderComparison

    comp = SliderComparison(first, second)
    return {"force_ratio": comp.force_ratio.tolist(),
            "dissipation_ratio": comp.dissipation_ratio.tolist()}


def _print(m) -> None:
    from kbm.cli import cli_message

    names = list(m.axes)
    print(f"{m.model}: " + ", ".join(f"{k} = {v:g}" for k, v in m.params.items()))
    head = "".join(f"{n:>10s}" for n in names)
    print(f"{head} {'regime':>24s} {'mean F':>10s} {'diss/dist':>10s} {'static':>9s} "
          f"{'stuck':>6s} {'wells':>6s} {'eta':>6s} steady")
    for p in m.points:
        vals = "".join(f"{p.params[n]:10.4g}" for n in names)
        if not p.ok:
            print(f"{vals}  failed: {cli_message(p.error)}")
            continue
        # a runaway has no mean force, dissipation or stuck fraction (JSON null): "--"
        print(f"{vals} {p.regime:>24s} {table_cell(p.mean_force, '10.5g')} "
              f"{table_cell(p.dissipation_per_distance, '10.5g')} "
              f"{table_cell(p.static_force, '9.4g')} {table_cell(p.stuck_fraction, '6.3f')} "
              f"{table_cell(p.wells_per_slip, '6.3g')} {p.eta:6.3g} {'yes' if p.steady else 'no'}")
        if p.note:
            print(f"{'':{10 * len(names)}s}  ({cli_message(p.note)})")


def _figures(first, second, out: Path) -> list[Path]:
    from numerics.paper.figures.friction import law_figure, map_figure
    from numerics.sliding.maps import SliderComparison

    out.mkdir(parents=True, exist_ok=True)
    if list(first.axes) == ["v"]:
        maps = [first] + ([second] if second is not None else [])
        return [law_figure(maps, out / f"friction_law_{first.model}.png")]
    names = list(first.axes)
    return [map_figure(SliderComparison(first, second),
                       out / f"friction_map_{names[0]}_{names[1]}.png")]


def _check_figures(names: list[str], against: str | None) -> None:
    """``--out`` draws a friction law (``v`` the only axis) or a map (``v`` first of two
    axes, with ``--against``)."""
    if names == ["v"] or (len(names) == 2 and names[0] == "v" and against):
        return
    raise ParameterError(f"--out draws a friction law (--vary v=... only) or a map (--vary "
                         f"v=... --vary NAME=... --against MODEL); got axes {', '.join(names)}"
                         + ("" if against or len(names) == 1 else " without --against"))


def _check_noise_flags(args: argparse.Namespace) -> None:
    """Refuse the options of the noisy runs on a deterministic one (no ``D`` or ``T``)."""
    from numerics.cli._thermal_friction import NOISE_FLAGS

    given = [f"--{name}" for name in NOISE_FLAGS if getattr(args, name) is not None]
    if given:
        verb = "apply" if len(given) > 1 else "applies"
        raise ParameterError(f"{', '.join(given)} {verb} to the runs with thermal noise: give "
                             "-p D=VALUE or -p T=VALUE (or --vary D=... / T=...), or drop "
                             f"{'them' if len(given) > 1 else 'it'} (without noise the "
                             "friction is the deterministic slider's)")
