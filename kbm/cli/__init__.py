"""The symbolic commands of the ``kbm`` command line: ``derive`` and ``series``.

One sub-command per module of this package, each defining ``register(subparsers)``
(which adds its parser and sets ``func``).  The console script ``kbm`` is
:func:`numerics.cli.main`, which adds these commands and the numerical ones on
top of both packages (so that :mod:`kbm` never imports :mod:`numerics`);
:func:`main` here runs the symbolic commands alone.  Errors of the package become
a one-line message on standard error and exit status 2.
"""

from __future__ import annotations

import argparse
import importlib
import re
import signal
import sys
from collections.abc import Callable, Sequence

from kbm.errors import KBMError

__all__ = ["main", "build_parser", "register_commands", "run_command", "cli_message", "COMMANDS"]

#: the symbolic sub-command modules, in the order ``kbm --help`` lists them
COMMANDS = ("derive", "series")

DESCRIPTION = "Krylov-Bogoliubov-Mitropolsky averaging to any order, checked numerically."


def register_commands(sub, package: str, names: Sequence[str]) -> None:
    """Import ``package.NAME`` for each name and let it register its parser.

    A command module that fails to import is an error (raised), never a silent skip.
    """
    for name in names:
        importlib.import_module(f"{package}.{name}").register(sub)


def _version() -> str:
    """The installed distribution's version (package metadata), or that of the source tree."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("kbm")
    except PackageNotFoundError:
        return "(not installed)"


def build_parser(extra: Callable[[object], None] | None = None) -> argparse.ArgumentParser:
    """The argument parser with the symbolic commands (and those ``extra(sub)`` adds)."""
    parser = argparse.ArgumentParser(prog="kbm", description=DESCRIPTION)
    parser.add_argument("--version", action="version", version=f"kbm {_version()}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    register_commands(sub, __name__, COMMANDS)
    if extra is not None:
        extra(sub)
    return parser


#: options whose value is an expression that may start with a minus sign (``--rhs -x**3``)
EXPRESSION_OPTIONS = ("--rhs", "--potential", "--omega0", "--root")


def _join_negative_values(argv: Sequence[str]) -> list[str]:
    """``["--rhs", "-x**3"]`` -> ``["--rhs=-x**3"]``: argparse would read ``-x**3`` as an option."""
    out: list[str] = []
    items = list(argv)
    i = 0
    while i < len(items):
        if (items[i] in EXPRESSION_OPTIONS and i + 1 < len(items)
                and items[i + 1].startswith("-") and not items[i + 1].startswith("--")):
            out.append(f"{items[i]}={items[i + 1]}")
            i += 2
        else:
            out.append(items[i])
            i += 1
    return out


#: library wording -> command-line wording in error messages (the library names its
#: arguments, the command line its flags)
_TRANSLATIONS = (
    (re.compile(r"(?:params|values)=\{([^}]+)\}"),
     lambda m: " ".join(f"--param {k}={v.strip()}" for k, v in
                        re.findall(r"'(\w+)':\s*([^,]+)", m.group(1)))),
    (re.compile(r"np\.float64\(([^()]*)\)"), r"\1"),
    (re.compile(r"\s*\(resume=True\)"), ""),
    (re.compile(r"make it an axis \(axes=\{'v': \[\.\.\.\]\}\) or fix it"),
     "give --vary v=... (or -p v=VALUE)"),
    (re.compile(r"give at least one axis, e\.g\. axes=\{'v': \[0\.01, 0\.1\]\}"),
     "give at least one --vary, e.g. --vary v=0.01,0.1"),
    (re.compile(r"raise max_wells or max_periods|raise mu, v or max_wells/max_periods"),
     "raise mu or v (a run stops after 3000 stage periods lam/v or 30000 natural periods)"),
    (re.compile(r"\bgive nu0 \("), "give --nu0 NU0 ("),
    (re.compile(r"\bcustom_model\b"), "--rhs EXPR"),
    (re.compile(r"\(x_start\)"), "(--x-start)"),
    (re.compile(r"\bpotential=(\.\.\.)?"), "--potential "),
    (re.compile(r"\bmethod='(\w+)'"), r"--method \1"),
    (re.compile(r"^digits must"), "--digits must"),
    (re.compile(r"use numeric_cycle_series for"), "use --float for"),
    (re.compile(r"with digits \(pure-Python mpmath\)"), "with --digits (pure-Python mpmath)"),
)


def cli_message(message: str) -> str:
    """An error message of the library in the command line's words, on one line."""
    msg = " ".join(str(message).split())
    for pattern, repl in _TRANSLATIONS:
        msg = pattern.sub(repl, msg)
    return msg


def run_command(parser: argparse.ArgumentParser, argv: Sequence[str] | None = None) -> int:
    """Parse ``argv`` and run the command; returns the exit status."""
    args = parser.parse_args(_join_negative_values(sys.argv[1:] if argv is None else argv))
    received: list[int] = []
    previous = _on_sigterm(received)
    try:
        status = args.func(args)
    except KBMError as exc:
        print(f"kbm {args.command}: error: {cli_message(exc)}", file=sys.stderr)
        return 2
    except (KeyboardInterrupt, SystemError) as exc:  # Ctrl-C, or SIGTERM (turned into this)
        # inside compiled code (numba) the interruption surfaces as a SystemError ("returned
        # a result with an exception set") whose context is the KeyboardInterrupt
        stop = _interruption(exc)
        if stop is None:
            raise
        how = "SIGTERM" if received else "Ctrl-C"
        detail = f": {stop}" if str(stop) else ""
        print(f"kbm {args.command}: interrupted ({how}){detail}", file=sys.stderr)
        return 143 if received else 130
    except BrokenPipeError:  # output piped into e.g. `head`: stop quietly
        import os

        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    except OSError as exc:  # a file the command reads or writes: the reason, no traceback
        where = f" {exc.filename!r}" if exc.filename else ""
        print(f"kbm {args.command}: error: cannot access{where}: {exc.strerror or exc}",
              file=sys.stderr)
        return 2
    finally:
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)
    return int(status or 0)


def _interruption(exc: BaseException) -> KeyboardInterrupt | None:
    """The KeyboardInterrupt ``exc`` is, or that caused it (through ``__context__`` or
    ``__cause__``), else ``None``."""
    seen = set()
    while exc is not None and id(exc) not in seen:
        if isinstance(exc, KeyboardInterrupt):
            return exc
        seen.add(id(exc))
        exc = exc.__cause__ or exc.__context__
    return None


def _on_sigterm(received: list[int]):
    """Let SIGTERM stop a command as Ctrl-C does (the local pool's workers are killed and
    the finished points counted); returns the previous handler, or ``None`` outside the
    main thread (where signals cannot be handled)."""
    import threading

    if threading.current_thread() is not threading.main_thread():
        return None

    def handler(signum, frame):
        received.append(signum)
        raise KeyboardInterrupt

    return signal.signal(signal.SIGTERM, handler)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the symbolic commands; returns the exit status."""
    return run_command(build_parser(), argv)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
