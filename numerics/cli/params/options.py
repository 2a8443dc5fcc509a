"""The options of the numerical commands defined once: the command's parser with its
model and shared options (:func:`command`, :func:`options`), the ensemble options of the
noisy runs (:data:`ENSEMBLE`: ``--trajectories``, ``--seed``, ``--workers``, ``--store``,
``--resume``, ``--budget``, taken by ``kbm spectrum``, ``noise``, ``escape`` and
``friction``; ``--fp-budget``, the cost budget of the Fokker-Planck solves of ``noise`` and
``escape``), their checks (:func:`check_ensemble`) and the store of a run
(:func:`stored`).

The shared options of every command (``-p``, ``--vary``, ``--order``, ``--json``,
``--out``, ...) are :data:`kbm.cli._common.OPTIONS`; the values of ``-p`` and ``--vary``
are read by :mod:`numerics.cli.params.values`.
"""

from __future__ import annotations

import argparse
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from typing import Any

from kbm.cli._common import OPTIONS, add_options
from kbm.errors import ParameterError
from numerics.noise.budget import STEP_BUDGET

__all__ = ["ENSEMBLE", "command", "options", "check_ensemble", "stored", "nothing_to_resume"]

#: the options of an ensemble of trajectories: name -> (flags, argparse keywords)
ENSEMBLE: dict[str, tuple[tuple[str, ...], dict[str, Any]]] = {
    "trajectories": (("--trajectories",), dict(type=int, default=None, metavar="N")),
    "seed": (("--seed",), dict(type=int, default=0, metavar="S",
                               help="root seed (numpy SeedSequence, one child per trajectory)")),
    "workers": (("--workers",), dict(
        type=int, default=None, metavar="N",
        help="worker processes (default: all cores; the numbers do not depend on it)")),
    "store": (("--store",), dict(
        metavar="FILE", help="keep every finished chunk of trajectories in the SQLite file "
                             "FILE, so that an interrupted run can be resumed")),
    "resume": (("--resume",), dict(
        action="store_true", help="with --store: continue the run kept in FILE (the same "
                                  "numbers as an uninterrupted run)")),
    "budget": (("--budget",), dict(type=float, default=STEP_BUDGET, metavar="STEPS")),
    # the cost budget of the Fokker-Planck solves of --method fokker-planck (its default is
    # the solve's own, so None here)
    "fp_budget": (("--fp-budget",), dict(type=float, default=None, metavar="COST")),
}


def options(parser: argparse.ArgumentParser, *names: str,
            **changes: Mapping[str, Any]) -> None:
    """Add the shared options ``names`` (of :data:`kbm.cli._common.OPTIONS` and
    :data:`ENSEMBLE`) in that order; ``changes[name]``: the keywords that differ in this
    command (:func:`kbm.cli._common.add_options`)."""
    add_options(parser, *names, table={**OPTIONS, **ENSEMBLE}, **changes)


def command(sub, name: str, description: str, *names: str, models: str | None = None,
            coupled: bool = False, noisy: str | None = None,
            **changes: Mapping[str, Any]) -> argparse.ArgumentParser:
    """The parser of the numerical command ``name`` (its ``kbm --help`` line from
    :data:`numerics.cli.SUMMARIES`) with its first arguments: the model (``models``: which
    it may be, with ``--rhs`` and ``--omega0``, :func:`kbm.cli._common.add_model_arguments`;
    or ``noisy``: a built-in of a command with noise, given as ``-p D=VALUE`` or ``-p
    T=VALUE``, and ``-p``), then the shared options ``names`` (:func:`options`)."""
    from kbm.cli._common import add_command, add_model_arguments
    from numerics.cli import SUMMARIES

    parser = add_command(sub, name, description, SUMMARIES)
    if noisy is not None:
        parser.add_argument("model", help=f"{noisy}; the noise as -p D=VALUE or as the "
                                          "temperature -p T=VALUE (T = kT = D/mu)")
        names = ("param", *names)
    elif models is not None:
        add_model_arguments(parser, models, coupled=coupled, **changes)
    options(parser, *names, **changes)
    return parser


def check_ensemble(args: argparse.Namespace) -> None:
    """Refuse a negative ``--seed``, a ``--workers`` outside 1..1024, a ``--budget`` that
    is negative or NaN (where given; ``--budget nan`` ran with no budget at all) and an
    ``--fp-budget`` that is not a positive finite number.

    Raises
    ------
    kbm.errors.ParameterError
        Naming the option and the value given.
    """
    from numerics.cli.params.values import positive, within

    seed = getattr(args, "seed", None)
    if seed is not None and seed < 0:
        raise ParameterError(f"--seed must be >= 0, got {seed}")
    within(getattr(args, "workers", None), "--workers", 1, 1024)
    budget = getattr(args, "budget", None)
    if budget is not None and not budget >= 0:
        raise ParameterError(f"--budget must be a number of integration steps >= 0, got "
                             f"{budget:g}")
    positive(getattr(args, "fp_budget", None), "--fp-budget")


def nothing_to_resume(path: str | None, resume: bool) -> None:
    """Refuse ``--store PATH --resume`` for a ``PATH`` that does not exist (a fresh run
    started without a word).

    Raises
    ------
    kbm.errors.ParameterError
        ``"PATH does not exist: nothing to resume; drop --resume to start a run"``.
    """
    from pathlib import Path

    if resume and path and not Path(path).exists():
        raise ParameterError(f"{path} does not exist: nothing to resume; drop --resume to "
                             "start a run")


@contextmanager
def stored(args: argparse.Namespace, what: str = "run") -> Iterator[object]:
    """The store of ``--store FILE [--resume]`` (:func:`numerics.cli.params.values.open_store`;
    ``None`` without ``--store``), closed when the run ends."""
    from numerics.cli.params.values import open_store

    path, resume = getattr(args, "store", None), bool(getattr(args, "resume", False))
    nothing_to_resume(path, resume)
    store = open_store(path, resume, what)
    try:
        yield store
    finally:
        if store is not None:
            store.close()
