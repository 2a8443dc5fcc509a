"""The compiled flows ahead of time: an extension module per generated source (issue 39).

numba's on-disk cache keeps the machine code of :mod:`numerics.flow.jit`'s generated
modules, but loading it still imports numba (0.2-0.4 s on two quiet cores, with
``scipy.linalg`` for numba's ``np.linalg``) and initialises numba's compiler target
(0.3-0.5 s) before the first call.  The same source compiled once ahead of time by
:mod:`numba.pycc` is a plain CPython extension: importing it and calling its ``flow``
takes well under a millisecond, and numba is not imported at all.

A module is built the first time its source is compiled or loaded by numba in a cache
folder (after numba's own compilation, in the same process: :func:`build`), and is read
by later processes (:func:`load`).  Its name is the SHA-256 of the source, of numba's
version and of this module's format; the file is written under a temporary name and
renamed, so a process never reads half a module; a build that fails (no C compiler) is
noted in the folder (``NAME.failed``) and not tried again there.  The functions exported
are the stepper's ``flow``, ``to_turn`` and ``to_section`` with the argument types the
compiled flow is called with, and the functions of the extra source compiled with it (the continuation's Newton
corrector ``shoot_correct`` and ``accelerations``: :data:`EXTRA_SIGNATURES`); the code is
that of the same Python source, compiled by the same LLVM without fast-math, so the numbers are those of the just-in-time code to the last bit (a test
compares them).  Set ``KBM_AOT=0`` to use numba's just-in-time code only.

Built modules are always read where they exist; a build (10-15 s a flow on two quiet cores)
is made only where start-up is what the user waits for: the commands ``kbm cycle`` and
``kbm branch`` ask for it (:func:`allow_builds`), and ``KBM_AOT=1`` asks for it everywhere.
Long jobs (``kbm reproduce``, sweeps, the library) keep numba's code and pay no build.
"""

from __future__ import annotations

import hashlib
import importlib.machinery
import importlib.util
import os
import shutil
import sys
import tempfile
import warnings
from pathlib import Path
from types import ModuleType

__all__ = ["enabled", "allow_builds", "builds_wanted", "module_name", "load", "build",
           "exports", "SIGNATURES", "EXTRA_SIGNATURES"]

#: version of the built modules' layout (part of the name)
_FORMAT = "1"

#: the exported functions and their types: the arrays C-contiguous (the callers pass
#: ``numpy.ascontiguousarray``), the scalars as :mod:`numerics.flow.jit` passes them
SIGNATURES = {
    "flow": "Tuple((f8[:,::1], i8, i8))(f8[::1], f8, f8[::1], f8, f8, i8, i8)",
    "to_turn": "Tuple((f8, f8, f8, i8))(f8[::1], f8, f8, f8[::1], f8, f8, i8)",
    "to_section": "Tuple((f8, f8, f8, i8))(f8[::1], f8, f8, f8, f8[::1], f8, f8, i8)",
}


#: the functions of the extra source compiled with the flow (:func:`numerics.flow.jit.jit_flow`'s
#: ``extra``: the continuation's Newton corrector, ``numerics/flow/_shooting_corrector.py``),
#: exported where the source defines them, with the types their callers pass
EXTRA_SIGNATURES = {
    "shoot_correct": "Tuple((i8, i8, f8[::1], f8[::1], f8[:,::1], f8[::1], f8[:,::1], f8))"
                     "(f8[::1], f8[::1], f8, f8[::1], f8[::1], f8, b1, f8, i8, i8, i8, f8, f8, f8, f8,"
                     " f8)",
    "accelerations": "f8[::1](f8[::1], f8[::1])",
}


def exports(source: str) -> dict[str, str]:
    """The functions exported from the module of ``source`` and their types: the stepper's
    (:data:`SIGNATURES`) and those of :data:`EXTRA_SIGNATURES` that ``source`` defines."""
    extra = {f: sig for f, sig in EXTRA_SIGNATURES.items() if f"\ndef {f}(" in source}
    return {**SIGNATURES, **extra}


def enabled() -> bool:
    """Whether ahead-of-time modules are used (``KBM_AOT`` is not ``0``)."""
    return os.environ.get("KBM_AOT", "").strip() != "0"


#: whether this process builds missing modules (:func:`allow_builds`)
_BUILDS = {"allowed": False}


def allow_builds(allowed: bool = True) -> None:
    """Let this process build the modules it lacks (the commands whose start-up matters:
    ``kbm cycle``, ``kbm branch``).  Where ``KBM_AOT=1`` they are built in any case."""
    _BUILDS["allowed"] = bool(allowed)


def builds_wanted() -> bool:
    """Whether a missing module is built now: ``KBM_AOT=1``, or allowed by the command and
    ``KBM_AOT`` not ``0``."""
    flag = os.environ.get("KBM_AOT", "").strip()
    return flag == "1" or (flag != "0" and _BUILDS["allowed"])


def _numba_version() -> str:
    """numba's version from its installed metadata's folder name, without importing it."""
    spec = importlib.util.find_spec("numba")
    if spec is None or not spec.origin:
        return "none"
    site = Path(spec.origin).parent.parent
    found = sorted(p.name for p in site.glob("numba-*.dist-info"))
    return found[-1] if found else "unknown"


def module_name(source: str) -> str:
    """The extension's module name for a generated ``source``."""
    text = f"{_FORMAT}|{_numba_version()}|{sys.implementation.cache_tag}|{source}"
    return "kbm_aot_" + hashlib.sha256(text.encode()).hexdigest()[:20]


def _path(folder: Path, name: str) -> Path:
    return folder / (name + importlib.machinery.EXTENSION_SUFFIXES[0])


def load(folder: Path, source: str) -> ModuleType | None:
    """The built module of ``source`` in ``folder``, or ``None`` (not built, or not
    loadable: then the just-in-time path is taken)."""
    if not enabled():
        return None
    name = module_name(source)
    if name in sys.modules:
        return sys.modules[name]
    path = _path(folder, name)
    if not path.exists():
        return None
    try:
        spec = importlib.util.spec_from_file_location(name, path)
        mod = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(mod)
    except Exception:  # noqa: BLE001 - an unloadable module is rebuilt by the JIT path
        return None
    if not all(callable(getattr(mod, f, None)) for f in exports(source)):
        return None
    sys.modules[name] = mod
    return mod


#: seconds of one build on two cores (measured: 10-15 s quiet, 50 s with the machine
#: loaded six-fold); the first-run notice says "about" this
BUILD_SECONDS = 15


def build(folder: Path, source: str, module: ModuleType, what: str = "the model's flow",
          notice: bool = False) -> bool:
    """Compile the stepper of ``module`` (the generated module of ``source``, imported by
    numba) ahead of time into ``folder``; ``False`` where that fails (no C compiler, no
    ``numba.pycc``): the just-in-time code is then used, at its speed.  With ``notice``
    announced on standard error as numba's compilations are
    (:func:`numerics.flow.numba_cache.compile_notice` decides when)."""
    name = module_name(source)
    failed = folder / f"{name}.failed"
    if not builds_wanted() or _path(folder, name).exists() or failed.exists():
        return False
    if notice:
        print(f"kbm: compiling {what} ahead of time (first run; about {BUILD_SECONDS} s on "
              f"two cores, then cached in {folder})", file=sys.stderr, flush=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{name}-", dir=folder))
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # numba.pycc is deprecated (still shipped)
            from numba.pycc import CC

            cc = CC(name)
            cc.output_dir = str(tmp)
            cc.verbose = False
            for func, sig in exports(source).items():
                cc.export(func, sig)(getattr(module, func).py_func)
            cc.compile()
        built = _path(tmp, name)
        if not built.exists():
            raise OSError("numba.pycc wrote no module")
        os.replace(built, _path(folder, name))
        return True
    except Exception as exc:  # noqa: BLE001 - time only: the just-in-time code stays in use
        try:  # not tried again in this folder (a build takes seconds)
            failed.write_text(f"{type(exc).__name__}: {exc}\n")
        except OSError:
            pass
        return False
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
