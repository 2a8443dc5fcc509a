"""The cache folder of the generated flow modules, their import, and the first-run notice of
numba's compilation (split from :mod:`numerics.flow.jit`).

The folder is ``$KBM_CACHE_DIR``, else ``$XDG_CACHE_HOME/kbm`` or ``~/.cache/kbm`` (a
temporary folder if that is not writable); a generated module is kept there under the
SHA-256 of its source, so numba's on-disk cache of its machine code is reused by later
processes.
"""

from __future__ import annotations

import hashlib
import importlib.util
import os
import sys
import tempfile
from pathlib import Path

from numerics._memo import memo

__all__ = ["cache_dir", "compile_notice", "COMPILE_SECONDS"]


def cache_dir() -> Path:
    """The folder of generated modules (created if missing)."""
    base = os.environ.get("KBM_CACHE_DIR")
    if base:
        path = Path(base)
    else:
        xdg = os.environ.get("XDG_CACHE_HOME")
        path = (Path(xdg) if xdg else Path.home() / ".cache") / "kbm"
    try:
        path.mkdir(parents=True, exist_ok=True)
        probe = path / f".probe-{os.getpid()}"
        probe.write_text("")
        probe.unlink()
    except OSError:
        user = os.getuid() if hasattr(os, "getuid") else 0
        path = Path(tempfile.gettempdir()) / f"kbm-cache-{user}"
        path.mkdir(parents=True, exist_ok=True)
    return path


@memo(maxsize=64)
def _load(source: str):
    """Import the generated module of ``source`` (written to the cache folder under the
    SHA-256 of the source; memoised per source: time only)."""
    digest = hashlib.sha256(source.encode()).hexdigest()[:20]
    name = f"kbm_flow_{digest}"
    path = cache_dir() / f"{name}.py"
    if not path.exists() or path.read_text() != source:
        tmp = path.with_suffix(f".{os.getpid()}.tmp")
        tmp.write_text(source)
        os.replace(tmp, path)
    spec = importlib.util.spec_from_file_location(name, path)
    mod = importlib.util.module_from_spec(spec)
    sys.modules[name] = mod
    spec.loader.exec_module(mod)
    return mod


#: the first-run notice of each module numba compiles: module name -> (what, seconds)
_NOTICES: dict[str, tuple[str, float]] = {}
#: the modules whose notice was printed in this process
_NOTICED: set[str] = set()
#: whether the listener of numba's compile events is registered
_LISTENING: list[bool] = []
#: seconds of a first compilation on two cores, by what is compiled (measured: ``python
#: benchmarks/bench_startup.py`` prints the cold runs); the notice says "about" these
COMPILE_SECONDS = {"flow": 20, "shooting": 40, "other": 20}


def compile_notice(module: str, what: str, seconds: float) -> None:
    """Announce on standard error, once a process, when numba starts compiling a function
    of ``module`` (not when it loads the function from its cache): ``what`` it compiles
    and the expected time.

    The first run of a command on a new model compiles for tens of seconds; silence there
    looked like a hang (issue 39).  The notice follows numba's own ``numba:compile``
    event, so it shows whenever numba compiles and never on a warm run.  It is printed
    where standard error is a terminal, or where ``KBM_COMPILE_NOTICE=1`` (``0``: never):
    a log or a test that reads the error stream gets the same lines, cold cache or warm.
    """
    _NOTICES[module] = (what, seconds)
    _listen()


def _notice_wanted() -> bool:
    """Whether to print the first-run notice: ``KBM_COMPILE_NOTICE`` (``1`` or ``0``), else
    whether standard error is a terminal."""
    flag = os.environ.get("KBM_COMPILE_NOTICE")
    if flag is not None:
        return flag.strip() not in ("", "0")
    try:
        return sys.stderr.isatty()
    except (AttributeError, ValueError):  # a closed or replaced stream
        return False


def _listen() -> None:
    """Register the listener of numba's compile events (once a process)."""
    if _LISTENING:
        return
    from numba.core import event

    class _Notice(event.Listener):
        def on_start(self, ev) -> None:
            func = getattr(ev.data.get("dispatcher"), "py_func", None)
            module = getattr(func, "__module__", "") or ""
            if module in _NOTICED or not (module in _NOTICES or module.startswith(
                    ("numerics.", "kbm_flow_"))) or not _notice_wanted():
                return
            _NOTICED.add(module)
            what, seconds = _NOTICES.get(module, (module, COMPILE_SECONDS["other"]))
            print(f"kbm: compiling {what} with numba (first run; about {seconds:g} s on two "
                  f"cores, then cached in {cache_dir()})", file=sys.stderr, flush=True)

        def on_end(self, ev) -> None:
            pass

    event.register("numba:compile", _Notice())
    _LISTENING.append(True)


def _announce_compile(source: str, what: str = "the model's flow",
                      seconds: float | None = None) -> None:
    """The first-run notice of the generated module of ``source`` (:func:`compile_notice`)."""
    digest = hashlib.sha256(source.encode()).hexdigest()[:20]
    compile_notice(f"kbm_flow_{digest}", what,
                   COMPILE_SECONDS["flow"] if seconds is None else seconds)
