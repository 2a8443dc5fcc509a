"""The Langevin model printed into a small Python module and compiled by numba
(:mod:`numerics.noise.langevin`): every parameter an argument (the stage velocity ``v`` of
the sliders too, so one compilation serves a whole friction map), the acceleration, the
force and friction of BAOAB's split, the spring and the energy (its potential in closed
form where there is one), followed by the kernels of :mod:`numerics.noise._kernels`,
:mod:`numerics.noise._passage_kernels` and :mod:`numerics.noise._pair_kernels` and the loops
of ``final_states``, ``first_passages`` and ``slip_stats`` over several trajectories
(:mod:`numerics.noise.lanes`); or ``N`` coupled accelerations as one vector function
``accel_n(t_, y, p, out)`` followed by :mod:`numerics.noise._kernels` (whose
``vector_paths`` integrates them: :mod:`numerics.noise.coupled`).  The machine code is
cached on disk under the SHA-256 of the source (:func:`numerics.flow.numba_cache.cache_dir`); the
choice of scheme (Kloeden-Platen or BAOAB) is made here too.
"""

from __future__ import annotations

from pathlib import Path

import sympy as sp

from kbm.errors import ModelError, ParameterError
from kbm.model.builtins import SLIDERS, Oscillator, get_model
from kbm.symbols import t as T, x as X, xdot as V

from .._memo import memo
from ..errors import NumericsError
from ..flow.jit import jit_available
from ..flow.numba_cache import _announce_compile, _load
from .lanes import lane_count, lanes_source, steps_in_parts

__all__ = ["SCHEMES", "vector_module", "python_accel"]

#: version of the generated source (part of its hash)
_VERSION = "3"

_KERNELS = "\n\n".join(Path(__file__).with_name(f).read_text()
                         for f in ("_kernels.py", "_passage_kernels.py", "_pair_kernels.py"))
_HEADER = "import math\n\nimport numpy as np\nfrom numba import njit\n\n"
_STAGE_V = sp.Symbol("v")


def _symbolic(model: Oscillator | str, at_rest: bool = False) -> Oscillator:
    """The model with every parameter a symbol (a slider's stage velocity ``v`` too, unless
    ``at_rest``: then the slider at ``v = 0``, whose force carries no drive term, so that the
    compiled step is as short as a hand-written one)."""
    if isinstance(model, str):
        base = get_model(model)
        return base.with_stage_velocity(_STAGE_V) if model in SLIDERS and not at_rest else base
    return model


def _potential(model: Oscillator) -> sp.Expr | None:
    """``G(x) = -int_0^x (x'' at x' = 0, without the drive)``; ``None`` without a closed form."""
    s = sp.Dummy("s")
    force = (model.acceleration() - model.drive).subs(V, 0)
    if T in force.free_symbols:
        return None
    G = sp.integrate(-force.subs(X, s), (s, 0, X), conds="none")
    return None if G.has(sp.Integral) else G


def _affine_in_velocity(model: Oscillator) -> bool:
    """Whether ``x''`` is ``force(t, x) - gamma(t, x) x'``: BAOAB's O part is then exact."""
    return sp.expand(sp.diff(model.acceleration(), V, 2)) == 0


SCHEMES = {"kp": 0, "baoab": 1}


def _printer(names: tuple[str, ...], decorator: str = "@njit(cache=True)"):
    """``fn(signature, expr)``: the lines of a function returning ``float(expr)`` (the
    model's symbols renamed, common subexpressions shared) under ``decorator``."""
    from sympy.printing.pycode import PythonCodePrinter

    ren = {T: sp.Symbol("t_"), X: sp.Symbol("x_"), V: sp.Symbol("v_")}
    ren.update({sp.Symbol(n): sp.Symbol(f"p_{i}") for i, n in enumerate(names)})
    pr = PythonCodePrinter({"fully_qualified_modules": True, "strict": True})
    head = [f"    p_{i} = p[{i}]" for i in range(len(names))]

    def fn(signature: str, expr: sp.Expr) -> list[str]:
        e = sp.sympify(expr).xreplace(ren)
        repl, (red,) = sp.cse([e], symbols=sp.numbered_symbols("w_"), order="canonical")
        return ([decorator] if decorator else []) + ([f"def {signature}:"] + head
                + [f"    {pr.doprint(s)} = {pr.doprint(v)}" for s, v in repl]
                + [f"    return float({pr.doprint(red)})", "", ""])

    return fn


@memo(maxsize=16)
def python_accel(model: Oscillator, names: tuple[str, ...]):
    """``accel(t_, x_, v_, p)`` of the compiled module (:func:`_compiled`) as plain Python:
    the same printed source without numba, for the few calls that need no compilation (the
    default step of :func:`numerics.noise.langevin.natural_step`: loading the compiled
    module from numba's cache takes about 0.8 s).  Memoised per model and names, as
    :func:`_compiled` (time only: the printing, 1.2 ms of natural_step's 1.3 ms per call, CDC)."""
    from sympy.printing.codeprinter import PrintMethodNotImplementedError

    try:
        lines = _printer(names, "")("accel(t_, x_, v_, p)", model.acceleration())
    except PrintMethodNotImplementedError as exc:
        raise ModelError(f"model {model.name!r} has a term with no math-module equivalent "
                         f"({exc}); the Langevin integrator cannot compile it") from None
    space: dict = {}
    exec(compile("import math\n\n" + "\n".join(lines), "<python_accel>", "exec"), space)
    return space["accel"]


def _friction_const(model: Oscillator) -> bool:
    """Whether ``x''`` is ``force(t, x) - gamma x'`` with ``gamma`` free of ``t`` and ``x``
    (BAOAB's O part then has constant factors, hoisted from the loops)."""
    gamma = -sp.diff(model.acceleration(), V)
    return _affine_in_velocity(model) and not (sp.sympify(gamma).free_symbols & {T, X})


def _source(model: Oscillator, names: tuple[str, ...]) -> str:
    fn = _printer(names)
    G = _potential(model)
    acc = model.acceleration()
    lines = fn("accel(t_, x_, v_, p)", acc)
    affine = _affine_in_velocity(model)
    lines += fn("force(t_, x_, p)", acc.subs(V, 0))
    lines += fn("friction(t_, x_, p)", -sp.diff(acc, V) if affine else sp.nan)
    lines += [f"FRICTION_CONST = {int(_friction_const(model))}", "", ""]
    lines += fn("spring(t_, x_, v_, p)", model.drive - model.omega0**2 * X)
    lines += fn("energy(x_, v_, p)", V**2 / 2 + G if G is not None else sp.nan)
    return "\n".join(lines)


@memo(maxsize=16)
def _compiled(model: Oscillator, names: tuple[str, ...], scheme: str = "kp"):
    """The compiled module of ``model`` (memoised per model: time only)."""
    if not jit_available():
        raise NumericsError("the Langevin integrator needs numba (pip install numba) and "
                            "KBM_NO_JIT unset")
    from sympy.printing.codeprinter import PrintMethodNotImplementedError

    try:
        body = _source(model, names)
    except PrintMethodNotImplementedError as exc:
        raise ModelError(f"model {model.name!r} has a term with no math-module equivalent "
                         f"({exc}); the Langevin integrator cannot compile it") from None
    source = (f"# generated by numerics.noise.langevin (version {_VERSION}); do not edit\n"
              + _HEADER + f"SCHEME = {SCHEMES[scheme]}\n\n\n" + body
              + "\n" + _KERNELS + "\n\n" + lanes_source(
                  lane_count(model, scheme), lane_count(model, scheme, events=True),
                  steps_in_parts(model, scheme, _friction_const(model))))
    _announce_compile(source)
    return _load(source)


def _scheme(model: Oscillator, scheme: str) -> str:
    if scheme not in (*SCHEMES, "auto"):
        raise ParameterError(f"scheme must be one of kp, baoab, auto, got {scheme!r}")
    affine = _affine_in_velocity(model)
    if scheme == "auto":
        return "baoab" if affine else "kp"
    if scheme == "baoab" and not affine:
        raise ParameterError(f"BAOAB needs x'' affine in x' (exact friction step); model "
                             f"{model.name!r} is not: use scheme 'kp'")
    return scheme


@memo(maxsize=8)
def vector_module(exprs: tuple, state: tuple, names: tuple[str, ...]):
    """The compiled module of ``accel_n(t_, y, p, out)``: ``out[i] = exprs[i]`` at the state
    ``y`` (the symbols ``state`` in order, ``t`` the time) and the parameters ``p`` (the
    symbols ``names`` in order), common subexpressions shared, with the kernels of
    :mod:`numerics.noise._kernels` (``vector_paths``) after it.

    Raises
    ------
    kbm.errors.ModelError
        For a term with no math-module equivalent.
    """
    if not jit_available():
        raise NumericsError("the Langevin integrator needs numba (pip install numba) and "
                            "KBM_NO_JIT unset")
    from sympy.printing.codeprinter import PrintMethodNotImplementedError
    from sympy.printing.pycode import PythonCodePrinter

    ren = {T: sp.Symbol("t_")}
    ren.update({s: sp.Symbol(f"y_{i}") for i, s in enumerate(state)})
    ren.update({sp.Symbol(n): sp.Symbol(f"p_{i}") for i, n in enumerate(names)})
    pr = PythonCodePrinter({"fully_qualified_modules": True, "strict": True})
    repl, red = sp.cse([sp.sympify(e).xreplace(ren) for e in exprs],
                       symbols=sp.numbered_symbols("w_"), order="canonical")
    try:
        lines = (["@njit(cache=True)", "def accel_n(t_, y, p, out):"]
                 + [f"    p_{i} = p[{i}]" for i in range(len(names))]
                 + [f"    y_{i} = y[{i}]" for i in range(len(state))]
                 + [f"    {pr.doprint(a)} = {pr.doprint(b)}" for a, b in repl]
                 + [f"    out[{i}] = {pr.doprint(e)}" for i, e in enumerate(red)])
    except PrintMethodNotImplementedError as exc:
        raise ModelError(f"a term with no math-module equivalent ({exc}); the Langevin "
                         "integrator cannot compile it") from None
    source = (f"# generated by numerics.noise.codegen (version {_VERSION}); do not edit\n"
              + _HEADER + "SCHEME = 0\nFRICTION_CONST = 0\n\n\n" + "\n".join(lines)
              + "\n\n\n" + Path(__file__).with_name("_kernels.py").read_text())
    _announce_compile(source)
    return _load(source)
