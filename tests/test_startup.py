"""Start-up of the ``kbm`` command line (issue 39): a run imports the module of its own
command only, ``kbm --help`` and ``kbm --version`` import nothing heavy, and the help that
lists the commands without importing them says what their modules register."""

from __future__ import annotations

import argparse
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
HEAVY = ("sympy", "numpy", "scipy", "numba", "matplotlib", "mpmath")


def _imported_by(args: list[str]) -> set[str]:
    """The heavy top-level modules imported by ``kbm ARGS`` in a fresh interpreter."""
    code = ("import sys, runpy; sys.argv = ['kbm', *sys.argv[1:]]\n"
            "try:\n    runpy.run_module('numerics.cli', run_name='__main__')\n"
            "except SystemExit:\n    pass\n"
            f"print('MODULES', ' '.join(m for m in {HEAVY!r} if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code, *args], capture_output=True, text=True,
                         timeout=120, cwd=ROOT, check=True).stdout
    line = next(x for x in out.splitlines() if x.startswith("MODULES"))
    return set(line.split()[1:])


@pytest.mark.parametrize("args", [["--version"], ["--help"], []])
def test_version_and_help_import_nothing_heavy(args):
    assert _imported_by(args) == set()


def test_a_command_imports_what_it_uses():
    """``kbm cycle --help`` builds the parser of ``cycle`` alone: not ``derive``'s (numpy at
    import, the model registry's names in its help) nor ``series``'s (sympy at import)."""
    assert _imported_by(["cycle", "--help"]) == set()


@pytest.mark.parametrize("command", ["noise", "escape"])
def test_fp_budget_default_in_help_imports_no_solver(command):
    """The help of ``--fp-budget`` prints the Fokker-Planck solves' default budgets, which
    sit in :mod:`numerics.noise.budget`: ``kbm noise --help`` had imported
    ``numerics.thermal`` for it (numpy, scipy and sympy, about 1 s)."""
    assert _imported_by([command, "--help"]) == set()


def _registered_help() -> dict[str, str]:
    from numerics.cli import build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return {a.dest: a.help for a in sub._choices_actions}


def test_summaries_are_what_the_command_modules_register():
    """The one-line summaries of ``kbm --help`` (kept in a table so that the help imports
    no command module) equal the ``help`` each module registers, in the same order."""
    from kbm.cli import SUMMARIES as SYMBOLIC
    from numerics.cli import SUMMARIES as NUMERIC

    assert {**SYMBOLIC, **NUMERIC} == _registered_help()
    assert list({**SYMBOLIC, **NUMERIC}) == list(_registered_help())


def test_lazy_help_equals_the_full_parsers_help():
    """``kbm --help`` built lazily prints the bytes of the parser with every command."""
    from numerics.cli import build_parser

    full = build_parser().format_help()
    proc = subprocess.run([sys.executable, "-m", "numerics.cli", "--help"], capture_output=True,
                          text=True, timeout=120, cwd=ROOT, check=True)
    assert proc.stdout == full


def test_version_is_the_distributions():
    """``kbm --version`` (read from the dist-info without importlib.metadata) agrees with
    :func:`importlib.metadata.version`."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        expected = version("kbm")
    except PackageNotFoundError:
        expected = "(not installed)"
    proc = subprocess.run([sys.executable, "-m", "numerics.cli", "--version"],
                          capture_output=True, text=True, timeout=120, cwd=ROOT, check=True)
    assert proc.stdout == f"kbm {expected}\n"


def test_unknown_command_is_argparses_error():
    proc = subprocess.run([sys.executable, "-m", "numerics.cli", "cycel"], capture_output=True,
                          text=True, timeout=120, cwd=ROOT)
    assert proc.returncode == 2
    assert "invalid choice: 'cycel'" in proc.stderr


#: a script's preamble that reaches the package only through an import hook placed after
#: Python's path finder (as setuptools' editable installs by a finder do), whatever the
#: environment's own install: the layout in which a bare folder 'kbm' shadows the package
_HOOK = '''\
import importlib.abc, importlib.util, os, sys
ROOT = {root!r}
sys.path[:] = [p for p in sys.path
               if not os.path.isfile(os.path.join(p or ".", "kbm", "__init__.py"))]
sys.meta_path[:] = [f for f in sys.meta_path
                    if not str(getattr(f, "__module__", "")).startswith("__editable__")]
class Hook(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path=None, target=None):
        if name in ("kbm", "numerics"):
            return importlib.util.spec_from_file_location(
                name, os.path.join(ROOT, name, "__init__.py"),
                submodule_search_locations=[os.path.join(ROOT, name)])
        return None
sys.meta_path.append(Hook())
'''


def _clone_beside(tmp_path: Path, code: str, **env: str) -> subprocess.CompletedProcess:
    """``python ../snippet.py`` run from ``tmp/notebooks``, the script saved next to a clone
    named ``tmp/kbm`` (issue 40 item 3)."""
    (tmp_path / "kbm" / "kbm").mkdir(parents=True)
    (tmp_path / "notebooks").mkdir()
    (tmp_path / "snippet.py").write_text(code)
    env = {"PATH": "/usr/bin:/bin", "HOME": str(tmp_path), **env}
    return subprocess.run([sys.executable, "../snippet.py"], cwd=tmp_path / "notebooks",
                          capture_output=True, text=True, timeout=120, env=env)


def test_the_shadow_message_names_the_scripts_folder(tmp_path):
    """With the package behind an import hook, the clone's folder next to the script is
    taken for ``kbm``: the message names the script's folder (``sys.path[0]``), not the
    current folder, and the way out."""
    proc = _clone_beside(tmp_path, _HOOK.format(root=str(ROOT)) + "import numerics\n")
    assert proc.returncode == 1
    last = proc.stderr.strip().splitlines()[-1]
    assert "the folder of the script '../snippet.py'" in last, last
    assert f"({tmp_path}, Python's first import folder) holds a folder named 'kbm'" in last
    assert "current folder" not in last
    assert "python -m pip install -e CLONE" in last


def test_a_script_next_to_the_clone_finds_the_package(tmp_path):
    """With the clone on ``sys.path`` (the static ``.pth`` line that ``pip install -e .``
    writes with ``package-dir = {"" = "."}``; here ``PYTHONPATH``, the same kind of entry,
    after the script's folder), the regular package wins over the bare folder: the script
    runs."""
    code = "import numerics, kbm\nprint(kbm.__file__)\nprint(kbm.get_model('vdp').name)\n"
    proc = _clone_beside(tmp_path, code, PYTHONPATH=str(ROOT))
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.splitlines() == [str(ROOT / "kbm" / "__init__.py"), "vdp"]


def test_a_folder_named_kbm_in_the_current_folder_is_named_as_the_cause(tmp_path):
    """Issue 24 item 4 (moved from test_new_user.py): from the folder that holds a clone
    named ``kbm``, with the package behind an import hook, ``import kbm`` finds that folder
    as a namespace package; ``import numerics`` says so, naming the current folder."""
    (tmp_path / "kbm" / "kbm").mkdir(parents=True)
    code = _HOOK.format(root=str(ROOT)) + "import kbm, numerics\n"
    proc = subprocess.run([sys.executable, "-c", code], cwd=tmp_path,
                          capture_output=True, text=True, timeout=120,
                          env={"PATH": "/usr/bin:/bin", "HOME": str(tmp_path)})
    assert proc.returncode == 1
    last = proc.stderr.strip().splitlines()[-1]
    assert "holds a folder named 'kbm'" in last
    assert f"Python's current folder ({tmp_path})" in last
