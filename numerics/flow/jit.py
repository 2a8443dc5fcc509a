"""A compiled (numba) Dormand-Prince 8(5,3) integrator of a model's extended flow.

The limit-cycle shooting (:mod:`numerics.cycles.shooting`) integrates the state, its
variational equations, the divergence and the two dissipation integrals (nine
states) over one period, a few times per cycle.  Through scipy each right-hand
side evaluation is a Python call; here the right-hand side is printed from the
model's sympy expressions (:mod:`kbm` defines the model once) into a small
Python module together with an adaptive DOP853 stepper, and both are compiled by
numba.  The stepper is the method of :func:`scipy.integrate.solve_ivp`
(``method="DOP853"``): the same Butcher tableau (taken from scipy), the same
3rd/5th-order blended error estimate and step-size control (Hairer, Norsett and
Wanner, *Solving Ordinary Differential Equations I*, 2nd ed., Springer 1993,
sec. II.10).  Outputs at equally spaced times are hit exactly by shortening
steps (no interpolation).

The generated module is written to a cache folder (``$KBM_CACHE_DIR``, else
``$XDG_CACHE_HOME/kbm`` or ``~/.cache/kbm``; a temporary folder if that is not
writable) under a name that is the SHA-256 of its source, so numba's on-disk
cache of the machine code is reused by later processes.  A flow without extra source
is also compiled ahead of time into an extension module (:mod:`numerics.flow.aot`),
which later processes import without numba.  The caches store compiled code of a fixed
source: they change the time, never the result.

Without numba, or for a model whose expressions have no :mod:`math`
equivalent (e.g. Bessel functions), :func:`jit_flow` returns ``None`` and the
callers use scipy's integrators.
"""

from __future__ import annotations

import functools
import hashlib
import importlib.util
import os
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Callable

import numpy as np

from numerics.flow.numba_cache import _announce_compile, _load, _notice_wanted, cache_dir

if TYPE_CHECKING:
    import sympy as sp

__all__ = ["jit_flow", "jit_available", "FlowResult", "flow_cache_key", "cached_flow"]

#: version of the generated source (part of the file's hash)
_VERSION = "4"

#: the stepper's source, appended to the printed right-hand side (a real, linted file)
_STEPPER = (Path(__file__).with_name("_dop853_stepper.py")).read_text()


def jit_available() -> bool:
    """Whether numba is installed (and ``KBM_NO_JIT`` is not set); found without importing
    it (its import is 0.2-0.4 s, and a flow built ahead of time needs none:
    :mod:`numerics.flow.aot`)."""
    if os.environ.get("KBM_NO_JIT"):
        return False
    return _numba_installed()


@functools.lru_cache(maxsize=1)
def _numba_installed() -> bool:
    """Whether numba can be imported, looked up once per process: the search of ``sys.path``
    costs about 0.7 ms, and :func:`jit_available` is asked at every flow call (a long-period
    Newton iteration makes some 30 000 calls, a two-parameter continuation thousands)."""
    try:
        return importlib.util.find_spec("numba") is not None
    except (ImportError, ValueError):
        return False


def rhs_source(exprs: Sequence[sp.Expr], t: sp.Symbol, y: Sequence[sp.Symbol],
               params: Sequence[sp.Symbol], n_state: int = 2) -> str:
    """Python source of ``rhs(t, y, p, out)`` that writes ``exprs`` into ``out``.

    Called with ``len(y) == n_state`` it evaluates only the first ``n_state``
    expressions (the state alone, e.g. for transients); with the full ``y``, all.

    Raises
    ------
    sympy.printing.codeprinter.PrintMethodNotImplementedError
        If an expression has no :mod:`math` equivalent.
    """
    import sympy as sp
    from sympy.printing.pycode import PythonCodePrinter

    ren = {t: sp.Symbol("t_")}
    ren.update({yi: sp.Symbol(f"y_{i}") for i, yi in enumerate(y)})
    ren.update({pi: sp.Symbol(f"p_{i}") for i, pi in enumerate(params)})
    exprs = [sp.sympify(e).xreplace(ren) for e in exprs]
    pr = PythonCodePrinter({"fully_qualified_modules": True, "strict": True})

    def block(es, indent):
        repl, reduced = sp.cse(es, symbols=sp.numbered_symbols("w_"), order="canonical")
        return ([f"{indent}{pr.doprint(s)} = {pr.doprint(e)}" for s, e in repl]
                + [f"{indent}out[{i}] = {pr.doprint(e)}" for i, e in enumerate(reduced)])

    lines = ["@njit(cache=True)", "def rhs(t_, y, p, out):"]
    lines += [f"    p_{i} = p[{i}]" for i in range(len(params))]
    lines += [f"    y_{i} = y[{i}]" for i in range(n_state)]
    if n_state < len(y):
        lines += [f"    if y.shape[0] == {n_state}:"]
        lines += block(exprs[:n_state], "        ")
        lines += ["        return"]
        lines += [f"    y_{i} = y[{i}]" for i in range(n_state, len(y))]
    lines += block(exprs, "    ")
    return "\n".join(lines) + "\n"


def flow_cache_key(key: str, n_state: int = 2, extra: str = "") -> str:
    """The name under which a compiled flow's source is cached: the SHA-256 of the model's
    canonical form ``key`` (the ``srepr`` of its expressions and its parameters' order) and
    of the compilation's options (the generator's version, the states integrated alone,
    the extra source compiled with it).

    A warm run reads the source under this name and numba's machine code of that source:
    no printing of expressions (common subexpressions, renaming) and no compilation.
    """
    mark = hashlib.sha256(extra.encode()).hexdigest()[:12] if extra else ""
    return hashlib.sha256(f"{_VERSION}|{n_state}|{key}|{mark}".encode()).hexdigest()[:24]


def _source_by_key(key, exprs, t, y, params, n_state, extra: str = "") -> str | None:
    """The generated module's source (``None`` if an expression cannot be printed)."""
    from sympy.printing.codeprinter import PrintMethodNotImplementedError

    path = None
    tail = _STEPPER + extra
    if key is not None:
        path = cache_dir() / f"kbm_src_{flow_cache_key(key, n_state, extra)}.txt"
        try:
            text = path.read_text()
            if text.startswith(_HEADER) and text.endswith(tail):
                return text
        except OSError:
            pass
    try:
        src = rhs_source(exprs() if callable(exprs) else exprs, t, y, params, n_state=n_state)
    except PrintMethodNotImplementedError:
        return None
    source = _HEADER + src + tail
    if path is not None:
        try:
            tmp = path.with_suffix(f".{os.getpid()}.tmp")
            tmp.write_text(source)
            os.replace(tmp, path)
        except OSError:
            pass  # an unwritable cache costs time only
    return source


def cached_flow(key: str, n_state: int = 2, extra: str = "") -> Callable | None:
    """The flow built ahead of time (:mod:`numerics.flow.aot`) of the source cached under
    ``key`` (:func:`jit_flow`'s, with the same ``extra`` source), or ``None`` when either is
    missing: found without sympy or numba (a warm run from a model card,
    :mod:`numerics.flow.card`, or a line card, :mod:`numerics.flow.line_card`)."""
    if not jit_available():
        return None
    try:
        text = (cache_dir() / f"kbm_src_{flow_cache_key(key, n_state, extra)}.txt").read_text()
    except OSError:
        return None
    if not (text.startswith(_HEADER) and text.endswith(_STEPPER + extra)):
        return None
    from numerics.flow.aot import load

    built = load(cache_dir(), text)
    return None if built is None else _aot_flow(built, extra)


_HEADER = (f"# generated by numerics.flow.jit (version {_VERSION}); do not edit\n"
           "import math\n\nimport numpy as np\nfrom numba import njit\n\n\n")


class FlowResult:
    """States at equally spaced times, the integrator status and the step count."""

    __slots__ = ("y", "status", "steps")

    def __init__(self, y: np.ndarray, status: int, steps: int):
        self.y, self.status, self.steps = y, status, steps

    @property
    def message(self) -> str:
        """What the status means (empty when the integration succeeded)."""
        return _MESSAGES.get(self.status, "")


_MESSAGES = {1: "the step limit was reached", 2: "the step size fell below the time resolution",
             3: "the state became non-finite"}


def jit_flow(exprs: Sequence[sp.Expr] | Callable[[], Sequence[sp.Expr]], t: sp.Symbol,
             y: Sequence[sp.Symbol], params: Sequence[sp.Symbol], n_state: int = 2, *,
             key: str | None = None, extra: str = "", what: str = "the model's flow",
             seconds: float | None = None) -> Callable | None:
    """A compiled flow of ``y' = exprs(t, y, params)``, or ``None`` if it cannot be compiled.

    Returns
    -------
    callable or None
        ``flow(y0, t_end, p, rtol, atol, n_out=1, max_steps=10**6)`` returning a
        :class:`FlowResult` with ``y`` of shape ``(n_out + 1, len(y0))`` at
        ``t_k = k t_end/n_out`` (rows not reached are NaN).  ``y0`` holds all
        the states, or only the first two (then only those are integrated).
        Its attribute ``to_turn(y0, sign, t_max, p, rtol, atol)`` follows the state
        ``(x, x')`` forward or backward to where ``x'`` first changes sign (an event the
        flow itself does not locate): ``(x, x', t, status)``; ``to_section(y0, sign,
        xsec, t_max, p, rtol, atol)`` to where ``x`` first crosses ``xsec``.
        The first call in a new cache folder compiles (a few seconds); later
        calls and processes reuse the machine code.

    Other parameters
    ----------------
    key
        A string that determines ``exprs`` (e.g. the ``srepr`` of the expressions they are
        built from).  Printing large expressions (common subexpressions, renaming) takes
        seconds; with a key the printed source is kept in the cache folder under the key's
        SHA-256 and read back by later processes.  ``exprs`` may then be a function that
        builds them, called only when the source is not there yet.  The source is the same
        either way: the key changes the time, never the result.
    extra
        More source appended to the module after the stepper (functions that call ``flow``
        and ``rhs``, compiled with them: e.g. a Newton corrector); the module is the
        returned flow's attribute ``module``.
    what, seconds
        The first-run notice: what is compiled and about how long it takes
        (:func:`compile_notice`; printed only when numba compiles, not when it loads).
    """
    if not jit_available():
        return None
    source = _source_by_key(key, exprs, t, y, params, n_state, extra)
    if source is None:
        return None
    from numerics.flow.aot import build, load

    built = load(cache_dir(), source)
    if built is not None:
        return _aot_flow(built, extra)
    _announce_compile(source, what, seconds)
    try:
        mod = _load(source)
        fn = mod.flow
        # compile now (or load from the cache), so that typing errors show here
        fn(np.zeros(len(y)), 1e-3, np.ones(len(params)), 1e-6, 1e-6, 1, 10)
    except Exception:  # noqa: BLE001 - any failure to compile means: use scipy instead
        return None
    # for the next process (this one goes on with numba's code)
    build(cache_dir(), source, mod, what, _notice_wanted())
    return _wrap_flow(mod, np.asarray, mod)


class _AotModule:
    """A module built ahead of time with extra source, as :func:`jit_flow`'s ``module``:
    its functions called with the arrays made C-contiguous (the exported types,
    :data:`numerics.flow.aot.EXTRA_SIGNATURES`); the numbers are those of numba's code."""

    def __init__(self, mod) -> None:
        self._mod = mod
        self.__name__, self.__file__ = mod.__name__, getattr(mod, "__file__", None)

    def __getattr__(self, name: str):
        fn = getattr(self._mod, name)
        if not callable(fn):
            return fn

        def call(*args):
            return fn(*(np.ascontiguousarray(a, dtype=float) if isinstance(a, np.ndarray)
                        else a for a in args))

        call.__name__ = name
        self.__dict__[name] = call
        return call


def _aot_flow(mod, extra: str = "") -> Callable:
    """The flow of a module built ahead of time (:mod:`numerics.flow.aot`): the calls of
    :func:`jit_flow`'s, the arrays made C-contiguous (the exported types); with ``extra``
    source its ``module`` calls the extra functions the same way (:class:`_AotModule`)."""
    return _wrap_flow(mod, np.ascontiguousarray, _AotModule(mod) if extra else mod)


def _wrap_flow(mod, array: Callable, module) -> Callable:
    """The calls of a compiled module's ``flow``, ``to_turn`` and ``to_section`` (numba's
    or one built ahead of time), their arrays passed through ``array`` (``np.asarray``, or
    ``np.ascontiguousarray`` for the exported types); ``module`` is the flow's attribute."""
    def flow(y0, t_end, p, rtol, atol, n_out=1, max_steps=10**6) -> FlowResult:
        out, status, steps = mod.flow(array(y0, dtype=float), float(t_end),
                                      array(p, dtype=float), float(rtol), float(atol),
                                      int(n_out), int(max_steps))
        return FlowResult(out, int(status), int(steps))

    def to_turn(y0, sign, t_max, p, rtol, atol, max_steps=10**6):
        """``(x, x', t, status)`` where ``x'`` first changes sign on the orbit of the state
        ``y0[:2]``, forward (``sign = 1``) or backward (``-1``) in time (the stepper's
        ``to_turn``: status 0 found, 1 not within ``t_max``, 3 non-finite)."""
        x, v, t, status = mod.to_turn(array(y0, dtype=float), float(sign), float(t_max),
                                      array(p, dtype=float), float(rtol), float(atol),
                                      int(max_steps))
        return float(x), float(v), float(t), int(status)

    def to_section(y0, sign, xsec, t_max, p, rtol, atol, max_steps=10**6):
        """``(x, x', t, status)`` where the orbit of the state ``y0[:2]``, forward (``sign =
        1``) or backward (``-1``) in time, first crosses ``x = xsec`` (the stepper's
        ``to_section``: status 0 found, 1 not within ``t_max``, 3 non-finite)."""
        x, v, t, status = mod.to_section(array(y0, dtype=float), float(sign), float(xsec),
                                         float(t_max), array(p, dtype=float), float(rtol),
                                         float(atol), int(max_steps))
        return float(x), float(v), float(t), int(status)

    flow.to_turn = to_turn
    flow.to_section = to_section
    flow.module = module
    return flow
