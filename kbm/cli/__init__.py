"""The ``kbm`` command line.

One sub-command per module of this package, each defining ``register(subparsers)``
(which adds its parser and sets ``func``).  Errors of the package become a
one-line message on standard error and exit status 2; the symbolic core is
imported by every command, :mod:`numerics` only by the commands that integrate.
"""

from __future__ import annotations

import argparse
import importlib
import sys
from collections.abc import Sequence

from ..errors import KBMError

__all__ = ["main", "build_parser"]

#: sub-command modules, in the order ``kbm --help`` lists them
COMMANDS = ("derive", "series", "cycle", "compare", "slide", "figures", "derivations", "reproduce")


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with every available sub-command."""
    parser = argparse.ArgumentParser(
        prog="kbm",
        description="Krylov-Bogoliubov-Mitropolsky averaging to any order, checked numerically.")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    for name in COMMANDS:
        try:
            module = importlib.import_module(f"{__name__}.{name}")
        except ModuleNotFoundError as exc:
            if exc.name == f"{__name__}.{name}":
                continue  # that command is not part of this build
            raise
        module.register(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        status = args.func(args)
    except KBMError as exc:
        msg = " ".join(str(exc).split())
        print(f"kbm {args.command}: error: {msg}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"kbm {args.command}: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # output piped into e.g. `head`: stop quietly
        import os

        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    return int(status or 0)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
