"""``kbm derivations``: regenerate the LaTeX files of ``derivations/``."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from numerics.cli.params.options import command


def register(sub) -> None:
    p = command(sub, "derivations", "Write the engine's derivations (sedf, cdc, van der Pol, "
                "Duffing, limit-cycle series, errata table) as LaTeX.")
    p.add_argument("--out", default="derivations", help="folder (default: derivations)")
    p.add_argument("--no-evidence", action="store_true",
                   help="leave out the errata table (it needs numerical limit cycles)")
    p.add_argument("--pdf", action="store_true", help="also run pdflatex on main.tex")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from kbm.output.derivations import write_derivations
    from kbm.output.files import output_folder
    from numerics.paper import errata_rows

    output_folder(args.out, "--out")  # before any computation

    rows = () if args.no_evidence else errata_rows()
    paths = write_derivations(args.out, rows)
    for p in paths:
        print(p)
    if args.pdf:
        from kbm.output.derivations import compile_pdf

        pdf = compile_pdf(Path(args.out) / "main.tex")
        print(pdf)
    sys.stdout.flush()
    return 0
