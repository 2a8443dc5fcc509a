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
cache of the machine code is reused by later processes.  The cache stores
compiled code of a fixed source: it changes the time, never the result.

Without numba, or for a model whose expressions have no :mod:`math`
equivalent (e.g. Bessel functions), :func:`jit_flow` returns ``None`` and the
callers use scipy's integrators.
"""

from __future__ import annotations

import hashlib
import importlib.util
import os
import sys
import tempfile
from collections.abc import Sequence
from pathlib import Path
from typing import Callable

import numpy as np
import sympy as sp

__all__ = ["jit_flow", "jit_available", "cache_dir", "FlowResult"]

#: version of the generated source (part of the file's hash)
_VERSION = "2"

_STEPPER = r'''
from scipy.integrate._ivp import dop853_coefficients as _dc

_NS = _dc.N_STAGES
_A = np.ascontiguousarray(_dc.A[:_NS, :_NS])
_B = np.ascontiguousarray(_dc.B)
_C = np.ascontiguousarray(_dc.C[:_NS])
_E3 = np.ascontiguousarray(_dc.E3)
_E5 = np.ascontiguousarray(_dc.E5)


@njit(cache=True)
def _norm(v, scale):
    s = 0.0
    for i in range(v.shape[0]):
        s += (v[i] / scale[i]) ** 2
    return math.sqrt(s / v.shape[0])


@njit(cache=True)
def flow(y0, t_end, p, rtol, atol, n_out, max_steps):
    """States at t_k = k t_end / n_out, k = 0..n_out (NaN after a failure); status 0 ok,
    1 step limit, 2 step size underflow, 3 non-finite state; and the number of steps."""
    n = y0.shape[0]
    out = np.full((n_out + 1, n), np.nan)
    out[0, :] = y0
    y = y0.copy()
    K = np.zeros((_NS + 1, n))
    f = np.empty(n)
    rhs(0.0, y, p, f)
    # initial step (Hairer, Norsett & Wanner, sec. II.4; as scipy's select_initial_step)
    scale = np.empty(n)
    for i in range(n):
        scale[i] = atol + abs(y[i]) * rtol
    d0 = _norm(y, scale)
    d1 = _norm(f, scale)
    if d0 < 1e-5 or d1 < 1e-5:
        h0 = 1e-6
    else:
        h0 = 0.01 * d0 / d1
    y1 = y + h0 * f
    f1 = np.empty(n)
    rhs(h0, y1, p, f1)
    d2 = _norm(f1 - f, scale) / h0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / 8.0)
    h = min(100 * h0, h1, t_end / n_out)
    t = 0.0
    k = 1
    steps = 0
    ynew = np.empty(n)
    fnew = np.empty(n)
    ys = np.empty(n)
    err3 = np.empty(n)
    err5 = np.empty(n)
    rejected = False
    while k <= n_out:
        t_next = t_end * k / n_out
        if steps >= max_steps:
            return out, 1, steps
        hmin = 10.0 * abs(np.nextafter(t, np.inf) - t)
        h_try = h
        last = False
        if t + h_try >= t_next - hmin:
            h_try = t_next - t
            last = True
        if h_try < hmin:
            return out, 2, steps
        # stages
        K[0, :] = f
        for s in range(1, _NS):
            for i in range(n):
                acc = 0.0
                for j in range(s):
                    acc += _A[s, j] * K[j, i]
                ys[i] = y[i] + h_try * acc
            rhs(t + _C[s] * h_try, ys, p, K[s])
        for i in range(n):
            acc = 0.0
            for j in range(_NS):
                acc += _B[j] * K[j, i]
            ynew[i] = y[i] + h_try * acc
        t_new = t_next if last else t + h_try
        rhs(t_new, ynew, p, fnew)
        K[_NS, :] = fnew
        steps += 1
        finite = True
        for i in range(n):
            if not math.isfinite(ynew[i]):
                finite = False
        e3 = 0.0
        e5 = 0.0
        for i in range(n):
            sc = atol + max(abs(y[i]), abs(ynew[i])) * rtol
            a3 = 0.0
            a5 = 0.0
            for j in range(_NS + 1):
                a3 += K[j, i] * _E3[j]
                a5 += K[j, i] * _E5[j]
            e3 += (a3 / sc) ** 2
            e5 += (a5 / sc) ** 2
        if e5 == 0.0 and e3 == 0.0:
            err = 0.0
        else:
            err = abs(h_try) * e5 / math.sqrt((e5 + 0.01 * e3) * n)
        if not finite:
            err = math.inf
        if err < 1.0:
            if err == 0.0:
                factor = 10.0
            else:
                factor = min(10.0, 0.9 * err ** (-1.0 / 8.0))
            if rejected:
                factor = min(1.0, factor)
            t = t_new
            y[:] = ynew
            f[:] = fnew
            if last:
                out[k, :] = y
                k += 1
                # keep the natural step, not the shortened one
                if h_try < h:
                    factor = 1.0
                    h_try = h
            h = h_try * factor
            rejected = False
        else:
            if not finite and h_try < 1e-12 * max(1.0, t_end):
                return out, 3, steps
            h = h_try * max(0.2, 0.9 * err ** (-1.0 / 8.0)) if finite else 0.5 * h_try
            rejected = True
    return out, 0, steps
'''


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


def jit_available() -> bool:
    """Whether numba can be imported (and ``KBM_NO_JIT`` is not set)."""
    if os.environ.get("KBM_NO_JIT"):
        return False
    try:
        import numba  # noqa: F401
    except ImportError:
        return False
    return True


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


#: generated modules loaded in this process, by source hash (time only)
_MODULES: dict[str, object] = {}


def _load(source: str):
    digest = hashlib.sha256(source.encode()).hexdigest()[:20]
    mod = _MODULES.get(digest)
    if mod is not None:
        return mod
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
    _MODULES[digest] = mod
    return mod


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


def jit_flow(exprs: Sequence[sp.Expr], t: sp.Symbol, y: Sequence[sp.Symbol],
             params: Sequence[sp.Symbol]) -> Callable | None:
    """A compiled flow of ``y' = exprs(t, y, params)``, or ``None`` if it cannot be compiled.

    Returns
    -------
    callable or None
        ``flow(y0, t_end, p, rtol, atol, n_out=1, max_steps=10**6)`` returning a
        :class:`FlowResult` with ``y`` of shape ``(n_out + 1, len(y0))`` at
        ``t_k = k t_end/n_out`` (rows not reached are NaN).  ``y0`` holds all
        the states, or only the first two (then only those are integrated).
        The first call in a new cache folder compiles (a few seconds); later
        calls and processes reuse the machine code.
    """
    if not jit_available():
        return None
    from sympy.printing.codeprinter import PrintMethodNotImplementedError

    try:
        src = rhs_source(exprs, t, y, params)
    except PrintMethodNotImplementedError:
        return None
    source = (f"# generated by numerics.flow.jit (version {_VERSION}); do not edit\n"
              "import math\n\nimport numpy as np\nfrom numba import njit\n\n\n" + src
              + _STEPPER)
    try:
        mod = _load(source)
        fn = mod.flow
        # compile now (or load from the cache), so that typing errors show here
        fn(np.zeros(len(y)), 1e-3, np.ones(len(params)), 1e-6, 1e-6, 1, 10)
    except Exception:  # noqa: BLE001 - any failure to compile means: use scipy instead
        return None

    def flow(y0, t_end, p, rtol, atol, n_out=1, max_steps=10**6) -> FlowResult:
        out, status, steps = fn(np.asarray(y0, dtype=float), float(t_end),
                                np.asarray(p, dtype=float), float(rtol), float(atol),
                                int(n_out), int(max_steps))
        return FlowResult(out, int(status), int(steps))

    return flow
