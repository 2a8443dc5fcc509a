"""The ``kbm`` command line: the symbolic commands of :mod:`kbm.cli` and the numerical ones.

This package sits on top of both :mod:`kbm` and :mod:`numerics` (the console
script ``kbm`` is :func:`main`).  Each command module only parses its arguments,
calls one library function and prints; a command module that fails to import
is an error, not a missing command.  A run imports its own command's module only
(:func:`kbm.cli.lazy_parser`; the others are listed by :data:`SUMMARIES`).
"""

from __future__ import annotations

import sys
from collections.abc import Sequence

from kbm.cli import (build_parser as _build_symbolic, lazy_parser, register_commands,
                     run_command, symbolic_commands)

__all__ = ["main", "build_parser", "COMMANDS", "SUMMARIES"]

#: the numerical sub-command modules, listed after ``derive`` and ``series``
COMMANDS = ("predict", "cycle", "compare", "slide", "figures", "derivations", "reproduce",
            "branch", "friction", "response", "escape", "noise", "lock", "spectrum", "diagram")

#: each command's line in ``kbm --help`` (the ``help`` its module registers; a test checks
#: they are equal), so that the help and the version import no command module
SUMMARIES = {
    "predict": "limit cycles predicted by averaging (energy balance or KBM)",
    "cycle": "limit cycle of the full equation by shooting",
    "compare": "KBM predictions (any order) against the numerical limit cycle",
    "slide": "driven stick-slip simulation (SEDF or CDC)",
    "figures": "write the figures (PNG and PDF)",
    "derivations": "regenerate the LaTeX derivations (byte-stable)",
    "reproduce": "the main job: derivations, tables, figures, summary",
    "branch": "branches of limit cycles in one parameter (folds, Hopf, homoclinic)",
    "friction": "friction laws and maps of the pulled sliders (SEDF, CDC)",
    "response": "frequency-response curve of a forced oscillator (KBM near a resonance, "
                "checked by shooting)",
    "escape": "escape rate from the well at the origin with noise sqrt(2 D) xi",
    "noise": "stationary state with noise sqrt(2 D) xi: averaged against simulated",
    "lock": "locking region of coupled oscillators: averaged vs true",
    "spectrum": "spectrum of a noisy oscillator: linewidth, response spectra, phase slips "
                "(averaged vs simulated)",
    "diagram": "bifurcation diagram in two parameters: curves, codim-2 points, averaged vs "
               "true",
}


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
    commands = {**symbolic_commands(), **{name: (__name__, SUMMARIES[name]) for name in COMMANDS}}
    status = run_command(lambda items: lazy_parser(items, commands), argv)
    if argv is None and status in (130, 143):
        import os

        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(status)
    return status

