"""``kbm response``: the frequency-response curve of a forced oscillator, KBM and shooting.

This module holds the options and the curve, the steady states at one detuning and the
non-resonant expansion; the forced model and its values are :mod:`numerics.cli.params.forced`,
``--convergence`` is :mod:`numerics.cli._response_convergence`, and coupled systems are
:func:`numerics.cli._coupled_branch.run_coupled_response`."""

from __future__ import annotations

import argparse

from kbm.cli._common import ONE_DOF, emit_json
from kbm.errors import ParameterError
from numerics.cli.params.forced import (amplitude_window, checked_values, forced_model,
                                       sigma_range)
from numerics._show import multipliers_text
from numerics.cli.params.options import command, options


def register(sub) -> None:
    p = command(sub, "response", "x'' + omega0^2 x = mu F(x, x', theta), theta = nu t, nu = (p/q) "
                "omega0 + mu sigma: the slow flow of the forced KBM expansion to order N, its "
                "fixed points (stable and unstable) followed in sigma with the folds (jump "
                "points) and the backbone, next to the true periodic responses of period 2 pi "
                "p/nu by shooting and pseudo-arclength continuation with Floquet multipliers.",
                "internal", models=ONE_DOF, coupled=True, model=dict(
        help="a forced model (duffing-forced, duffing-super, duffing-super-hard, "
             "duffing-sub-hard, mathieu, vdp-forced, parametric, mathieu-2, mathieu-3, slider, "
             "slider-cdc) or an autonomous one (duffing, vdp, ...) with --forcing or --hard"),
        rhs=dict(action="append", help=(
            "your own F in x, xdot, theta and parameters (instead of a model); repeat it for N "
            "coupled degrees of freedom (F_i in x1..xN, xdot1..xdotN, theta; with --omega0 "
            "W1,..,WN and --nu0)")),
        omega0=dict(help="linear frequency for --rhs (default 1); comma-separated for several "
                         "--rhs"),
        nu0=dict(help="several --rhs: the forcing frequency nu = NU0 + mu sigma of theta"),
        internal=dict(
        metavar="P:Q[@I,J]",
        help="several --rhs: declared resonances (P:Q@I,F with the forcing), kept with the model"))
    p.add_argument("--forcing", metavar="EXPR",
                   help="added to F: a 2 pi-periodic function of theta = nu t, smooth in x "
                        "and xdot, e.g. 'h*cos(theta)', '-h*x*cos(theta)' or "
                        "'-d*sin(x + theta)' (not polynomial: numeric backend)")
    p.add_argument("--hard", metavar="K",
                   help="a hard (order-one) forcing K cos(theta) on the right-hand side, "
                        "x'' + omega0^2 x = mu F + K cos(nu t), for sub- and superharmonic "
                        "resonances (K a number or parameter name)")
    p.add_argument("--resonance", metavar="P/Q", default=None,
                   help="the declared resonance nu ~ (p/q) omega0 (1/1 primary, 1/3 "
                        "superharmonic, 3 subharmonic, 2 parametric); default the model's")
    options(p, "param", "vary", vary=dict(
        default=None, metavar="sigma=FROM:TO[:N]",
        help="the detuning range and about N points per branch (default 400)"))
    p.add_argument("--detuning", type=float, metavar="SIGMA",
                   help="instead of --vary: every steady response at this one detuning")
    p.add_argument("--nu", metavar="VALUE",
                   help="instead of a resonance: a fixed forcing frequency, for the "
                        "non-resonant expansion (refused, with the resonance named, when a "
                        "harmonic comes near resonance)")
    p.add_argument("--order", type=int, default=None, metavar="N",
                   help="KBM order of the analytic curve (default 1); with --convergence the "
                        "orders 1..N compared (default 2)")
    p.add_argument("--amax", type=float, default=5.0,
                   help="largest amplitude searched for steady states (default 5)")
    options(p, "a_range", a_range=dict(
        help="the amplitude window of the steady states instead of --amax (default "
             "0.001*amax:amax); for F not polynomial in x, xdot (slider, slider-cdc, sin(k*x + "
             "theta)) also the interval of the numeric forced backend (default 0.05*amax:amax)"))
    p.add_argument("--no-numeric", action="store_true", help="the analytic curve only")
    options(p, "out", "convergence", out=dict(
        help="write the figure response.png into DIR (convergence.png with --convergence)"),
        convergence=dict(help=(
            "convergence study instead of the curve: the error of each KBM order 1..N against "
            "the true periodic response (shooting) for these values of mu (at least 3, "
            "positive, distinct), with the fitted slopes of log(error) against log(mu) "
            "(expected N): the amplitude at --detuning SIGMA, or the detuning of a fold (jump) "
            "in --vary sigma=FROM:TO; with --out, the log-log figure convergence.png")))
    p.add_argument("--fold", type=int, default=None, metavar="K",
                   help="with --convergence and --vary: the fold studied, counted from the "
                        "lowest sigma (default 0)")
    options(p, "start", "json", start=dict(
        metavar="X1,..,XDOT1,..",
        help="coupled systems: the state to start the branch from (default: the attracting "
             "response after a transient from x_i = 1)"))
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from pathlib import Path

    from kbm.model.coupled_builtins import COUPLED_MODELS

    from numerics.cli.params.values import within
    from numerics.comparison.response_diagram import response_diagram

    if args.vary is not None:  # the last --vary silently replaced the others
        if len(args.vary) > 1:
            raise ParameterError(f"kbm response varies the detuning alone: give one --vary "
                                 f"(got {', '.join(v.split('=')[0] for v in args.vary)})")
        args.vary = args.vary[0]
    if args.rhs is not None and len(args.rhs) > 1:
        from numerics.cli._coupled_branch import run_coupled_response

        return run_coupled_response(args)
    if args.nu0 is not None or args.internal:
        raise ParameterError("--nu0 and --internal are for coupled systems (several --rhs)")
    if args.rhs is not None:
        args.rhs = args.rhs[0]
    if args.model in COUPLED_MODELS:
        from numerics.cli._coupled_branch import run_coupled_response

        return run_coupled_response(args)
    if args.start is not None:
        raise ParameterError("--start is for the coupled systems (duffing-1-3, "
                             "quadratic-1-2, ...)")
    if args.convergence is not None:
        from numerics.cli._response_convergence import run_convergence

        return run_convergence(args)
    if args.fold is not None:
        raise ParameterError("--fold chooses the fold of a convergence study: use it with "
                             "--convergence and --vary")
    if args.order is None:
        args.order = 1
    if args.nu is not None:
        return _run_nonresonant(args)
    if (args.vary is None) == (args.detuning is None):
        raise ParameterError("give either --vary sigma=FROM:TO[:N] (a response curve) or "
                             "--detuning SIGMA (the steady states at one detuning)")
    within(args.order, "--order", 1, 8)
    if not args.amax > 0:
        raise ParameterError(f"--amax must be positive, got {args.amax}")
    model = forced_model(args)
    args.window = amplitude_window(model, args)
    if args.detuning is not None:
        return _run_one(model, args)
    lo, hi, n = sigma_range(args.vary)
    d = response_diagram(model, checked_values(model, args, ("sigma",)), (lo, hi),
                         order=args.order, n_points=400 if n is None else n, resonance=args.resonance,
                         amplitudes=args.window, numeric=not args.no_numeric)
    if args.out:
        from numerics.paper.figures.forced import plot_response

        plot_response(d, Path(args.out) / "response.png")
    if args.json:
        return emit_json(d.to_json())
    print(f"{d.model}, resonance {d.resonance}, KBM order {d.order}: "
          f"{', '.join(f'{k} = {v:g}' for k, v in d.values.items())}")
    print(f"  slow flow: da/dt = {d.slow_flow[0]}\n             dphi/dt = {d.slow_flow[1]}")
    for i, b in enumerate(d.analytic.branches):
        print(f"  analytic branch {i}: {len(b.sigma)} points, amplitude "
              f"{b.amplitude.min():.6g} .. {b.amplitude.max():.6g}, "
              f"{int(b.stable.sum())} stable")
    if not d.analytic.branches:
        print(f"  no steady state with {args.window[0]:g} < a < {args.window[1]:g}")
    for lo_s, hi_s, st in _intervals(d.analytic.trivial):
        print(f"  trivial state a = 0: {st} for sigma in "
              f"[{lo_s:.6g}, {hi_s:.6g}]")
    for f in d.analytic.folds:
        print(f"  fold (jump) at sigma = {f.sigma:.10g}, a = {f.amplitude:.8g}")
    if d.numeric is not None:
        for i, b in enumerate(d.numeric.branches):
            print(f"  shooting branch {i}: {len(b)} responses, "
                  f"{sum(o.stable for o in b)} stable")
        for o in d.numeric.folds:
            kind = "branch point on x = 0" if o.amplitude_max < 1e-3 * args.window[1] \
                else "fold"
            print(f"  true {kind} at sigma = {o.sigma:.10g}, a = {o.amplitude:.8g}, "
                  f"max|x| = {o.amplitude_max:.8g}")
        for sp in d.numeric.special:
            m = multipliers_text(sp.orbit.multipliers)
            print(f"  {sp.kind} at sigma = {sp.orbit.sigma:.10g}, a = {sp.orbit.amplitude:.8g} "
                  f"(multipliers {m})")
        for msg in d.numeric.failures:
            print(f"  not continued: {msg}")
    if args.out:
        print(f"  figure: {Path(args.out) / 'response.png'}")
    return 0


def _intervals(trivial) -> list[tuple[float, float, str]]:
    """Runs of equal stability of the trivial state: ``(from, to, kind)``."""
    out: list[tuple[float, float, bool]] = []
    for s, st in trivial:
        if out and out[-1][2] == st:
            out[-1] = (out[-1][0], s, st)
        else:
            out.append((s, s, st))
    return out


def _run_one(model, args: argparse.Namespace) -> int:
    from numerics.cli.params.values import within
    from numerics.comparison.response_diagram import steady_states

    within(args.detuning, "--detuning")
    if args.out:
        raise ParameterError("--out draws a response curve: use it with --vary")
    s = steady_states(model, checked_values(model, args), args.detuning, order=args.order,
                      resonance=args.resonance, amplitudes=args.window,
                      numeric=not args.no_numeric)
    if args.json:
        return emit_json(s.to_json())
    print(f"{s.model}, resonance {s.resonance}, KBM order {s.order}, sigma = {s.sigma:g}: "
          f"{len(s.analytic)} steady state(s) with a > 0")
    for f in s.analytic:
        print(f"  KBM:      a = {f.amplitude:.10g}, phi = {f.phase:.8g}, "
              f"{'stable' if f.stable else 'unstable'}")
    if s.trivial is not None:
        print(f"  KBM:      a = 0 (trivial), {s.trivial}")
    for o in s.numeric:
        mods = ", ".join(f"{abs(m):.6g}" for m in o.multipliers)
        print(f"  shooting: a = {o.amplitude:.10g}, max|x| = {o.amplitude_max:.8g}, "
              f"|multipliers| = {mods}, {'stable' if o.stable else 'unstable'}")
    for msg in s.failures:
        print(f"  not found: {msg}")
    return 0


def _run_nonresonant(args: argparse.Namespace) -> int:
    from kbm.expansion.forced import derive_forced

    if args.vary or args.detuning is not None or args.resonance or args.out:
        raise ParameterError("--nu (a fixed, non-resonant forcing frequency) goes without "
                             "--vary, --detuning, --resonance and --out")
    model = forced_model(args)
    if not model.is_polynomial:
        raise ParameterError(f"--nu (the non-resonant expansion) needs F polynomial in x and "
                             f"xdot; F of {model.name!r} is not, and its numeric backend "
                             "works near a declared resonance: use --resonance P/Q with "
                             "--vary or --detuning instead")
    r = derive_forced(model, args.order, checked_values(model, args), nu=args.nu)
    if args.json:
        return emit_json({**r.to_json(), "nu": args.nu})
    print(f"{r.model.name}, nu = {args.nu} (non-resonant), KBM order {r.order}:")
    print(f"  da/dt   = {r.amplitude_rate()}\n  dpsi/dt = {r.phase_rate()}")
    return 0
