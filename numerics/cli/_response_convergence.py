"""``kbm response --convergence``: the error of each KBM order against the true periodic
response (shooting) over several values of mu, at one detuning or for one fold."""

from __future__ import annotations

import argparse

from kbm.cli._common import emit_json
from kbm.errors import ParameterError
from numerics.cli.params.forced import (amplitude_window, checked_values, forced_model,
                                       sigma_range)


def convergence_mus(text: str) -> list[float]:
    """The values of ``--convergence``: at least 3, positive, finite and distinct."""
    from numerics.comparison.response_convergence import check_mus

    from numerics.cli.params.values import numbers

    try:
        return list(check_mus(numbers(text, "--convergence"), minimum=3))
    except ParameterError as exc:
        raise ParameterError(f"--convergence {text}: {exc}") from None


def run_convergence(args: argparse.Namespace) -> int:
    """``--convergence``: the order-``N`` error against ``mu`` at one detuning (amplitude)
    or for one fold (its detuning), with the fitted slopes."""
    import sys
    from pathlib import Path

    from kbm.backend.forced import forced_expansion
    from numerics.cli.params.values import within
    from numerics.comparison.response_convergence import amplitude_study, fold_study

    refused = [name for name, on in (("--nu", args.nu is not None),
                                     ("--no-numeric", args.no_numeric)) if on]
    if refused:
        raise ParameterError(f"--convergence compares with the true responses at the "
                             f"resonance and cannot go with {' or '.join(refused)}")
    if (args.vary is None) == (args.detuning is None):
        raise ParameterError("--convergence needs either --detuning SIGMA (the amplitude "
                             "there) or --vary sigma=FROM:TO (the detuning of a fold)")
    if args.detuning is not None and args.fold is not None:
        raise ParameterError("--fold chooses a fold of the curve: use it with --vary, not "
                             "--detuning")
    mus = convergence_mus(args.convergence)
    order = 2 if args.order is None else args.order
    within(order, "--order", 1, 8)
    if not args.amax > 0:
        raise ParameterError(f"--amax must be positive, got {args.amax}")
    model = forced_model(args)
    values = checked_values(model, args, () if args.vary is None else ("sigma",))
    if "mu" in values:
        raise ParameterError(f"--convergence sets mu ({args.convergence}): leave out "
                             f"--param mu={values['mu']}")
    amplitudes = amplitude_window(model, args)
    orders = tuple(range(1, order + 1))
    result = forced_expansion(model, order, values, resonance=args.resonance,
                              a_range=amplitudes)
    if args.detuning is not None:
        within(args.detuning, "--detuning")
        table = amplitude_study(model, values, args.detuning, mus, orders,
                                amplitudes=amplitudes, result=result)
    else:
        lo, hi, n = sigma_range(args.vary)
        fold = 0 if args.fold is None else args.fold
        if fold < 0:
            raise ParameterError(f"--fold counts the folds from 0, got {fold}")
        kw = {} if n is None else {"n_points": n}
        if n is not None and not 2 <= n <= 100000:
            raise ParameterError(f"the number of points must be between 2 and 100000, got {n}")
        table = fold_study(model, values, (lo, hi), mus, orders, which=fold,
                           amplitudes=amplitudes, result=result, **kw)
    figure = None
    if args.out:
        from numerics.paper.figures.forced import plot_convergence

        figure = plot_convergence(table, Path(args.out) / "convergence.png")
    if args.json:
        emit_json(table.to_json())
        if figure is not None:
            print(f"figure: {figure}", file=sys.stderr)
        return 0
    print(table.table())
    if figure is not None:
        print(f"figure: {figure}")
    return 0
