"""``kbm friction ... -p D=VALUE``: the friction laws and maps with thermal noise, and the
output of a map and its ``--against`` one (:func:`emit_maps`, with or without noise).

Called by :mod:`numerics.cli.friction` when the noise ``D`` (or the CDC's temperature
``T = D/mu``) is a parameter or an axis.
"""

from __future__ import annotations

import sys
from pathlib import Path

from kbm.cli import cli_message
from kbm.cli._common import table_cell
from kbm.errors import ParameterError
from numerics._show import cell
from numerics.noise.budget import STEP_BUDGET

#: the options of the noisy runs (default None on the parser, so that "given" is told
#: from "default"; refused without noise) and their values when not given
NOISE_FLAGS = {"trajectories": 16, "wells": 50.0, "seed": 0, "budget": STEP_BUDGET}


def wanted(params: dict, axes: dict) -> bool:
    """Whether the run has noise (``D`` or ``T`` given)."""
    return bool({"D", "T"} & (set(params) | set(axes)))


def run_thermal(args, params: dict, axes: dict, store, client) -> int:
    from numerics.thermal.friction import thermal_friction_map

    if args.netcdf:
        raise ParameterError("--netcdf writes the deterministic maps; with noise use --json")
    if args.engine != "compiled":
        raise ParameterError("with noise the Langevin integrator is used; drop --engine")
    for name, default in NOISE_FLAGS.items():
        if getattr(args, name) is None:
            setattr(args, name, default)
    kw = dict(trajectories=args.trajectories, wells=args.wells, seed=args.seed,
              budget=args.budget, executor=client, workers=args.workers,
              progress=not args.no_progress and not args.json, store=store)
    first = thermal_friction_map(args.model, params, axes, **kw)
    second = thermal_friction_map(args.against, params, axes, **kw) if args.against else None
    return emit_maps(args, first, second, _print, lambda f, s, out: [_figure(f, s, out)])


def emit_maps(args, first, second, printer, figures, ratios=None) -> int:
    """A map and its ``--against`` one (``second``, or ``None``) as the command line asks:
    ``--json`` the first's JSON with the second's under ``against`` (and the keys of
    ``ratios(first, second)``), else the tables of ``printer``; ``--out DIR`` the paths of
    ``figures(first, second, DIR)`` named (on standard error with ``--json``, so that
    standard output holds the JSON only).  Returns the exit status 0."""
    if args.json:
        from kbm.cli._common import emit_json

        data = first.to_json()
        if second is not None:
            data["against"] = second.to_json()
            data.update(ratios(first, second) if ratios else {})
        emit_json(data)
    else:
        for i, m in enumerate((first, second) if second is not None else (first,)):
            print("\n" if i else "", end="")
            printer(m)
    if args.out:
        for path in figures(first, second, Path(args.out)):
            print(f"wrote {path}", file=sys.stderr if args.json else sys.stdout)
    return 0


def _print(m) -> None:
    names = list(m.axes)
    print(f"{m.model} with noise sqrt(2 D) xi: "
          + ", ".join(f"{k} = {v:g}" for k, v in m.params.items() if k not in m.axes)
          + f"; {m.trajectories} trajectories x {m.wells:g} stage periods per point, "
            f"seed {m.seed}")
    head = "".join(f"{n:>10s}" for n in names if n not in ("D", "T"))
    print(f"{head}{'D':>10s}{'kT':>9s} {'mean F':>10s} {'+-':>8s} {'slip F':>9s} {'+-':>8s} "
          f"{'L slip':>9s} {'+-':>8s} {'slips':>6s} {'back':>5s}")
    for p in m.points:
        vals = "".join(f"{p.params[n]:10.4g}" for n in names if n not in ("D", "T"))
        kT = cell(p.kT, ".4g")
        if p.error:
            print(f"{vals}{p.params['D']:10.4g}{kT:>9s}  failed: {cli_message(p.error)}")
            continue
        cells = " ".join(table_cell(value, fmt) for value, fmt in (
            (p.mean_force.value, "10.5g"), (p.mean_force.stderr, "8.2g"),
            (p.slip_force.value, "9.5g"), (p.slip_force.stderr, "8.2g"),
            (p.slip_position.value, "9.5g"), (p.slip_position.stderr, "8.2g")))
        print(f"{vals}{p.params['D']:10.4g}{kT:>9s} {cells} {p.slips:6d} {p.backward:5d}")
    print("(slip F: the peak spring force before each slip; L slip: the stage position at the "
          "slip relative to the well left, v t - n lam"
          + ("; --: no slip in the run" if any(not p.error and p.slips == 0
                                                   for p in m.points) else "") + ")")
    if m.note:
        print(f"note: {m.note}")


def _noise_label(m, D: float) -> str:
    """The legend of one noise level: ``kT = D/mu`` when the noise was given as ``T`` (an
    axis or a parameter), else ``D``."""
    if ("T" in m.axes or "T" in m.params) and m.params["mu"] is not None:  # mu no axis
        return f"{m.model}, kT = {D / m.params['mu']:.4g}"
    return f"{m.model}, D = {D:.4g}"


def _title(first, second) -> str:
    """The fixed parameters, the noise among them when it is fixed (``D``, or ``T`` as given:
    with ``mu`` an axis the legend can only name ``D = mu T``), and the ensemble; the axes
    are in the legend and on the abscissa."""
    fixed = ", ".join(f"{k} = {v:.4g}" for k, v in first.params.items() if k not in first.axes)
    models = first.model + (f" (o) against {second.model} (s)" if second is not None else "")
    return (f"{models} with noise sqrt(2 D) xi: {fixed}\n{first.trajectories} trajectories x "
            f"{first.wells:g} stage periods per point, seed {first.seed}")


def _figure(first, second, out: Path) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    out.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(figsize=(5.6, 3.8), dpi=150)
    for m, style in ((first, "-o"), (second, "--s")):
        if m is None:
            continue
        v = np.array([p.params["v"] for p in m.points])
        D = np.array([p.params["D"] for p in m.points])
        for j, d in enumerate(np.unique(D)):
            sel = D == d
            F = np.array([p.mean_force.value for p, s in zip(m.points, sel) if s])
            E = np.array([p.mean_force.stderr for p, s in zip(m.points, sel) if s])
            ax.errorbar(v[sel], F, yerr=2 * E, fmt=style, ms=3, lw=1, color=f"C{j}",
                        label=_noise_label(m, d))
    ax.set_xscale("log")
    ax.set_xlabel("stage velocity $v$")
    ax.set_ylabel(r"mean spring force $\bar F$ ($\pm 2$ s.e.)")
    ax.legend(fontsize=8)
    ax.set_title(_title(first, second), fontsize=8)
    fig.tight_layout()
    path = out / f"thermal_friction_{first.model}.png"
    fig.savefig(path)
    plt.close(fig)
    return path
