"""``kbm noise``: the stationary state of a noisy model, averaged against simulated."""

from __future__ import annotations

import math

from pathlib import Path

from kbm.cli._common import emit_json, write_json
from kbm.errors import ParameterError
from numerics._show import cell
from numerics.cli.params.options import command, options
from numerics.noise.budget import BUDGET_TEXT, FP_BUDGET
from numerics.noise.validity import ERROR_SOURCES


def register(sub) -> None:
    p = command(sub, "noise", "The stationary state of x'' + ... = sqrt(2 D) xi(t) (unit mass, "
                "<xi(t) xi(t')> = delta(t - t'); kT = D/mu for linear damping mu): the moments "
                "<a^2> (a^2 = x^2 + (x'/omega0)^2) and <x^2> and a density, predicted by "
                "stochastic averaging (the amplitude for weakly nonlinear models, the energy "
                "envelope for the sliders' strong potential) and estimated from an ensemble of "
                "Langevin trajectories (weak order 2, one seed per trajectory spawned from "
                "--seed) with standard errors.  A linearly damped model also gets the exact "
                "Boltzmann <x^2>.", "trajectories", "t_end",
                noisy="a built-in model (vdp, duffing, rayleigh, linear_damping, cdc, sedf, "
                      "sedf_comoving)", trajectories=dict(
        default=100, help="independent trajectories (default 100; at least 8)"), t_end=dict(
        metavar="T", help="averaging time per trajectory after the burn-in (default 400/|mu|)"))
    p.add_argument("--burn-in", type=float, default=None, metavar="T",
                   help="time discarded first (default 20/|mu|)")
    options(p, "dt", "seed", "budget", "workers", "store", "resume", dt=dict(
        help="time step (default: the fastest linear period / 50, smaller where the numerical "
             "heating would exceed 1e-3 of kT, halved for BAOAB, then halved again while a "
             "pilot at dt and dt/2 measures a bias of the moments beyond 2e-4, and shortened "
             "so that --t-end is a whole number of steps; the run prints the step used)"),
        budget=dict(help=f"largest number of integration steps (default {BUDGET_TEXT}); "
                         "beyond it the averaged answer is given alone"),
        workers=dict(help="worker processes of the ensemble (default: all cores), and at most "
                          "this many for the Fokker-Planck solve (default 2, the environment's "
                          "KBM_FP_WORKERS); the numbers do not depend on it"))
    p.add_argument("--order", type=int, choices=(1, 2), default=1,
                   help="order of the amplitude averaging (default 1; 2 adds the O(mu) and "
                        "O(mu^2) corrections at fixed D/mu, docs/noise.rst; "
                        "polynomial F only)")
    p.add_argument("--method", choices=("averaging", "fokker-planck"), default="averaging",
                   help="the prediction beside the simulation: stochastic averaging (default; "
                        "a model at rest also gets the stationary Fokker-Planck moments when "
                        "they are affordable), or fokker-planck: the stationary Kramers "
                        "equation solved numerically, required (an error when the model is "
                        "driven or its damping is not polynomial in x')")
    options(p, "fp_budget", fp_budget=dict(
        help=f"largest cost of a Fokker-Planck solve (default {FP_BUDGET:.2g}): N_Hermite x "
             "N_Chebyshev^2 on the Chebyshev grid (time about cost x N_Chebyshev, memory about "
             "cost numbers; its last Hermite rung may take up to 2.8 times it), 0.6 "
             "N_Hermite^2 x elements on the spectral elements of a multi-well slider (about "
             "100 bytes per unit); N_Chebyshev and the elements halved for a model symmetric "
             "under (x, x') -> (-x, -x'); raise it for more digits at low friction"))
    p.add_argument("--no-fokker-planck", action="store_true",
                   help="skip the Fokker-Planck moments (moments.*.fokker_planck = null)")
    p.add_argument("--extrapolate", action="store_true",
                   help="also report the two-level Richardson value E_dt + (4/3)(E_dt/2 - "
                        "E_dt) (weak order 4): BAOAB at dt plus the correction from a smaller "
                        "coupled ensemble at dt and dt/2 sized by Giles' allocation, with the "
                        "standard error of both levels (moments.*.extrapolated; adds about 1.3-1.5 "
                        "times the main run's steps)")
    options(p, "json", "out", out=dict(help="write noise-MODEL.png (the averaged density "
                                                "over the histogram) and noise-MODEL.json"))
    p.set_defaults(func=run)



def _fp_format(rep: dict) -> str:
    """The Fokker-Planck moments' format: ten digits, fewer when the Hermite truncation's
    measured change (``fokker_planck.hermite_change``; ``None``: not measured) supports
    fewer."""
    fp = rep.get("fokker_planck") or {}
    change = fp.get("hermite_change", 0.0)
    if change is None:
        return "#.2g"
    return "#.10g" if change <= 1e-10 else f"#.{min(10, max(2, int(-math.log10(change))))}g"


def _fp_stated(rep: dict) -> str:
    """The text line of the Fokker-Planck moments' stated error (``""`` without them, or
    when it is not measured: a warning says so): ``fokker_planck.hermite_change`` (relative)
    times each moment, the ``+-`` of the digits the column prints."""
    fp = rep.get("fokker_planck") or {}
    change = fp.get("hermite_change")
    if not fp or change is None:
        return ""
    if change == 0:  # numerics.fokker_planck.kramers: linear damping, sigma^2 = kT
        return ("stated error of the Fokker-Planck values: none from the Hermite functions "
                "(linear damping: the Maxwellian is one of them), the grid resolves "
                "exp(-G/kT) to 1e-9")
    return ("stated error of the Fokker-Planck values: " + ", ".join(
        f"<{k[0]}^2> +- {change * abs(rep['moments'][k]['fokker_planck']):.2g}"
        for k in ("a2", "x2")) + f" (relative {change:.2g}: the change under the last "
        "refinements of the Hermite functions and the grid)")


def run(args) -> int:
    from numerics.cli.params.options import check_ensemble, stored
    from kbm.parameters.values import parameter_value
    from numerics.cli.params.noise import noisy_model
    from numerics.cli.params.values import given

    check_ensemble(args)
    if args.method == "fokker-planck" and args.no_fokker_planck:  # the method won silently
        raise ParameterError("--no-fokker-planck contradicts --method fokker-planck, which "
                             "requires the Fokker-Planck moments: give one of them")
    if args.fp_budget is not None and args.no_fokker_planck:
        raise ParameterError("--fp-budget contradicts --no-fokker-planck, which skips the "
                             "Fokker-Planck solve: give one of them")
    params, noise = noisy_model(args.model, args.param)
    from numerics.thermal.stationary import noise_report  # after the input is checked
    figure = None
    if args.out:
        out = Path(args.out)
        out.mkdir(parents=True, exist_ok=True)
        figure = out / f"noise-{args.model}.png"
    with stored(args) as store:
        rep = noise_report(args.model, params, trajectories=args.trajectories,
                           t_end=args.t_end, burn_in=args.burn_in, dt=args.dt, seed=args.seed,
                           budget=args.budget, workers=args.workers, progress=not args.json,
                           figure=figure, store=store, method=args.method,
                           fokker_planck=not args.no_fokker_planck, order=args.order,
                           extrapolate=args.extrapolate, fp_budget=args.fp_budget,
                           energy_density=bool(args.json or args.out))  # P(E): not printed
    if args.out:
        write_json(Path(args.out) / f"noise-{args.model}.json", rep)
    if args.json:
        return emit_json(rep)
    temp = (f" (T = D/mu = {float(parameter_value('T', given(args.param)['T'])):g})"
            if noise == "T" else "")
    print(f"stationary state of {args.model} with noise sqrt(2 D) xi, D = {rep['D']:g}{temp}")
    print(f"  averaging: {rep['method'] or '-- (' + rep['message'] + ')'}"
          + (f", order {rep['averaged_order']}" if rep.get("averaged_order") else ""))
    # the burn-in is a whole number of steps (numerics.thermal.stationary.default_times)
    ran = "simulated" if rep["density"] is not None else "not simulated (refused, below)"
    print(f"  {ran}: {rep['trajectories']} trajectories x t = {rep['t_end']:.6g} after a "
          f"burn-in of {rep['burn_in']:.4g} ({round(rep['burn_in'] / rep['dt'])} steps), "
          f"dt = {rep['dt']:.4g}, seed {rep['seed']}")
    pilot = rep.get("step_pilot") or {}
    if pilot.get("outcome") == "unresolved":
        print(f"  dt is the heating rule's, unmeasured: the step pilot cannot resolve its bias "
              f"tolerance {pilot['tolerance']:.2g} within its budget of "
              f"{pilot['budget']:.2g} steps")
    elif pilot.get("outcome") == "shrunk":
        print(f"  dt is the step pilot's: the heating rule's {pilot['h0']:.4g} had a measured "
              f"bias beyond {pilot['tolerance']:.2g}")
    if rep.get("fokker_planck"):
        f = rep["fokker_planck"]
        points = ("points of spectral elements" if "elements" in f.get("method", "")
                  else "Chebyshev points")
        print(f"  Fokker-Planck: stationary Kramers equation, {f['hermite']} Hermite functions "
              f"of x' x {f['chebyshev']} {points} on |x| <= {f['half_width']:.4g}")
        change = f.get("hermite_change", 0.0)
        if change is None:
            print("  WARNING: the Fokker-Planck moments' truncation error is not measured (a "
                  "second Hermite truncation passes the cost budget); only 2 digits are shown")
        elif change > 1e-6:
            print(f"  WARNING: the Fokker-Planck moments are not converged: the last "
                  f"refinements of the Hermite functions and the grid moved them by "
                  f"{change:.2g} (relative; the solve stops at 1e-8 or at its cost budget); "
                  f"only the digits this supports are shown")
        if f.get("advice"):
            print(f"  {f['advice']}")
    elif rep.get("fokker_planck_message"):
        print(f"  Fokker-Planck: -- ({rep['fokker_planck_message']})")
    print(f"  {'':6}{'averaged':>12}  {'simulated':>12}  {'stderr':>9}  (avg-sim)/stderr"
          f"  {'Fokker-Planck':>13}")
    for key in ("a2", "x2"):
        m = rep["moments"][key]  # the gap: the validity record's (gap_z)
        print(f"  <{key[0]}^2> {cell(m['averaged'], '#.6g'):>12}  "
              f"{cell(m['simulated'], '#.6g'):>12}  {cell(m['stderr'], '.2g'):>9}  "
              f"{cell(rep['validity']['z'][key], '+.2f'):>16}  "
              f"{cell(m.get('fokker_planck'), _fp_format(rep)):>13}")
    stated = _fp_stated(rep)
    if stated:
        print(f"  {stated}")
    errs = [(k, rep["moments"][k]) for k in ("a2", "x2")
            if rep["moments"][k].get("averaged_error") is not None]
    if errs:
        print(f"  expected error of the averaged values (order {rep['averaged_order']}): "
              + ", ".join(f"<{k[0]}^2> +- {m['averaged_error']:.2g} "
                          f"({ERROR_SOURCES[m['averaged_error_source']]})" for k, m in errs))
    ext = rep.get("extrapolation")
    if ext and ext.get("applied"):
        for key in ("a2", "x2"):
            m = rep["moments"][key]
            print(f"  <{key[0]}^2> extrapolated (two-level Richardson, order {ext['order']}, "
                  f"{ext['trajectories']['coarse']} + {ext['trajectories']['correction']} "
                  f"trajectories): {cell(m['extrapolated'], '#.6g')} +- "
                  f"{cell(m['extrapolated_stderr'], '.2g')}")
    elif ext:
        print(f"  extrapolation: -- ({ext['reason']})")
    if rep["moments"]["x2"]["boltzmann"] is not None:
        print(f"  Boltzmann <x^2> (exact, exp(-G/kT) by quadrature): "
              f"{cell(rep['moments']['x2']['boltzmann'], '#.6g')}")
    if rep.get("validity", {}).get("flagged"):
        print(f"  WARNING: {rep['validity']['advice']}")
    if rep["message"] and rep["method"]:
        print(f"  {rep['message']}")
    if args.out:
        print(f"  wrote {figure} and {Path(args.out) / f'noise-{args.model}.json'}")
    return 0
