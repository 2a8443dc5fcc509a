"""The ``kbm`` command line: the symbolic commands of :mod:`kbm.cli` and the numerical ones.

This package sits on top of both :mod:`kbm` and :mod:`numerics` (the console
script ``kbm`` is :func:`main`).  Each command module only parses its arguments,
calls one library function and prints; a command module that fails to import
is an error, not a missing command.
"""

from __future__ import annotations

import sys
from collections.abc import Sequence

from kbm.cli import build_parser as _build_symbolic, register_commands, run_command

__all__ = ["main", "build_parser", "COMMANDS"]

#: the numerical sub-command modules, listed after ``derive`` and ``series``
COMMANDS = ("predict", "cycle", "compare", "slide", "figures", "derivations", "reproduce",
            "branch", "friction", "response", "escape", "noise", "lock")


def build_parser():
    """The parser of every ``kbm`` command."""
    return _build_symbolic(lambda sub: register_commands(sub, __name__, COMMANDS))


def main(argv: Sequence[str] | None = None) -> int:
    """Run the ``kbm`` command line; returns the exit status.

    Run as the program (``argv`` None) and interrupted (status 130 or 143), it leaves at
    once after its message: the killed workers' pipes are gone, and the executor's
    threads, stopped by the interpreter's shutdown, would print an ``OSError`` traceback
    under the message.
    """
    status = run_command(build_parser(), argv)
    if argv is None and status in (130, 143):
        import os

        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(status)
    return status


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
