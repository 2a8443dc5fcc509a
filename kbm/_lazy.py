"""Public names of a package imported from their modules on first use (PEP 562).

A package's ``__init__`` lists its heavier names with their modules; ``import kbm`` (and
every command of the ``kbm`` command line) then costs only what it uses.  A name that is
also a submodule's (a function ``sweep`` held by a module ``sweep``) is kept the
object by :func:`keep_objects`: importing the submodule would otherwise set the package
attribute to the module.
"""

from __future__ import annotations

import sys
import types
from collections.abc import Callable, Iterable, Mapping
from importlib import import_module

__all__ = ["lazy_names", "keep_objects"]


def lazy_names(package: str, namespace: dict, names: Mapping[str, str]
               ) -> tuple[Callable[[str], object], Callable[[], list[str]]]:
    """``(__getattr__, __dir__)`` for ``package`` whose ``namespace`` (its ``globals()``)
    gets each of ``names`` (name -> module, absolute or relative to ``package``) on first
    access."""
    def __getattr__(name: str):
        module = names.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(import_module(module, package), name)
        namespace[name] = value
        return value

    def __dir__() -> list[str]:
        return sorted(set(namespace) | set(names))

    return __getattr__, __dir__


def keep_objects(package: str, names: Iterable[str]) -> None:
    """Keep ``package.NAME`` the object ``NAME`` of the submodule ``package.NAME`` when that
    submodule is imported (the import system sets the package attribute to the module; here
    the module's own ``NAME`` is stored instead).

    The package's module object gets a subclass of :class:`types.ModuleType` whose
    ``__setattr__`` does this (a module's ``__class__`` may be assigned, Python >= 3.5).
    """
    module = sys.modules[package]
    kept = frozenset(names)

    class _Package(types.ModuleType):
        def __setattr__(self, name: str, value: object) -> None:
            if (name in kept and isinstance(value, types.ModuleType)
                    and value.__name__ == f"{package}.{name}"):
                value = getattr(value, name)
            super().__setattr__(name, value)

    module.__class__ = _Package
