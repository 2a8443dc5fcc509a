"""``kbm cycle``: the limit cycle of the full equation (shooting, Floquet multipliers)."""

from __future__ import annotations

import argparse

from kbm.cli._common import checked_params, describe_params, emit_json, model_spec, parse_params
from kbm.errors import ParameterError
from numerics._show import multipliers_text
from numerics.cli.params.options import command, options


def register(sub) -> None:
    p = command(sub, "cycle", "Find the periodic orbit of x'' + omega0^2 x = mu F(x, x') by "
                "Newton's method on the return map to x' = 0, x > 0, with Floquet multipliers and "
                "the dissipation per cycle (paper eqs. 10-11).", "param", "start",
                models="vdp, rayleigh, sedf, cdc, ...; coupled: coupled-vdp, duffing-1-3, "
                       "quadratic-1-2", coupled=True, start=dict(
        metavar="X1,..,XN,V1,..,VN",
        help="coupled systems: the state to start from (default x_i = 1, xdot_i = 0)"))
    p.add_argument("--transient", type=float, default=None, metavar="T",
                   help="coupled systems: time integrated before shooting (default 20/mu "
                        "within [100, 4000]; 0 shoots from --start itself)")
    options(p, "digits", "rtol", digits=dict(
        help="also compute period and amplitudes to N digits (mpmath Taylor series)"),
        rtol=dict(default=1e-12, help="integrator tolerance (1e-12)"))
    p.add_argument("--method", default="auto",
                   choices=["auto", "compiled", "LSODA", "DOP853", "Radau", "BDF"],
                   help="integrator of the shooting: auto (compiled DOP853 unless stiff, then "
                        "LSODA), compiled (DOP853 compiled with numba), or a scipy method")
    options(p, "x_start", x_start=dict(
        default=1.0, help="start of the last-resort transient, x = X, x' = 0 (default 1)"))
    p.add_argument("--all", action="store_true",
                   help="every cycle the energy-balance averaging predicts (stable and "
                        "unstable, on every annulus), each confirmed by shooting")
    options(p, "json")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from kbm.cli.derive import is_coupled
    from numerics.cli.params.values import within
    from numerics.flow.aot import allow_builds

    allow_builds()  # start-up is what this command is waited for (issue 39)

    if is_coupled(args):
        return _run_coupled(args)
    if args.start is not None or args.transient is not None:
        raise ParameterError("--start and --transient are for coupled systems; for one degree "
                             "of freedom use --x-start")

    within(args.digits, "--digits", 1, 200)
    within(args.rtol, "--rtol", 1e-15, 1e-3)
    within(args.x_start, "--x-start")
    kw = dict(digits=args.digits, rtol=args.rtol, method=args.method)
    from numerics.flow.card import use_cards  # noqa: PLC0415 - on use (issue 39)

    try:
        return _run_one(args, kw)
    finally:
        use_cards(False)  # the cards are this command's (a process may run others after)


def _run_one(args: argparse.Namespace, kw: dict) -> int:
    """One degree of freedom: the cycle (or ``--all``), printed."""
    from numerics import limit_cycle
    from numerics.cli.params.values import wavenumber

    card = None if args.all else _card(args)
    kinds = ("one", "coupled")  # a forced built-in: refused, no traceback
    if args.all:
        from numerics import limit_cycles

        params = checked_params(args.param, model_spec(args), kinds)
        wavenumber(model_spec(args), params)
        return _run_all(limit_cycles(model_spec(args), params, **kw), args)
    if card is not None:  # a warm run: no sympy (the names were checked by a cold one)
        params = parse_params(args.param)
        cyc = limit_cycle(_spec(args), params, x_start=args.x_start, **kw)
    else:
        from numerics.flow.card import name_model

        model = model_spec(args)
        params = checked_params(args.param, model, kinds)
        wavenumber(model, params)
        if getattr(args, "rhs", None):
            name_model(model, _spec(args))
        cyc = limit_cycle(model, params, x_start=args.x_start, **kw)
        card = _described(args, params, cyc)
    if args.json:
        emit_json({**_cycle_json(cyc), "params_given": params})
        return 0 if cyc.success else 1
    _print_cycle(cyc, args.digits, args, card)
    return 0 if cyc.success else 1


def _card(args: argparse.Namespace) -> dict | None:
    """The model card (:mod:`numerics.flow.card`) of a built-in model and these ``-p``
    values that a cold run stored after checking them (with the text of the parameters),
    or ``None``."""
    from kbm.cli._common import check_model_flags
    from numerics.flow.card import card_key, read_card, use_cards

    use_cards()
    check_model_flags(args)
    card = read_card(card_key(_spec(args), parse_params(args.param)))
    return card if card is not None and isinstance(card.get("described"), str) else None


def _described(args: argparse.Namespace, params: dict, cyc) -> dict:
    """The text of the parameters, added to the model card for the warm runs."""
    from numerics.flow.card import card_key, update_card

    text = describe_params(model_spec(args), parse_params(args.param), cyc.to_json()["params"])
    update_card(card_key(_spec(args), params), described=text)
    return {"described": text}


def _spec(args: argparse.Namespace):
    """The model's name on the command line, or ``("--rhs", RHS, OMEGA0)`` (a model card's
    name for the user's model, :func:`numerics.flow.card.card_key`)."""
    rhs = getattr(args, "rhs", None)
    if not rhs:
        return args.model
    return ("--rhs", rhs[0] if isinstance(rhs, list) else rhs,
            1 if args.omega0 is None else args.omega0)


def _cycle_json(cyc) -> dict:
    """The keys of :meth:`numerics.cycles.result.LimitCycle.to_json` and ``x_min``, the
    smallest x of the orbit's samples (the text's ``x_min``; ``None`` without samples)."""
    return {**cyc.to_json(), "x_min": float(min(cyc.x)) if len(cyc.x) else None}


#: how a cycle found as the mirror image of another is labelled (odd-symmetric models)
_MIRROR = "mirror image (x -> -x) of a cycle found"


def _run_all(cycles, args: argparse.Namespace) -> int:
    pred = cycles.predictions
    if args.json:
        rows = [{**_cycle_json(c), "annulus": _MIRROR if p is None else p.annulus,
                 "predicted": None if p is None else p.to_json()}
                for c, p in zip(cycles, cycles.predicted)]
        emit_json({"model": pred.model, "params": pred.params,
                   "params_given": parse_params(args.param), "cycles": rows,
                   "reason": pred.reason,
                   "failures": [{"predicted": p if isinstance(p, str) else p.to_json(),
                                 "error": e} for p, e in cycles.failures]})
        return 0 if all(c.success for c in cycles) else 1
    print(f"{len(cycles)} cycle(s) of {pred.model} from {len(pred.cycles)} predicted by the "
          "energy balance" + (f" ({pred.reason})" if not pred.cycles else ""))
    for c, p in zip(cycles, cycles.predicted):
        if p is None:
            print(f"\n[{_MIRROR}]")
        else:
            print(f"\n[{p.annulus}] predicted x_max {p.amplitude_max:.6g}, T {p.period:.6g}, "
                  f"{'stable' if p.stable else 'unstable'}")
        _print_cycle(c, args.digits, args)
    for p, e in cycles.failures:
        if isinstance(p, str):
            print(f"\n[{p}] no cycle found ({e})")
        else:
            print(f"\n[{p.annulus}] predicted x_max {p.amplitude_max:.6g}: no cycle found "
                  f"({e})")
    if cycles.failures and not cycles:
        return 1  # cycles were predicted and none was confirmed
    return 0 if all(c.success for c in cycles) else 1


#: what the text calls a key of ``--json`` (``amplitude_max`` is the largest x, negative on a
#: cycle in the left-hand well)
_LABELS = {"amplitude_max": "x_max (largest x)"}


def _print_cycle(cyc, digits, args, card: dict | None = None) -> None:
    data = cyc.to_json()
    w = digits or 12
    pars = card["described"] if card is not None else \
        describe_params(model_spec(args), parse_params(args.param), data["params"])
    print(f"limit cycle of {data['model']} ({pars})")
    for key in ("period", "frequency", "amplitude_max", "amplitude_first_harmonic"):
        val = data[key]
        label = _LABELS.get(key, key)
        if isinstance(val, str):
            print(f"  {label:26s} {val}")
        else:
            # never more digits than the accuracy estimate supports
            n = cyc.significant_digits(key, limit=w)
            note = f"  (relative accuracy ~{cyc.accuracy[key]:.0e})" if n < w else ""
            print(f"  {label:26s} {format(val, f'.{n}g')}{note}")
        if key == "amplitude_max" and len(cyc.x):
            print(f"  {'x_min (smallest x)':26s} {float(min(cyc.x)):.6g}  "
                  f"(of {len(cyc.x)} samples of the orbit)")
    m = cyc.floquet_multipliers
    print(f"  {'floquet multipliers':26s} {m[0].real:.12f} (trivial), {m[1].real:.6e} "
          f"({'stable' if cyc.stable else 'UNSTABLE'})")
    d = cyc.dissipation
    factor = "" if d.plus_factor == 1 else f"{d.plus_factor:g} "
    print(f"  {'dissipation Gamma':26s} {d.total:.3e} = {factor}Gamma+ - Gamma- (eq. 11; "
          f"Gamma+ {d.gamma_plus:.6g} gained, Gamma- {d.gamma_minus:.6g} lost)")
    print(f"  {'energy residual':26s} {cyc.energy_residual:.3e}")
    print(f"  {cyc.message}")


def _run_coupled(args: argparse.Namespace) -> int:
    import math

    from kbm.cli.derive import coupled_model
    from numerics.cli.params.values import numbers, within
    from numerics.shooting.coupled_orbit import coupled_cycle

    if args.all or args.digits is not None or args.method != "auto":
        raise ParameterError("--all, --digits and --method are for one degree of freedom; a "
                             "coupled system is shot from a transient (--start, --transient)")
    within(args.rtol, "--rtol", 1e-14, 1e-3)
    start = None if args.start is None else numbers(args.start, "--start")
    if start is not None and not all(math.isfinite(v) for v in start):
        raise ParameterError(f"--start must be finite numbers, got {args.start!r}")
    within(args.transient, "--transient", 0, 1e6)
    model = coupled_model(args)
    given = checked_params(args.param, model)
    if start is not None and len(start) != 2 * model.dof:
        raise ParameterError(f"--start needs {2 * model.dof} numbers (x1..x{model.dof}, "
                             f"xdot1..xdot{model.dof}), got {len(start)}")
    if model.forced:
        return _run_forced(model, given, start, args)
    cyc = coupled_cycle(model, given, start=start, transient=args.transient,
                        rtol=max(args.rtol, 1e-13))
    if args.json:
        return emit_json({**cyc.to_json(), "params_given": given})
    n = len(cyc.amplitudes)
    print(f"periodic orbit of {cyc.model} ({', '.join(f'{k}={v:g}' for k, v in cyc.params.items())})")
    print(f"  {'period':26s} {cyc.period:.12g}")
    print(f"  {'frequency':26s} {cyc.frequency:.12g}")
    for i in range(n):
        print(f"  {f'x{i + 1}: amplitude, phase':26s} {cyc.amplitudes[i]:.10g}, "
              f"{cyc.phases[i]:+.8f} rad")
    mults = multipliers_text(cyc.floquet_multipliers, 8)
    print(f"  {'floquet multipliers':26s} {mults} "
          f"({'stable' if cyc.stable else 'UNSTABLE'}; the first is the trivial one)")
    print(f"  {cyc.message}")
    return 0


def _run_forced(model, given, start, args) -> int:
    import math

    from numerics.shooting.coupled_orbit import forced_response

    periods = None
    if args.transient is not None:
        periods = int(math.ceil(args.transient / (2 * math.pi)))
        if args.transient > 0 and periods == 0:
            raise ParameterError("--transient is rounded up to whole forcing periods")
    res = forced_response(model, given, start=start, transient_periods=periods,
                          rtol=max(args.rtol, 1e-13))
    if args.json:
        return emit_json({**res.to_json(), "success": True, "params_given": given})
    print(f"periodic response of {res.model} ({', '.join(f'{k}={v:g}' for k, v in res.params.items())})")
    print(f"  {'forcing frequency nu':26s} {res.nu:.12g}")
    print(f"  {'period':26s} {res.period:.12g} ({res.multiple} x 2 pi/nu)")
    for i, a in enumerate(res.amplitudes, 1):
        print(f"  {f'x{i}: amplitude':26s} {a:.10g}")
    mults = multipliers_text(res.floquet_multipliers, 8)
    print(f"  {'floquet multipliers':26s} {mults} ({'stable' if res.stable else 'UNSTABLE'})")
    print(f"  Newton: {res.iterations} iterations, |y(T) - y0| = {res.residual:.2e}; det Phi = "
          f"{res.liouville[0]:.10g} against exp(int tr J) = {res.liouville[1]:.10g} "
          "(Liouville)")
    return 0
