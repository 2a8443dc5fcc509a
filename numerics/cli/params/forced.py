"""The forced model and the ``-p``/``--vary`` values of ``kbm response`` for one degree of
freedom: the model of the command line (a forced built-in, or a model or ``--rhs`` with
``--forcing`` and ``--hard``), its values read by the one layer
(:mod:`numerics.cli.params.values`), the detuning's range and the amplitude window."""

from __future__ import annotations

import argparse

from kbm.errors import ModelError, ParameterError


def sigma_range(text: str) -> tuple[float, float, int | None]:
    """``sigma=FROM:TO[:N]`` -> ``(FROM, TO, N)``, ``N`` None when not given."""
    return named_range(text, "sigma")[1:]


def named_range(text: str,
                allowed: str | None = None) -> tuple[str, float, float, int | None]:
    """``NAME=FROM:TO[:N]`` -> ``(NAME, FROM, TO, N)`` by the grammar of
    :func:`numerics.cli.params.values.parse_vary`; ``allowed``: the only name taken."""
    from numerics.cli.params.values import parse_vary

    v = parse_vary(text)
    if allowed is not None and v.name != allowed:
        raise ParameterError(f"kbm response varies the detuning: --vary {allowed}=FROM:TO[:N], "
                             f"not {v.name!r}")
    lo, hi = v.interval("a response curve", points=True)
    return v.name, lo, hi, v.count


def checked_values(model, args: argparse.Namespace,
                   varied: tuple[str, ...] = ()) -> dict[str, str]:
    """The ``-p`` values of a forced model of one degree of freedom, read and checked by
    the one layer (:func:`numerics.cli.params.values.check`): every name one of the model's
    (``mu`` and the parameters of ``F``, ``omega0`` and a hard forcing), the detuning
    ``sigma`` only as ``--vary sigma=...`` or ``--detuning``.

    Raises
    ------
    kbm.errors.ParameterError
        For an unknown name (the valid ones listed) or ``-p sigma``.
    """
    from numerics.cli.params.values import check, given, wavenumber

    params = given(args.param)
    if "sigma" in params and not varied:
        raise ParameterError(f"sigma is the detuning: give it as --detuning {params['sigma']}"
                             " or a range --vary sigma=FROM:TO, not -p sigma")
    check(model, params, varied, extra=("sigma",) if varied else ())
    wavenumber(model, params)
    return params


def forced_model(args: argparse.Namespace):
    """The forced model of the command line: a forced built-in, or a model/--rhs with
    --forcing (and --hard) added."""
    model = _base_model(args)
    if getattr(args, "hard", None):
        from kbm.symbols import parse

        model = model.with_hard(model.hard + parse(args.hard))
    return model


def _base_model(args: argparse.Namespace):
    from kbm.model.forced_builtins import FORCED_MODELS, get_forced_model
    from kbm.model.forced import ForcedOscillator, add_forcing
    from kbm.model.builtins import custom_model
    from kbm.symbols import parse

    if args.model and args.rhs:
        raise ModelError("give either a model name or --rhs, not both")
    if not args.model and not args.rhs:
        raise ModelError("name a forced model (e.g. duffing-forced) or give --rhs EXPR")
    if args.model and args.omega0 is not None:
        raise ModelError(f"--omega0 applies to --rhs only, not to the model {args.model!r}")
    res = args.resonance or "1/1"
    if args.rhs:
        F = parse(args.rhs, extra=("theta",))
        if args.forcing:
            F = F + parse(args.forcing, extra=("theta",))
        w0 = custom_model("x", omega0=1 if args.omega0 is None else args.omega0).omega0
        return ForcedOscillator("custom", F, w0, res, f"user model mu*({F})")
    if args.model in FORCED_MODELS:
        model = get_forced_model(args.model)
        if args.forcing:
            model = ForcedOscillator(model.name, model.F + parse(args.forcing, extra=("theta",)),
                                     model.omega0, model.resonance, model.description,
                                     hard=model.hard)
        return model
    if not args.forcing and not getattr(args, "hard", None):
        raise ModelError(f"the model {args.model!r} has no forcing: add one with --forcing "
                         "EXPR in theta (e.g. --forcing 'h*cos(theta)') or --hard K, or use a "
                         f"forced model ({', '.join(FORCED_MODELS)})")
    return add_forcing(args.model, args.forcing or "0", res, name=f"{args.model}-forced")


def amplitude_window(model, args: argparse.Namespace) -> tuple[float, float]:
    """The amplitude window: ``--a-range``, or from ``--amax`` (clear of ``a = 0`` for the
    numeric backend, whose expansion has ``1/a`` terms)."""
    from kbm.backend.sampling import parse_a_range

    if args.a_range:
        return parse_a_range(args.a_range)
    return ((1e-3 if model.is_polynomial else 0.05) * args.amax, args.amax)
