"""The layering of the two packages (architecture review, issue 15).

- the core of kbm (every module but kbm.cli) imports nothing of numerics, even
  indirectly: checked in a fresh interpreter;
- the private algebra wing kbm.algebra is kbm's own: numerics and the benchmarks
  never import it (checked over their sources).
"""

from __future__ import annotations

import os
import pkgutil
import re
import subprocess
import sys
from pathlib import Path

import kbm

ROOT = Path(__file__).resolve().parents[1]


def _kbm_core_modules() -> list[str]:
    names = ["kbm"]
    for info in pkgutil.walk_packages(kbm.__path__, prefix="kbm."):
        if info.name == "kbm.cli" or info.name.startswith("kbm.cli."):
            continue
        names.append(info.name)
    return sorted(names)


def test_core_module_list_covers_the_wing():
    names = _kbm_core_modules()
    assert {"kbm.expansion.one_dof", "kbm.slowflow.averaged", "kbm.slowflow.series",
            "kbm.algebra.base",
            "kbm.algebra.poly_fourier", "kbm.algebra.bessel_fourier",
            "kbm.algebra.lazy_series", "kbm.algebra.laurent"} <= set(names)
    assert not any(n.startswith("kbm.cli") for n in names)


def test_kbm_core_never_imports_numerics():
    """Importing every module of kbm except kbm.cli leaves numerics out of sys.modules."""
    code = ("import importlib, sys\n"
            f"for name in {_kbm_core_modules()!r}:\n"
            "    importlib.import_module(name)\n"
            "bad = sorted(m for m in sys.modules if m == 'numerics' or m.startswith('numerics.'))\n"
            "print(' '.join(bad))\n")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=300, env=dict(os.environ), cwd=ROOT)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "", f"kbm's core imports {proc.stdout.strip()}"


_ALGEBRA_IMPORT = re.compile(r"^\s*(from\s+kbm\.algebra\b|import\s+kbm\.algebra\b"
                             r"|from\s+kbm\s+import\s+.*\balgebra\b)", re.MULTILINE)


def test_numerics_does_not_import_the_private_algebra():
    offenders = []
    for folder in ("numerics", "benchmarks"):
        for path in sorted((ROOT / folder).rglob("*.py")):
            text = path.read_text(encoding="utf-8")
            for m in _ALGEBRA_IMPORT.finditer(text):
                line = text.count("\n", 0, m.start()) + 1
                offenders.append(f"{path.relative_to(ROOT)}:{line}: {m.group(0).strip()}")
    assert not offenders, "\n".join(offenders)
