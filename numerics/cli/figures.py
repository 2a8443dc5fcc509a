"""``kbm figures``: write all figures (the paper's Figs. 2-6 and the KBM comparison)."""

from __future__ import annotations

import argparse
import sys


def register(sub) -> None:
    p = sub.add_parser("figures", help="write the figures (PNG and PDF)",
                       description="Write the paper's Figs. 2-6 and the comparison, branch, "
                                   "forced-response and friction figures (PNG and PDF) into "
                                   "--out; --list names them, --only picks some.")
    p.add_argument("--out", default="figures", help="folder (default: figures)")
    p.add_argument("--only", nargs="*", default=None, metavar="NAME",
                   help="figure names (default: all; see --list)")
    p.add_argument("--list", action="store_true", help="list the figure names and exit")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from kbm.files import output_folder
    from numerics.paper.figures import FIGURES, write_figures

    if args.list:
        print("\n".join(FIGURES))
        return 0
    output_folder(args.out, "--out")  # before any computation
    paths = write_figures(args.out, args.only,
                          progress=lambda n: print(f"  {n} ...", file=sys.stderr, flush=True))
    for p in paths:
        print(p)
    return 0
