"""``kbm escape``: the escape rate from the well at the origin, averaged and simulated."""

from __future__ import annotations

from kbm.cli._common import emit_json, single_well
from kbm.errors import ModelError, ParameterError
from numerics.cli.params.options import command, options
from numerics.noise.budget import BUDGET_TEXT, ESCAPE_FP_BUDGET


def register(sub) -> None:
    p = command(sub, "escape", "The rate of escape from the well at the origin of x'' + ... = "
                "sqrt(2 D) xi(t) (unit mass; kT = D/mu for linear damping mu): 1/MFPT of the "
                "averaged energy diffusion (energy-envelope stochastic averaging, underdamped "
                "regime), Kramers' low-friction rate, the Mel'nikov-Meshkov rate (one exit) and "
                "the turnover rate of the well's two exits (Kramers' spatial-diffusion factor "
                "times Mel'nikov-Meshkov's two-exit depopulation factor, any friction) for "
                "linear damping, against first passages of simulated trajectories started at "
                "the well bottom (escape: |x| reaches the saddle bounding the well).  With --method "
                "fokker-planck also the exact transition rate to the next wells and its like "
                "quantity: first passages to the next wells' bottoms from the well's Boltzmann "
                "state, compared in standard errors.  Where the expected "
                "cost of the simulation exceeds --budget steps the simulation is refused with the "
                "estimate and the averaged answer is given alone.", "trajectories", "t_end", "dt",
                "seed", "budget", "no_simulation",
                noisy="an autonomous model with a well at the origin bounded by saddles (cdc, "
                      "sedf at v = 0)",
                trajectories=dict(default=200,
                                  help="simulated trajectories (default 200; at least 20)"),
                t_end=dict(metavar="T",
                           help="longest run per trajectory (default: 5 averaged MFPTs; runs "
                                "still in the well at T are censored)"),
                dt=dict(help="time step (default: the well's period/40, smaller where the "
                             "numerical heating would exceed 1e-3 of kT; docs/noise.rst)"),
                budget=dict(help="largest expected number of integration steps (default "
                                 f"{BUDGET_TEXT})"),
                no_simulation=dict(help="the averaged rate only"))
    p.add_argument("--method", choices=("averaging", "fokker-planck"), default="averaging",
                   help="fokker-planck: also the slowest decay rate of the Kramers equation "
                        "with a sink at the next wells' bottoms (the transition rate, any "
                        "damping; with its sink and truncation errors), and the simulated "
                        "transitions to the next wells from the well's Boltzmann state")
    options(p, "fp_budget", "json", fp_budget=dict(
        help="with --method fokker-planck: the largest cost of the escape rate's Kramers "
             f"solves (default {ESCAPE_FP_BUDGET:.2g}): N_Hermite x N_Chebyshev^2 on the "
             "Chebyshev grid (the factorisation keeps about 3 times it in numbers), 7.5 "
             "N_Hermite^2 x elements/2 numbers on the spectral elements that low friction "
             "takes for a symmetric model; a bound on every solve: "
             "refused before solving, with the costs, where the first two rungs or the "
             "first grid check exceed it; the ladders stop at their last solve that fits, "
             "their stated errors and a warning say so"))
    p.set_defaults(func=run)


def run(args) -> int:
    from kbm.parameters.names import lookup, names_of
    from numerics.cli.params.options import check_ensemble
    from numerics.cli.params.noise import noisy_model
    from numerics.escape.report import escape_report

    check_ensemble(args)
    if args.fp_budget is not None and args.method != "fokker-planck":
        raise ParameterError("--fp-budget is the budget of the Fokker-Planck solve: give it "
                             "with --method fokker-planck")
    params, _ = noisy_model(args.model, args.param)
    if "v" in params:  # a slider's v (noisy_model takes it): "unknown parameter 'v'" before
        raise ParameterError(f"kbm escape computes the escape of {args.model} at rest, v = 0 "
                             "(the stage not pulling: the potential's barrier is fixed), so "
                             "-p v is not taken: leave it out (kbm noise or kbm friction "
                             "simulate the pulled slider)")
    if single_well(lookup(args.model, ("one",))):
        raise ModelError(f"{args.model} has no barrier to escape over at any parameter values: "
                         "its F at x' = 0 does not depend on x, so its potential is the single "
                         "well omega0^2 x^2/2; choose a model with side wells (cdc, or sedf "
                         "at v = 0, with Delta large enough)")
    try:
        rep = escape_report(args.model, params, trajectories=args.trajectories,
                            t_end=args.t_end, dt=args.dt, seed=args.seed, budget=args.budget,
                            simulate=not args.no_simulation, method=args.method,
                            fp_budget=args.fp_budget)
    except ModelError as exc:
        if "Delta" in names_of(args.model).valid or "(e.g. a larger Delta)" not in str(exc):
            raise
        raise ModelError(str(exc).replace(
            "choose parameters with side wells (e.g. a larger Delta)",
            f"choose parameters of {args.model} whose potential has a barrier, or a model "
            "with side wells (cdc, or sedf at v = 0, with Delta large enough)")) from None
    if args.json:
        return emit_json(rep)
    print(f"escape from the well at the origin: {args.model}, D = {rep['D']:g}")
    print(f"  barrier E_b - E_0 = {rep['barrier']:.6g}" + (
        f", kT = D/mu = {rep['kT']:.6g}, E_b/kT = {rep['barrier_over_kT']:.4g}"
        if rep["kT"] is not None else ""))
    print(f"  averaged energy diffusion: rate = {rep['rate_averaged']:.6g} "
          f"(MFPT {rep['mfpt_averaged']:.6g})")
    if rep["rate_kramers"] is not None:
        print(f"  Kramers low friction:      rate = {rep['rate_kramers']:.6g}")
        print(f"  Mel'nikov-Meshkov:         rate = {rep['rate_melnikov']:.6g} "
              "(one exit: A(delta) (omega0/2 pi) exp(-E_b/kT))")
    if rep.get("rate_turnover") is not None:
        print(f"  turnover, two exits:       rate = {rep['rate_turnover']:.6g} "
              "((lambda_+/omega_b) 2 A(delta/2) (omega0/2 pi) exp(-E_b/kT), Kramers x "
              f"Mel'nikov-Meshkov; omega_b = {rep['omega_b']:.6g})")
    if rep.get("rate_fokker_planck") is not None:
        print(fokker_planck_line(rep))
    if rep.get("rate_simulated_wells") is not None:
        w = rep["simulated_wells"]
        print(f"  simulated transitions:     rate = {rep['rate_simulated_wells']:.6g} +- "
              f"{rep['stderr_wells']:.2g} ({w['escaped']}/{rep['trajectories']} from the "
              + ("well's Boltzmann state" if w["start"] == "boltzmann" else "well bottom")
              + f" reached x = {w['wells'][0]:.6g} or "
              f"{w['wells'][1]:.6g} by t = {w['t_end']:.6g}"
              + (f"; the rate from the {w['settled']} still in the well at t = "
                 f"{w['settle']:.3g}" if w.get("settle") else "")
              + f"); Fokker-Planck - simulated = {rep['z_fokker_planck']:+.2f} standard errors")
    if rep["rate_simulated"] is not None:
        print(f"  simulated:                 rate = {rep['rate_simulated']:.6g} +- "
              f"{rep['stderr']:.2g} ({rep['escaped']}/{rep['trajectories']} escaped by "
              f"t = {rep['t_end']:.6g}, dt = {rep['dt']:.4g}, seed {rep['seed']})")
    for warning in rep.get("warnings", []):
        print(f"  WARNING: {warning}")
    if rep["message"]:
        print(f"  {rep['message']}")
    return 0


def fokker_planck_line(rep: dict) -> str:
    """The text line of the Fokker-Planck rate: 7 significant digits where its three error
    estimates (sink, truncation, Chebyshev) are all at most 1e-6 of it, else 6."""
    f = rep["fokker_planck"]
    rate = rep["rate_fokker_planck"]
    errors = [f.get(k) for k in ("sink_error", "truncation_error", "chebyshev_error")]
    digits = 7 if all(e is not None and e <= 1e-6 * rate for e in errors) else 6
    return (f"  Fokker-Planck (Kramers eq.): rate = {rate:.{digits}g} "
            f"(+- {f['sink_error']:.2g} sink, +- {f['truncation_error']:.2g} truncation, "
            f"+- {f['chebyshev_error']:.2g} Chebyshev; "
            f"{f['hermite']} Hermite x {f['chebyshev']} Chebyshev)")
