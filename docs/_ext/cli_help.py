"""A directive that renders the ``kbm`` command line's help, one literal block per command.

``.. kbm-cli-help::`` calls :func:`numerics.cli.build_parser` (the console script) and prints each
sub-command's ``format_help()`` (deterministic: argparse output, fixed width).
"""

import os

from docutils import nodes
from docutils.parsers.rst import Directive


class CliHelp(Directive):
    has_content = False

    def run(self):
        os.environ["COLUMNS"] = "90"
        from numerics.cli import build_parser

        parser = build_parser()
        out = []
        sub = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction")
        for name, p in sub.choices.items():
            sec = nodes.section(ids=[f"cli-{name}"])
            sec += nodes.title(text=f"kbm {name}")
            sec += nodes.literal_block(text=p.format_help())
            out.append(sec)
        return out


def setup(app):
    app.add_directive("kbm-cli-help", CliHelp)
    return {"parallel_read_safe": True}
