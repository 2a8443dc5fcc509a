"""Helpers shared by the sub-commands: ``--param`` parsing and JSON output."""

from __future__ import annotations

import argparse
import json
import sys
from typing import Any

from ..errors import ParameterError

__all__ = ["add_param_option", "parse_params", "emit_json", "add_model_arguments", "model_spec"]


def add_param_option(parser: argparse.ArgumentParser) -> None:
    """Add the repeatable ``--param name=value`` option."""
    parser.add_argument("--param", "-p", action="append", default=[], metavar="NAME=VALUE",
                        help="set a parameter (repeatable), e.g. --param beta=1 --param mu=0.1")


def parse_params(items: list[str]) -> dict[str, str]:
    """``["beta=1", "mu=0.1"]`` -> ``{"beta": "1", "mu": "0.1"}`` (values stay strings, read exactly)."""
    out: dict[str, str] = {}
    for item in items:
        name, sep, value = item.partition("=")
        name, value = name.strip(), value.strip()
        if not sep or not name or not value:
            raise ParameterError(f"--param takes NAME=VALUE, got {item!r}")
        if name in out:
            raise ParameterError(f"parameter {name!r} is given twice")
        out[name] = value
    return out


def emit_json(obj: Any) -> None:
    """Print ``obj`` as JSON (keys in a fixed order, as built)."""
    json.dump(obj, sys.stdout, indent=2, allow_nan=True)
    sys.stdout.write("\n")


def add_model_arguments(parser: argparse.ArgumentParser,
                        models: str = "vdp, rayleigh, sedf, cdc, ...") -> None:
    """Add the model name, ``--rhs`` and ``--omega0`` arguments."""
    parser.add_argument("model", nargs="?", help=f"built-in model ({models})")
    parser.add_argument("--rhs", metavar="EXPR", help="your own F (in x, xdot and parameters) "
                        "instead of a built-in model")
    parser.add_argument("--omega0", default="1", help="linear frequency for --rhs (default 1)")


def model_spec(args: argparse.Namespace):
    """The model named on the command line (a built-in name) or the user's ``--rhs`` model.

    Raises
    ------
    kbm.errors.ModelError
        If neither or both are given.
    """
    from ..errors import ModelError
    from ..models import custom_model

    if args.model and getattr(args, "rhs", None):
        raise ModelError("give either a model name or --rhs, not both")
    if getattr(args, "rhs", None):
        return custom_model(args.rhs, omega0=args.omega0 if args.omega0 else 1)
    if not args.model:
        raise ModelError("name a model (e.g. vdp) or give --rhs EXPR")
    return args.model
