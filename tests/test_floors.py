"""The layering of the two packages, as tests (the architecture review's rules, issue 15).

- :mod:`kbm` (engine and its symbolic commands) never imports :mod:`numerics`;
- inside :mod:`numerics` a module imports only its own floor and the floors below:
  base (``errors``, ``_memo``, ``_show``, ``_plot``, ``executor``, ``store``) < ``flow`` < ``shooting`` < ``noise`` < ``energy`` < ``cycles`` <
  ``locking`` < ``comparison`` < ``sliding`` < ``fokker_planck`` < ``escape`` < ``thermal`` <
  ``spectrum`` < ``bifurcation`` < ``paper`` < ``cli``;
- only the command line (``numerics.cli``) imports ``kbm.cli``;
- ``kbm --help`` lists every command, and a command module that fails to import is an
  error, not a missing command.

The imports are read from the source (``ast``), so function-local imports count too.
"""

from __future__ import annotations

import ast
import functools
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

#: the floors of numerics, bottom up (a module's floor is its first package component)
FLOORS = ("base", "flow", "shooting", "noise", "energy", "cycles", "locking", "comparison", "sliding",
          "fokker_planck", "escape", "thermal", "spectrum", "bifurcation", "paper",
          "cli")
BASE = {"errors", "_memo", "_show", "_plot", "executor", "store", "__init__"}


@functools.lru_cache(maxsize=None)
def _imports(path: Path) -> frozenset[str]:
    """Absolute module names imported by a file (relative imports resolved); each file is
    parsed once for all the tests here (the parse is most of their time)."""
    tree = ast.parse(path.read_text(), filename=str(path))
    pkg = ".".join(path.relative_to(ROOT).with_suffix("").parts[:-1])
    out: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = pkg.split(".")
                base = base[:len(base) - node.level + 1]
                mod = ".".join(base + ([node.module] if node.module else []))
            else:
                mod = node.module or ""
            out.add(mod)
            out.update(f"{mod}.{a.name}" for a in node.names)
    return frozenset(out)


def _floor(module: str) -> int:
    parts = module.split(".")
    if len(parts) < 2 or parts[1] in BASE:
        return 0
    return FLOORS.index(parts[1]) if parts[1] in FLOORS else -1


def _modules(package: str):
    for path in sorted((ROOT / package).rglob("*.py")):
        yield ".".join(path.relative_to(ROOT).with_suffix("").parts), path


def test_kbm_never_imports_numerics():
    """No module of kbm (engine, results, LaTeX, the symbolic commands) imports numerics."""
    bad = [(m, i) for m, p in _modules("kbm") for i in _imports(p)
           if i == "numerics" or i.startswith("numerics.")]
    assert not bad, bad


def test_every_numerics_module_has_a_floor():
    """Each module of numerics sits in one of the named floors (a new subpackage must be
    placed in FLOORS deliberately)."""
    unknown = [m for m, _ in _modules("numerics") if _floor(m) < 0]
    assert not unknown, unknown


def test_numerics_imports_only_downwards():
    """A module of numerics imports its own floor and the floors below, never above."""
    bad = []
    for mod, path in _modules("numerics"):
        f = _floor(mod)
        for imp in _imports(path):
            if imp.startswith("numerics.") and _floor(imp) > f:
                if mod == "numerics.__init__" and FLOORS[_floor(imp)] != "cli":
                    continue  # the package's public surface re-exports every floor but cli
                bad.append((mod, imp))
    assert not bad, bad


def test_only_the_command_line_imports_kbm_cli():
    """kbm.cli (argument parsing) is imported by no library module."""
    bad = [(m, i) for pkg in ("kbm", "numerics") for m, p in _modules(pkg)
           if not (m.startswith("kbm.cli") or m.startswith("numerics.cli"))
           for i in _imports(p) if i.startswith("kbm.cli")]
    assert not bad, bad


def test_help_lists_every_command():
    """``kbm --help`` lists the symbolic and the numerical commands."""
    from kbm.cli import COMMANDS as SYMBOLIC
    from numerics.cli import COMMANDS as NUMERIC

    proc = subprocess.run([sys.executable, "-m", "numerics.cli", "--help"], capture_output=True,
                          text=True, timeout=120, cwd=ROOT)
    assert proc.returncode == 0
    for name in (*SYMBOLIC, *NUMERIC):
        assert f"\n    {name}" in proc.stdout, name


def test_broken_command_module_fails_loudly(monkeypatch):
    """A command module that cannot be imported raises; the command is not silently dropped."""
    import numerics.cli as cli

    monkeypatch.setattr(cli, "COMMANDS", (*cli.COMMANDS, "no_such_command"))
    with pytest.raises(ModuleNotFoundError, match="no_such_command"):
        cli.build_parser()
