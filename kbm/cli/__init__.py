"""The symbolic commands of the ``kbm`` command line: ``derive`` and ``series``.

One sub-command per module of this package, each defining ``register(subparsers)``
(which adds its parser and sets ``func``).  The console script ``kbm`` is
:func:`numerics.cli.main`, which adds these commands and the numerical ones on
top of both packages (so that :mod:`kbm` never imports :mod:`numerics`);
:func:`main` here runs the symbolic commands alone.  Errors of the package become
a one-line message on standard error and exit status 2.

A run imports the module of its command only (:func:`lazy_parser`): the other commands
are listed by their one-line summaries (:data:`SUMMARIES`), so ``kbm --help`` and ``kbm
--version`` import neither sympy nor numpy.  :func:`build_parser` imports every command
(the documentation's full help, and the tests).
"""

from __future__ import annotations

import argparse
import importlib
import re
import signal
import sys
from collections.abc import Callable, Mapping, Sequence

from kbm.errors import KBMError

__all__ = ["main", "build_parser", "lazy_parser", "register_commands", "run_command",
           "cli_message", "COMMANDS", "SUMMARIES"]

#: the symbolic sub-command modules, in the order ``kbm --help`` lists them
COMMANDS = ("derive", "series")

#: each command's one line in ``kbm --help`` (the ``help`` its module registers; a test
#: checks they are equal), so that the help imports no command module
SUMMARIES = {
    "derive": "KBM expansion A_n, B_n, u_n to a given order",
    "series": "mu-series of the limit cycle (polynomial F)",
}

DESCRIPTION = "Krylov-Bogoliubov-Mitropolsky averaging to any order, checked numerically."


def register_commands(sub, package: str, names: Sequence[str]) -> None:
    """Import ``package.NAME`` for each name and let it register its parser.

    A command module that fails to import is an error (raised), never a silent skip.
    """
    for name in names:
        importlib.import_module(f"{package}.{name}").register(sub)


def _version() -> str:
    """The installed distribution's version, or ``(not installed)``.

    Read from the first ``kbm-*.dist-info/METADATA`` on ``sys.path``, the one
    :func:`importlib.metadata.version` finds, without that module's imports (email
    parsing: a third of ``kbm --version``'s time).
    """
    import os

    for entry in sys.path:
        try:
            names = sorted(os.listdir(entry or "."))
        except OSError:
            continue
        for name in names:
            if name.startswith("kbm-") and name.endswith(".dist-info"):
                try:
                    with open(os.path.join(entry or ".", name, "METADATA"),
                              encoding="utf-8") as fh:
                        for line in fh:
                            if line.startswith("Version:"):
                                return line.split(":", 1)[1].strip()
                            if not line.strip():
                                break
                except OSError:
                    continue
    return "(not installed)"


class _VersionAction(argparse.Action):
    """``--version``: the version is read (package metadata) only when asked for."""

    def __init__(self, option_strings, dest=argparse.SUPPRESS, default=argparse.SUPPRESS,
                 help="show program's version number and exit"):
        super().__init__(option_strings=option_strings, dest=dest, default=default, nargs=0,
                         help=help)

    def __call__(self, parser, namespace, values, option_string=None):
        parser._print_message(f"kbm {_version()}\n", sys.stdout)
        parser.exit()


def _top_parser() -> tuple[argparse.ArgumentParser, object]:
    """The ``kbm`` parser without commands, and its sub-parsers' action."""
    parser = argparse.ArgumentParser(prog="kbm", description=DESCRIPTION)
    parser.add_argument("--version", action=_VersionAction)
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    return parser, sub


def build_parser(extra: Callable[[object], None] | None = None) -> argparse.ArgumentParser:
    """The argument parser with the symbolic commands (and those ``extra(sub)`` adds)."""
    parser, sub = _top_parser()
    register_commands(sub, __name__, COMMANDS)
    if extra is not None:
        extra(sub)
    return parser


def command_name(argv: Sequence[str]) -> str | None:
    """The command ``argv`` names: its first word that is not an option (``kbm`` itself
    takes only ``--help`` and ``--version``, neither with a value)."""
    for item in argv:
        if item == "--":
            return None
        if not item.startswith("-"):
            return item
    return None


def lazy_parser(argv: Sequence[str], commands: Mapping[str, tuple[str, str]]
                ) -> argparse.ArgumentParser:
    """The parser of the command that ``argv`` names, importing that command's module only.

    ``commands`` maps each command, in the order of ``kbm --help``, to ``(package,
    summary)``: the named command is registered by ``package.NAME.register``, every other
    one by its summary alone (``kbm --help`` lists them all; a command name that is not one
    of them is argparse's usual error).
    """
    name = command_name(argv)
    parser, sub = _top_parser()
    for cmd, (package, summary) in commands.items():
        if cmd == name:
            importlib.import_module(f"{package}.{cmd}").register(sub)
        else:
            sub.add_parser(cmd, help=summary, add_help=False)
    return parser


def symbolic_commands() -> dict[str, tuple[str, str]]:
    """The symbolic commands for :func:`lazy_parser`: name -> (package, summary)."""
    return {name: (__name__, SUMMARIES[name]) for name in COMMANDS}


#: options whose value is an expression that may start with a minus sign (``--rhs -x**3``)
EXPRESSION_OPTIONS = ("--rhs", "--potential", "--omega0", "--root")


#: a value that starts with a minus sign and a number (no option of kbm does): ``-0.1``,
#: ``-1e-3``, ``-inf``, and lists and ranges ``-0.1,0.05,0.1``, ``-1:2``
_NEGATIVE_VALUE = re.compile(r"-(?:\.?\d|inf\b|nan\b)", re.IGNORECASE)


def _join_negative_values(argv: Sequence[str]) -> list[str]:
    """``["--rhs", "-x**3"]`` -> ``["--rhs=-x**3"]``: argparse would read ``-x**3`` as an option.

    The same for any option followed by a value that starts with a minus sign and a number
    (``--convergence -0.1,0.05,0.1``, ``--detuning -1e-3``): argparse takes ``-0.1`` and
    ``-.5`` for values but ``-0.1,0.05`` or ``-1e-3`` for an unknown option ("expected one
    argument").  The option then checks the value in its own terms.
    """
    out: list[str] = []
    items = list(argv)
    i = 0
    while i < len(items):
        if i + 1 < len(items) and items[i].startswith("-") and items[i] != "--" \
                and "=" not in items[i] and _NEGATIVE_VALUE.match(items[i + 1]):
            out.append(f"{items[i]}={items[i + 1]}")
            i += 2
        elif (items[i] in EXPRESSION_OPTIONS and i + 1 < len(items)
                and items[i + 1].startswith("-") and not items[i + 1].startswith("--")):
            out.append(f"{items[i]}={items[i + 1]}")
            i += 2
        else:
            out.append(items[i])
            i += 1
    return out


#: library wording -> command-line wording in error messages (the library names its
#: arguments, the command line its flags)
_TRANSLATIONS = tuple((re.compile(pattern), repl) for pattern, repl in (
    (r"(?:params|values)=\{([^}]+)\}",
     lambda m: " ".join(f"--param {k}={v.strip()}" for k, v in
                        re.findall(r"'(\w+)':\s*([^,]+)", m.group(1)))),
    (r"np\.float64\(([^()]*)\)", r"\1"),
    (r"\s*\(resume=True\)", ""),
    (r"make it an axis \(axes=\{'v': \[\.\.\.\]\}\) or fix it",
     "give --vary v=... (or -p v=VALUE)"),
    (r"give at least one axis, e\.g\. axes=\{'v': \[0\.01, 0\.1\]\}",
     "give at least one --vary, e.g. --vary v=0.01,0.1"),
    (r"raise max_wells or max_periods|raise mu, v or max_wells/max_periods",
     "raise mu or v (a run stops after 3000 stage periods lam/v or 30000 natural periods)"),
    (r"\bgive nu0 \(", "give --nu0 NU0 ("),
    (r"\bdeclare it: internal=\['([^']*)'\]", r"declare it: --internal \1"),
    (r"\b(?:the )?internal resonance '([^']*)'", r"--internal \1"),
    (r"^the resonance '([^']*)' names the forcing", r"--internal \1 names the forcing"),
    (r"\bdeclare it: resonance='([^']*)'", r"declare it: --resonance \1"),
    (r"\bcustom_model\b", "--rhs EXPR"),
    (r"\(x_start\)", "(--x-start)"),
    (r"\(potential=\.\.\.\)", "(--potential EXPR)"),
    (r"\bleave potential=None\b", "leave out --potential"),
    (r"\bpass its antiderivative as `potential`",
     "give its antiderivative as --potential EXPR"),
    (r"a confining `potential`", "a confining --potential EXPR"),
    (r"`potential`|\bpotential=(?=\s)", "--potential"),
    (r" in params\b", ""),
    (r"\bchoose one with root=", "choose one with --root A0"),
    (r"\buse averaged_cycles for them",
     "use kbm predict --method kbm for them"),
    (r"\b(lower|raise) rtol\b", r"\1 --rtol"),
    (r"^rtol must", "--rtol must"),
    (r"^trajectories = (\d+):", r"--trajectories \1:"),
    (r"^the seed must", "--seed must"),
    (r"^the a-range\b", "--a-range"),
    (r"^--a-range needs a_min < a_max", "--a-range needs AMIN < AMAX"),
    (r"^(?:the )?(?:series )?order must be", "--order must be"),
    (r"^order (\d+) is above the limit (.*); ask for order <=",
     r"--order \1 is above the limit \2; ask for --order <="),
    (r"^nu must be", "--nu must be"),
    (r"^tol must be", "--tol must be"),
    (r"^friction setting slips must", "--slips must"),
    (r"^a convergence study needs values", "--convergence needs values"),
    (r"^the resonance p/q must", "--resonance p/q must"),
    (r"\bt_end = ", "--t-end "),
    (r"\bt_end\b", "--t-end"),
    (r"\bmethod='(\w+)'", r"--method \1"),
    (r"^digits must", "--digits must"),
    (r"use numeric_cycle_series for", "use --float for"),
    (r"with digits \(pure-Python mpmath\)", "with --digits (pure-Python mpmath)"),
))


def cli_message(message: str) -> str:
    """An error message of the library in the command line's words, on one line."""
    msg = " ".join(str(message).split())
    for pattern, repl in _TRANSLATIONS:
        msg = pattern.sub(repl, msg)
    return msg


def _check_out(args: argparse.Namespace) -> None:
    """An unwritable ``--out DIR`` refused before the command computes anything (it failed
    after the computation: minutes of a diagram, a whole spectrum)."""
    out = getattr(args, "out", None)
    if isinstance(out, str) and out:
        from ..output.files import check_folder

        check_folder(out, "--out")


def run_command(parser: argparse.ArgumentParser | Callable[[list[str]], argparse.ArgumentParser],
                argv: Sequence[str] | None = None) -> int:
    """Parse ``argv`` and run the command; returns the exit status.

    ``parser`` is the parser, or a function of the arguments that builds it
    (:func:`lazy_parser`).
    """
    argv = _join_negative_values(sys.argv[1:] if argv is None else argv)
    if not isinstance(parser, argparse.ArgumentParser):
        parser = parser(argv)
    args, extra = parser.parse_known_args(argv)
    if extra:
        _command_parser(parser, getattr(args, "command", None)).error(
            f"unrecognized arguments: {' '.join(extra)}")
    received: list[int] = []
    previous = _on_sigterm(received)
    try:
        _check_out(args)
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


def _command_parser(parser: argparse.ArgumentParser,
                    name: str | None) -> argparse.ArgumentParser:
    """The parser of the command ``name`` (``parser`` itself if there is none), so that an
    option the command does not take is refused with the command's usage and ``kbm NAME:
    error: unrecognized arguments: ...`` (argparse refuses it with the top-level usage,
    ``usage: kbm [-h] [--version] COMMAND ...``, which lists no option of the command)."""
    for action in parser._actions:  # the sub-parsers' action (argparse has no public getter)
        choices = getattr(action, "choices", None)
        if isinstance(action, argparse._SubParsersAction) and name in choices:
            return choices[name]
    return parser


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
    return run_command(lambda items: lazy_parser(items, symbolic_commands()), argv)

