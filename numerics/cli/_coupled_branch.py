"""``kbm branch`` and ``kbm response`` for coupled systems (``N`` degrees of freedom, or a
built-in of one degree of freedom as ``N = 1``): the true branch by pseudo-arclength
continuation of the shooting problem (:func:`numerics.shooting.coupled_branch.continue_coupled`);
:func:`run_coupled_response` is ``kbm response`` of a forced coupled built-in or ``--rhs``
list."""

from __future__ import annotations

import argparse
import math

from kbm.cli._common import emit_json
from kbm.errors import ParameterError
from numerics._show import multipliers_text


def shown(points: list) -> list:
    """About 20 of a branch's points for its table: every k-th and the last."""
    step = max(1, len(points) // 20)
    return list(points[::step]) + ([points[-1]] if (len(points) - 1) % step else [])


def _start(text: str | None, dof: int):
    if text is None:
        return None
    from numerics.cli.params.values import numbers

    start = numbers(text, "--start")
    if not all(math.isfinite(v) for v in start) or len(start) != 2 * dof:
        raise ParameterError(f"--start needs {2 * dof} finite numbers (x1..x{dof}, "
                             f"xdot1..xdot{dof}), got {text!r}")
    return start


def run_coupled_branch(args: argparse.Namespace, name: str, lo: float, hi: float,
                       what: str, model=None) -> int:
    """Continue the periodic orbits of the command line's coupled system (or ``model``) in
    ``name`` over ``[lo, hi]`` (from ``-p NAME=VALUE`` if given, else from ``lo``)."""
    from kbm.cli.derive import coupled_model
    from numerics.shooting.acceptance import RESIDUAL_FACTOR, orbit_scale, residual_tolerance
    from numerics.shooting.coupled_branch import continue_coupled

    model = coupled_model(args) if model is None else model
    if what == "response" and not model.forced:
        raise ParameterError(f"{model.name!r} has no forcing (theta); its branches of cycles "
                             "are kbm branch")
    from numerics.cli.params.values import check, given as read, within

    given = read(args.param)
    check(model, given, [name], start=True)
    start = _start(getattr(args, "start", None), model.dof)
    max_points = getattr(args, "max_points", None) or 200
    within(max_points, "--max-points", 2, 100000)
    rtol = max(getattr(args, "rtol", 1e-11) or 1e-11, 1e-13)
    if not rtol <= 1e-5:
        raise ParameterError(f"--rtol must be between 1e-13 and 1e-5, got {rtol}")
    br = continue_coupled(model, given, name, (lo, hi), start=start,
                          max_points=max_points, rtol=rtol)
    if args.json:
        return emit_json({**br.to_json(), "params_given": given})
    kind = "periodic responses" if br.forced else "periodic orbits"
    print(f"branch of {kind} of {br.model} ({br.dof} degrees of freedom), {name} from "
          f"{lo:g} to {hi:g}: {len(br.points)} points, {br.evaluations} integrations of a "
          "period with the monodromy")
    amp = "  ".join(f"{f'max|x{i + 1}|':>12s}" for i in range(br.dof))
    print(f"  {name:>14s} {'period':>12s}  {amp}  {'|multiplier| max':>16s}")
    zeros = False
    for p in shown(br.points):
        rest = p.floquet_multipliers if br.forced else p.floquet_multipliers[1:]
        big = max(abs(z) for z in rest)
        floor = residual_tolerance(rtol, orbit_scale(p.state))
        zeros |= min(p.amplitudes) < floor
        amps = "  ".join(f"{a:12.8g}" if a >= floor else f"{0:12d}" for a in p.amplitudes)
        print(f"  {p.parameter:14.8g} {p.period:12.8g}  {amps}  {big:16.6g} "
              f"{'stable' if p.stable else 'UNSTABLE'}")
    if zeros:
        print(f"  (0: below the accuracy of the orbit, the residual accepted, "
              f"{RESIDUAL_FACTOR:g} rtol max(1, |state|) with rtol = {rtol:g})")
    for s in br.special:
        mult = multipliers_text(s.floquet_multipliers)
        print(f"  {s.kind}: {name} = {s.parameter:.10g} (bracket {s.bracket[0]:.10g} .. "
              f"{s.bracket[1]:.10g}); multipliers {mult}")
    for r in br.reasons:
        print(f"  end {r}")
    return 0


def run_coupled_response(args: argparse.Namespace) -> int:
    """A forced coupled built-in: the true response branch in its detuning."""
    from kbm.cli.derive import coupled_model
    from numerics.cli.params.forced import named_range

    extra = [f for f, v in (("--forcing", args.forcing),
                            ("--hard", args.hard), ("--resonance", args.resonance),
                            ("--detuning", args.detuning), ("--nu", args.nu),
                            ("--convergence", args.convergence), ("--out", args.out),
                            ("--order", args.order), ("--a-range", args.a_range))
             if v is not None]
    if extra:
        raise ParameterError(f"{', '.join(extra)}: not for the coupled system "
                             f"{args.model or 'of the --rhs list'!r}; "
                             "its response is the true branch in a detuning (--vary "
                             "NAME=FROM:TO[:N]); its slow flow is kbm derive")
    if args.vary is None:
        raise ParameterError("give the range of the detuning (or another parameter): --vary "
                             "NAME=FROM:TO")
    if args.rhs:
        from kbm.model.coupled_builtins import coupled_custom

        if args.model:
            raise ParameterError("give either a model name or --rhs, not both")
        if args.nu0 is None:
            raise ParameterError("--nu0 is needed with several --rhs: the forcing frequency "
                                 "nu = NU0 + mu sigma of theta")
        model = coupled_custom(args.rhs, args.omega0, nu0=args.nu0)
    else:
        if args.nu0 is not None:
            raise ParameterError(f"--nu0 is for --rhs lists; {args.model!r} has its own")
        model = coupled_model(args)
    if args.internal:
        model = model.with_internal(args.internal)
    name, lo, hi, n = named_range(args.vary)
    args.max_points = n
    return run_coupled_branch(args, name, lo, hi, "response", model=model)
