"""Helpers shared by the sub-commands: ``--param`` parsing and JSON output."""

from __future__ import annotations

import argparse
import json
import sys
from typing import Any

from ..errors import ParameterError

__all__ = ["add_param_option", "parse_params", "emit_json"]


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
