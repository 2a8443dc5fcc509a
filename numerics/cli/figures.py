"""``kbm figures``: write all figures (the paper's Figs. 2-6 and the KBM comparison)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from kbm.errors import ParameterError
from numerics.cli.params.options import command


def register(sub) -> None:
    p = command(sub, "figures", "Write the paper's Figs. 2-6 and the comparison, branch, "
                "forced-response and friction figures (PNG and PDF) into --out; --list names "
                "them, --only picks some.")
    p.add_argument("--out", default="figures", help="folder (default: figures)")
    p.add_argument("--only", nargs="*", default=None, metavar="NAME",
                   help="figure names (default: all; see --list)")
    p.add_argument("--list", action="store_true", help="list the figure names and exit")
    p.add_argument("--friction-size", type=int, default=None, metavar="N",
                   help="the friction maps on N x N grids (default 8, as kbm reproduce; the "
                        "docs' figures use 32, which takes several minutes on two cores)")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from kbm.output.files import output_folder
    from numerics.paper.figures import FIGURES, write_figures

    if args.list:
        print("\n".join(FIGURES))
        return 0
    from numerics.cli.params.values import within
    from numerics.paper.figures.friction import friction_figures

    within(args.friction_size, "--friction-size", 2, 32)
    if args.only == []:  # wrote nothing and exited 0
        raise ParameterError(f"--only names the figures to write (of {', '.join(FIGURES)}); "
                             "give at least one, or leave out --only for all")
    output_folder(args.out, "--out")  # before any computation
    names = list(FIGURES) if args.only is None else list(args.only)
    import time

    stage = ["", time.perf_counter()]

    def say(name: str) -> None:
        """One line per figure, with the time the previous one took."""
        now = time.perf_counter()
        if stage[0]:
            print(f"  {stage[0]}: {now - stage[1]:.1f} s", file=sys.stderr, flush=True)
        if name:
            print(f"  {name} ...", file=sys.stderr, flush=True)
        stage[:] = [name, now]

    t0 = time.perf_counter()
    paths = write_figures(args.out, [n for n in names if n != "friction"], progress=say)
    if "friction" in names:  # the maps on all cores, with progress bars
        say("friction")
        paths += friction_figures(Path(args.out), size=args.friction_size, progress=True)
    say("")
    print(f"  all figures: {time.perf_counter() - t0:.1f} s", file=sys.stderr, flush=True)
    for p in paths:
        print(p)
    return 0
