"""The packages' public names imported on first use (kbm._lazy, PEP 562): each name of
``__all__`` is the function or class it was before, even after its module (or a module of
the same name) was imported, and the command line does not import the heavy modules it does
not use."""

from __future__ import annotations

import importlib
import subprocess
import sys
import types

import pytest


@pytest.mark.parametrize("package", ["kbm", "kbm.model.forced", "numerics", "numerics.noise"])
def test_every_public_name_is_the_object_not_a_module(package):
    pkg = importlib.import_module(package)
    for name in pkg.__all__:
        obj = getattr(pkg, name)
        assert not isinstance(obj, types.ModuleType), f"{package}.{name} is a module"
        assert name in dir(pkg)
    with pytest.raises(AttributeError, match="has no attribute"):
        getattr(pkg, "no_such_name")


def test_a_submodule_of_the_same_name_does_not_shadow_the_function():
    """``kbm.latex`` is the function, also once its module (``kbm.output.latex``) is imported."""
    code = ("import kbm.output.latex, kbm; import types; "
            "print(isinstance(kbm.latex, types.ModuleType), callable(kbm.latex))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout.split()
    assert out == ["False", "True"]


def test_the_command_line_imports_only_what_it_uses():
    """``import numerics.cli`` (every ``kbm`` command's start) leaves the averaging engine,
    the comparisons and the paper unimported."""
    code = ("import sys, numerics.cli; print(' '.join(m for m in ('kbm.expansion.one_dof', "
            "'numerics.comparison', 'numerics.paper', 'kbm.backend.forced') if m in "
            "sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout.strip()
    assert out == ""
