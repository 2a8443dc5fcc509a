"""Public names of a package imported from their modules on first use (PEP 562).

A package's ``__init__`` lists its heavier names with their modules; ``import kbm`` (and
every command of the ``kbm`` command line) then costs only what it uses.  A name that is
also a submodule's (``kbm.latex``) must stay an eager import: importing the submodule would
set the package attribute to the module.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from importlib import import_module

__all__ = ["lazy_names"]


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
