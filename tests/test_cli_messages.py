"""Library messages name API arguments; the command line names its flags (issue 15, item 4).

The same missing parameter is reported by the library as ``params={'beta': ...}`` and by
``kbm`` as ``--param beta=...``, in one line with exit status 2.
"""

from __future__ import annotations

import pytest

from kbm.cli import cli_message
from kbm.errors import ParameterError
from numerics import limit_cycle
from numerics.cli import main


def test_library_names_arguments_and_cli_names_flags(capsys):
    with pytest.raises(ParameterError, match=r"params=\{'beta'"):
        limit_cycle("sedf", {"mu": 0.1, "Delta": 1, "lam": 1})
    assert main(["cycle", "sedf", "-p", "mu=0.1", "-p", "Delta=1", "-p", "lam=1"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--param beta=" in err[0] and "params=" not in err[0]


@pytest.mark.parametrize("library,cli", [
    ("needs values for mu (e.g. params={'mu': 0.1})", "(e.g. --param mu=0.1)"),
    ("or give your own F with custom_model", "or give your own F with --rhs EXPR"),
    ("start elsewhere (x_start) to look for a cycle", "start elsewhere (--x-start) to look"),
])
def test_translation_table(library, cli):
    assert cli in cli_message(library)
