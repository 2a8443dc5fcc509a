"""``kbm spectrum``: the spectrum of a noisy oscillator, averaged against simulated.

A self-excited model of one degree of freedom (a built-in or ``--rhs``) gets its linewidth
(phase diffusion with the amplitude-phase coupling), mean frequency and PSD near the
fundamental (:mod:`numerics.spectrum.result`); a forced model goes to
:func:`numerics.cli._spectrum_driven.run_driven` (response spectra per detuning) and an
autonomous coupled one to :func:`numerics.cli._spectrum_driven.run_slips` (phase slips).
"""

from __future__ import annotations

from pathlib import Path

from kbm.cli._common import emit_json, write_json
from kbm.errors import ParameterError
from numerics._show import cell
from numerics.cli.params.options import command, options
from numerics.noise.validity import ERROR_SOURCES


def register(sub) -> None:
    p = command(sub, "spectrum", "The spectrum of x'' + omega0^2 x = mu F + sqrt(2 D) xi(t) (unit "
                "mass, <xi(t) xi(t')> = delta(t - t'); T = D/mu): for a self-excited model the "
                "linewidth (HWHM of the fundamental, angular: phase diffusion with the "
                "amplitude-phase coupling, Lax), the mean frequency and the PSD of x, by "
                "stochastic averaging and from an ensemble of Langevin trajectories (Welch PSD "
                "with a confidence band, phase-variance growth, one seed per trajectory spawned "
                "from --seed); for a forced model the noise spectra about its stable states; for "
                "coupled oscillators the phase-slip rate.", "param", "vary", "trajectories",
                models="vdp, rayleigh, sedf, ...; forced: duffing-forced, ...; coupled: "
                       "coupled-vdp", coupled=True, vary=dict(
        metavar="NAME=FROM:TO[:N]",
        help="forced: the detuning (e.g. sigma=0.5:1.5); coupled: the detuning; self-excited: "
             "D (or T), one run per value (the linewidth-vs-D figure)"), trajectories=dict(
        help="independent trajectories (default 64 self-excited, 32 otherwise; at least 8)"))
    p.add_argument("--duration", type=float, default=None, metavar="T",
                   help="recorded time per trajectory (default: enough for a resolution of a "
                        "quarter of the averaged linewidth and 100 amplitude relaxation times)")
    p.add_argument("--resolution", type=float, default=None, metavar="W",
                   help="self-excited: angular resolution of the PSD (default: the averaged "
                        "HWHM/4); a --duration shorter than 2 pi/W is refused")
    options(p, "seed", "workers", "store", "resume")
    p.add_argument("--order", type=int, choices=(1, 2), default=1,
                   help="order of the averaging (default 1; 2 adds the second-order KBM rates "
                        "mu^2 A_2, mu^2 B_2 and the corrections of the phase response through "
                        "the near-identity transform to the linewidth, right through mu^2 "
                        "(through mu for a transcendental F such as the SEDF's); its stated "
                        "error is measured against the true cycle)")
    p.add_argument("--floquet", action="store_true",
                   help="self-excited: add the small-noise linewidth D <Z_v^2> and frequency "
                        "of the true cycle (phase response by the adjoint Floquet problem; "
                        "exact in mu, first order in D)")
    options(p, "no_simulation", "json", "out", no_simulation=dict(
        help="self-excited: the averaged line alone (simulated entries null)"), out=dict(
        help="write spectrum-NAME-psd.png, spectrum-NAME-linewidth.png and the JSON"))
    p.set_defaults(func=run)


def _kind(args) -> str:
    """``"forced"``, ``"coupled"`` or ``"one"``."""
    from kbm.cli.derive import is_coupled

    if args.rhs and len(args.rhs) == 1 and "theta" in args.rhs[0]:
        return "forced"
    if args.model and not args.rhs:
        from kbm.model.forced_builtins import FORCED_MODELS

        if args.model in FORCED_MODELS:
            return "forced"
    if is_coupled(args):
        if args.model and not args.rhs:
            from kbm.model.coupled_builtins import get_coupled_model

            if get_coupled_model(args.model).forced:
                return "forced"
        elif args.nu0 is not None:
            return "forced"
        return "coupled"
    return "one"


def _bind(args):
    """``(model, params without D, D values, noise name)`` of a self-excited run."""
    from kbm.cli._common import check_model_flags
    from kbm.model.builtins import custom_model, with_slider_defaults
    from kbm.parameters.names import noise_intensity
    from numerics.spectrum.phase_diffusion import LINEWIDTH_NEED
    from kbm.parameters.values import parameter_value
    from numerics.cli.params.noise import noise_axis_model, noisy_model
    from numerics.cli.params.values import parse_vary, without_noise

    check_model_flags(args)
    if len(args.vary) > 1:
        raise ParameterError("--vary takes one range here: the noise, --vary D=FROM:TO[:N]")
    vary = parse_vary(args.vary[0]) if args.vary else None
    if vary is not None and vary.name not in ("D", "T"):
        raise ParameterError(f"--vary {vary.name}: a self-excited model's spectrum varies the "
                             "noise only: --vary D=FROM:TO[:N] or --vary T=FROM:TO[:N]")
    model = custom_model(args.rhs[0], omega0=1 if args.omega0 is None else args.omega0) \
        if args.rhs else args.model
    if vary is None:
        params, noise = noisy_model(model, args.param)
    else:  # refused naming the --vary typed
        params, noise, axis = noise_axis_model(model, args.param, vary, 3, LINEWIDTH_NEED)
    params, D0 = without_noise(with_slider_defaults(model, params), LINEWIDTH_NEED)
    if "mu" not in params:
        raise ParameterError("give the small parameter: -p mu=VALUE")
    mu = float(parameter_value("mu", params["mu"]))
    values = [D0]
    if vary is not None:
        values = [noise_intensity(float(v) * (mu if vary.name == "T" else 1.0), LINEWIDTH_NEED)
                  for v in axis]
    return model, params, values, noise


#: the options of a self-excited line that the other kinds do not use
_LINE_ONLY = {"forced": ("floquet", "no_simulation"),
              "coupled": ("floquet", "no_simulation", "resolution")}


def _check_options(args, kind: str) -> None:
    """Refuse a non-positive ``--duration`` or ``--resolution`` (``--resolution 0`` ended in
    a ``ZeroDivisionError``) and an option this kind of model would ignore."""
    from numerics.cli.params.values import positive

    positive(args.duration, "--duration")
    positive(args.resolution, "--resolution")
    what = {"forced": "response spectra of a forced model",
            "coupled": "phase-slip rate of coupled oscillators"}.get(kind)
    for name in _LINE_ONLY.get(kind, ()):
        if getattr(args, name) not in (None, False):
            flag = "--" + name.replace("_", "-")
            raise ParameterError(f"{flag} is for the line of a self-excited model; the {what} "
                                 f"would ignore it: leave out {flag}")


def run(args) -> int:
    from numerics.cli.params.options import check_ensemble, stored

    check_ensemble(args)
    kind = _kind(args)
    _check_options(args, kind)
    if kind == "forced":
        from numerics.cli._spectrum_driven import run_driven

        return run_driven(args)
    if kind == "coupled":
        from numerics.cli._spectrum_driven import run_slips

        return run_slips(args)
    from numerics.spectrum.result import DEFAULT_TRAJECTORIES, line_report, write_figures

    model, params, values, _ = _bind(args)
    reports = []
    with stored(args) as store:
        for D in values:
            reports.append(line_report(
                model, params, D, order=args.order,
                trajectories=args.trajectories or DEFAULT_TRAJECTORIES,
                duration=args.duration, resolution=args.resolution, seed=args.seed,
                workers=args.workers, store=store, progress=not args.json,
                simulate=not args.no_simulation, floquet=args.floquet, shared=len(values)))
    rep = dict(reports[0])
    if len(reports) > 1:
        rep["sweep"] = [{"D": r["D"], "linewidth": r["linewidth"], "frequency": r["frequency"],
                         "validity": r["validity"]} for r in reports]
    name = reports[0]["model"]
    if args.out:
        out = Path(args.out)
        rep["figures"] = [str(p) for p in write_figures(reports, out, name)]
        write_json(out / f"spectrum-{name}.json", rep)
    if args.json:
        return emit_json(rep)
    _print(rep, reports)
    return 0


def _print(rep: dict, reports: list[dict]) -> None:
    th = rep["theory"]
    print(f"spectrum of {rep['model']} with noise sqrt(2 D) xi, D = {rep['D']:g}, mu = "
          f"{rep['params'].get('mu', float('nan')):g} (averaging order {rep['order']})")
    print(f"  averaged cycle a* = {th['amplitude']:.6g}, relaxation lambda = "
          f"{th['relaxation']:.4g}, shear g = {th['shear']:.4g}: the coupling widens the line "
          f"{th['enhancement']:.3g} times")
    if rep.get("simulation"):
        s = rep["simulation"]
        print(f"  simulated: {s['trajectories']} trajectories x t = {s['duration']:.6g} after "
              f"{s['burn_in']:.4g}, dt = {s['dt']:.4g}, PSD resolution {s['resolution']:.3g}, "
              f"seed {s['seed']}")
    print(f"  {'':10}{'averaged':>12}  {'linearised':>12}  {'simulated':>12}  {'stderr':>9}  "
          "(avg-sim)/stderr")
    gaps = rep.get("validity", {}).get("z") or {}
    for key, label in (("linewidth", "HWHM"), ("frequency", "Omega")):
        r = rep[key]
        # the validity record's gap: Omega's with the scheme's step bias removed
        print(f"  {label:10}{cell(r['averaged'], '.8g'):>12}  {cell(r['linearised'], '.8g'):>12}"
              f"  {cell(r['simulated'], '.8g'):>12}  {cell(r['stderr'], '.2g'):>9}  "
              f"{cell(gaps.get(key), '+.2f'):>16}")
    errs = [(label, rep[key]) for key, label in (("linewidth", "HWHM"), ("frequency", "Omega"))
            if rep[key].get("expected_error") is not None]
    if errs:
        print(f"  expected error of the averaged values (order {rep['order']}): "
              + ", ".join(f"{label} +- {r['expected_error']:.2g} "
                          f"({ERROR_SOURCES[r['expected_error_source']]})" for label, r in errs))
    lw = rep["linewidth"]
    if lw.get("floquet") is not None:
        print(f"  true cycle (adjoint Floquet, first order in D): HWHM = {lw['floquet']:.6g}, "
              f"Omega = {rep['frequency']['floquet']:.8g}")
    if lw.get("fit") is not None:
        src = lw.get("fit_stderr_source") or ""
        print(f"  Lorentzian fit to the simulated PSD: HWHM = {lw['fit']:.4g} +- "
              f"{lw['fit_stderr']:.2g}"
              + ("" if src.startswith("jackknife") else f" (standard error by {src})"))
    if rep["frequency"].get("step_bias"):
        print(f"  the scheme's frequency bias omega0 (omega0 dt)^2/6 = "
              f"{rep['frequency']['step_bias']:.2g} (removed from the simulated Omega in "
              "(avg-sim)/stderr)")
    if rep.get("validity", {}).get("flagged"):
        print(f"  WARNING: {rep['validity']['advice']}")
    for r in reports[1:]:
        print(f"  D = {r['D']:g}: HWHM averaged {r['linewidth']['averaged']:.6g}, simulated "
              f"{cell(r['linewidth']['simulated'], '.6g')} +- {cell(r['linewidth']['stderr'], '.2g')}")
        if r.get("validity", {}).get("flagged"):
            print(f"  WARNING (D = {r['D']:g}): {r['validity']['advice']}")
    for p in rep.get("figures", []):
        print(f"  wrote {p}")
