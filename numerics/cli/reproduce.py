"""``kbm reproduce``: the main job (:func:`numerics.paper.reproduce.reproduce`)."""

from __future__ import annotations

import argparse

from numerics.cli.params.options import command


def register(sub) -> None:
    p = command(sub, "reproduce", "Regenerate the derivations, compare KBM with the true limit "
                "cycles for the paper's and small-parameter cases, run the paper's sliding "
                "experiments, write all figures.")
    p.add_argument("--out", default="out", help="output folder (default: out)")
    p.add_argument("--no-pdf", action="store_true", help="do not run pdflatex")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from kbm.output.files import output_folder
    from numerics.paper.reproduce import reproduce

    output_folder(args.out, "--out")  # before any computation
    reproduce(args.out, pdf=not args.no_pdf)
    return 0
