"""``kbm derivations``: regenerate the LaTeX files of ``derivations/``."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path


def register(sub) -> None:
    p = sub.add_parser("derivations", help="regenerate the LaTeX derivations (byte-stable)",
                       description="Write the engine's derivations (sedf, cdc, van der Pol, "
                                   "Duffing, limit-cycle series, errata table) as LaTeX.")
    p.add_argument("--out", default="derivations", help="folder (default: derivations)")
    p.add_argument("--no-evidence", action="store_true",
                   help="leave out the errata table (it needs numerical limit cycles)")
    p.add_argument("--pdf", action="store_true", help="also run pdflatex on main.tex")
    p.set_defaults(func=run)


def errata_rows():
    """The errata of :data:`kbm.paper.ERRATA` with numerical evidence from :mod:`numerics`."""
    from numerics.errata import errata_evidence

    from ..derivations import ErratumRow
    from ..paper import ERRATA

    evidence = errata_evidence()
    rows = []
    for e in ERRATA:
        eq = {"6": ("6",), "7": ("7",), "8": ("8",), "9": ("9", "10")}[e.equation]
        ev = tuple((r.equation, r.case, r.quantity, r.printed, r.corrected, r.numeric)
                   for r in evidence if r.equation in eq)
        rows.append(ErratumRow(e.equation, e.quantity, e.printed, e.difference, ev))
    return rows


def run(args: argparse.Namespace) -> int:
    from ..derivations import write_derivations

    rows = () if args.no_evidence else errata_rows()
    paths = write_derivations(args.out, rows)
    for p in paths:
        print(p)
    if args.pdf:
        from ..derivations import compile_pdf

        pdf = compile_pdf(Path(args.out) / "main.tex")
        print(pdf)
    sys.stdout.flush()
    return 0
