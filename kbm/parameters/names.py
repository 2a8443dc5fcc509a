"""The names of a model's parameters, physical and scaled, and the noise ``D`` or ``T = D/mu``.

One place answers, for every model and command, which parameter names are valid and how
the physical ones of the paper map to the scaled ones the engines use (eqs. 3 and 12):
``delta = Delta/mu`` and ``k = 2 pi/lam``, and back, ``Delta = mu delta`` and
``lam = 2 pi/k``.  Where noise ``sqrt(2 D) xi`` applies, its intensity may be given as
``D`` or as the temperature ``T = kT = D/mu`` of a linearly damped oscillator
(fluctuation-dissipation, Kubo 1966: ``<x'^2> = kT`` for unit mass).

:class:`kbm.parameters.values.ParameterNames` is what a command checks the user's names against,
and :func:`kbm.parameters.values.scaled_values` the one binding layer of every model (both
defined in :mod:`kbm.parameters.values`, below the model types);
:func:`lookup` finds a built-in model of any kind by name (the one-degree-of-freedom, forced and
coupled ones) with a message that lists them all.  :func:`physical_axis` binds a ``--vary`` range
given in a physical name (``Delta=0:1``) to the scaled parameter it is computed as (``delta`` over
``[0, 10]`` at ``mu = 0.1``) and maps the values found back (:class:`PhysicalAxis`), for every
command that follows or spans one.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..errors import ModelError, ParameterError
from .values import ParameterNames, closest, parameter_value

if TYPE_CHECKING:
    import sympy as sp

__all__ = ["names_of", "lookup", "builtin_model",
           "builtin_names", "to_physical", "noise_from", "noise_intensity",
           "PhysicalAxis", "physical_axis", "MONOTONE_POINTS"]


def builtin_model(name: str):
    """The built-in of any kind called ``name`` (one degree of freedom, forced, coupled), or
    ``None``."""
    from ..model.builtins import MODELS, get_model

    if name in MODELS:
        return get_model(name)
    from ..model.coupled_builtins import get_coupled_model, is_coupled_name
    from ..model.forced_builtins import FORCED_MODELS, get_forced_model

    if name in FORCED_MODELS:
        return get_forced_model(name)
    if is_coupled_name(name):
        return get_coupled_model(name)
    return None


def builtin_names(kinds: Iterable[str] = ("one", "forced", "coupled")) -> dict[str, list[str]]:
    """The built-in model names by kind: ``one`` degree of freedom, ``forced``, ``coupled``."""
    from ..model.coupled_builtins import coupled_model_names
    from ..model.forced_builtins import FORCED_MODELS
    from ..model.builtins import MODELS

    table = {"one": list(MODELS), "forced": list(FORCED_MODELS),
             "coupled": list(coupled_model_names())}
    return {k: table[k] for k in kinds}


_KIND_WORDS = {"one": "one degree of freedom", "forced": "forced",
               "coupled": "coupled (and sedf-chain-N)"}


def lookup(name: str, kinds: Iterable[str] = ("one", "forced", "coupled"), *,
           rhs: bool = False):
    """The built-in model called ``name`` among ``kinds``.

    Raises
    ------
    kbm.errors.ModelError
        For an unknown name: the closest name, and every built-in a command of these
        ``kinds`` takes (``--rhs`` offered only where ``rhs``).
    """
    from ..model.builtins import MODELS

    kinds = tuple(kinds)
    found = builtin_model(name)
    if "one" in kinds and name in MODELS:  # before the other catalogues, which import
        return found                       # slowly (0.26 s: issue 39)
    table = builtin_names(kinds)
    ok = found is not None and any(
        name in table[k] or (k == "coupled" and name.startswith("sedf-chain-"))
        for k in kinds)
    if ok:
        return found
    every = [n for k in kinds for n in table[k]]
    lists = "; ".join(f"{_KIND_WORDS[k]}: {', '.join(table[k])}" for k in kinds)
    if found is not None:  # a built-in of another kind: not unknown, the wrong command
        kind = next(k for k, ns in builtin_names(("one", "forced", "coupled")).items()
                    if name in ns or (k == "coupled" and name.startswith("sedf-chain-")))
        raise ModelError(f"{name!r} is a {_KIND_WORDS[kind].split(' (')[0]} model, and this "
                         f"command takes {lists}"
                         + (" (or your own F with --rhs EXPR)" if rhs else ""))
    near = closest(name, every)
    raise ModelError(f"unknown model {name!r}" + (f" (did you mean {near}?)" if near else "")
                     + f"; the built-in models are {lists}"
                     + (" (or give your own F with --rhs EXPR)" if rhs else ""))


def names_of(model, *, extra: Iterable[str] = (), noise: bool = False) -> ParameterNames:
    """The :class:`ParameterNames` of a model (or built-in name)."""
    import sympy as sp

    if isinstance(model, str):
        model = lookup(model)
    physical = {k: sp.sympify(v) for k, v in (getattr(model, "physical", {}) or {}).items()}
    return ParameterNames(model.name, tuple(model.parameters), physical, tuple(extra), noise)


def to_physical(names: ParameterNames, values: Mapping[str, object]) -> dict[str, sp.Expr]:
    """The values with each scaled name that has a physical form replaced by it:
    ``delta -> Delta = mu delta``, ``k -> lam = 2 pi/k`` (exact), the order kept.

    Raises
    ------
    kbm.errors.ParameterError
        If the conversion needs ``mu`` and it is not among ``values``, or the physical
        value is undefined (``k = 0``).
    """
    import sympy as sp

    out: dict[str, sp.Expr] = {}
    for key, raw in values.items():
        expr = names.physical.get(key)
        if expr is None:
            out[key] = raw
            continue
        (phys,) = [s for s in expr.free_symbols if s.name != "mu"]
        need = {s.name for s in expr.free_symbols} - {phys.name}
        missing = sorted(need - set(values))
        if missing:
            raise ParameterError(f"{key} = {sp.sstr(expr)} needs {', '.join(missing)} to "
                                 f"give {phys.name}: give "
                                 + " and ".join(f"-p {m}=VALUE" for m in missing))
        (sol,) = sp.solve(sp.Eq(expr, sp.Symbol("_value")), phys)
        env = {sp.Symbol(n): parameter_value(n, values[n]) for n in need}
        env[sp.Symbol("_value")] = parameter_value(key, raw)
        val = sp.sympify(sol.xreplace(env))
        if not (val.is_finite and val.is_real):
            raise ParameterError(f"{key} = {raw} gives no finite {phys.name} "
                                 f"({key} = {sp.sstr(expr)})")
        out[phys.name] = val
    return out


def noise_from(values: Mapping[str, object],
               need: str | None = None) -> tuple[dict[str, object], sp.Expr | None, str]:
    """``(values without the noise, D, the name given)`` from ``D`` or ``T = D/mu``.

    ``D`` is ``None`` when neither is given, and as given (unread) when given as ``D``;
    ``T`` is read here, and needs ``mu > 0`` (the temperature of the linear damping
    ``mu x'``).  ``need`` says, as in :func:`noise_intensity`, why the caller refuses
    ``T = 0``: a negative ``T`` is then told the range ``T > 0`` the caller accepts, not
    ``T >= 0``.

    Raises
    ------
    kbm.errors.ParameterError
        For both given, a negative ``T`` (named ``T``), or ``T`` without ``mu > 0``.
    """
    rest = dict(values)
    if "D" in rest and "T" in rest:
        raise ParameterError("give the noise as D or as T = D/mu, not both")
    if "D" in rest:  # read and checked where it is used (:func:`noise_intensity`)
        return rest, rest.pop("D"), "D"
    if "T" in rest:
        raw = rest.pop("T")
        val = parameter_value("T", raw)
        if val < 0:
            rule = ("finite and >= 0 (T = 0 is the deterministic model)" if need is None
                    else f"finite and > 0 ({need}); give -p T=VALUE with T > 0")
            raise ParameterError(f"T = {raw} is negative; the temperature kT = D/mu must be "
                                 + rule)
        if "mu" not in rest:
            raise ParameterError("T = D/mu needs mu: give -p mu=VALUE, or the noise as "
                                 "-p D=VALUE")
        mu = parameter_value("mu", rest["mu"])
        if not mu > 0:
            raise ParameterError(f"T = D/mu is the temperature of the damping mu x' and "
                                 f"needs mu > 0, got mu = {rest['mu']}; give -p D=VALUE")
        return rest, val * mu, "T"
    return rest, None, ""


def noise_intensity(D: object, need: str | None = None) -> float:
    """The noise intensity ``D`` of ``x'' + ... = sqrt(2 D) xi(t)`` as a float, checked.

    The one check of ``D`` for every command and function with noise: a finite number
    ``>= 0`` (``D = 0`` is the deterministic model), or ``> 0`` where ``need`` says why the
    noise cannot be zero.  Read as :func:`kbm.parameters.values.parameter_value` reads any
    value (``"0.01"``, ``"1/100"``, ``0.01``).

    Parameters
    ----------
    D : object
        The value as given (a string of the command line or a number).
    need : str, optional
        Why ``D = 0`` is refused (``"without noise nothing escapes the well"``); ``None``:
        ``D = 0`` is accepted.

    Returns
    -------
    float
        ``D``, read exactly and rounded once.

    Raises
    ------
    kbm.errors.ParameterError
        ``"D = VALUE: give the noise intensity of sqrt(2 D) xi as -p D=VALUE with D > 0
        and finite (...)"`` (``D >= 0`` where ``need`` is ``None``) for a value that is no
        number, NaN, infinite, negative, or zero where refused.
    """
    if isinstance(D, float) and math.isfinite(D):  # (numpy's too) the exact read rounds
        value = float(D) + 0.0  # back to the same float (-0.0: 0.0): no sympy (a sweep of
        # 1e5 values took 10 s)
    else:
        try:
            value = float(parameter_value("D", D))
        except ParameterError:
            value = None
    if value is not None and (value > 0 or (value == 0 and need is None)):
        return value
    shown = str(D).strip() if value is None else f"{value:g}"
    rule = ("D >= 0 and finite (D = 0: the deterministic model)" if need is None else
            f"D > 0 and finite ({need}; or the temperature -p T=VALUE > 0, T = D/mu)")
    raise ParameterError(f"D = {shown}: give the noise intensity of sqrt(2 D) xi as "
                         f"-p D=VALUE with {rule}")


#: points of the grid on which a physical axis's map is checked finite and strictly monotone
#: (a pole inside the range, ``k = 2 pi/lam`` over ``lam = -1:1``, breaks one or the other)
MONOTONE_POINTS = 33


def _float(x: float) -> float:
    return float(x)


@dataclass(frozen=True)
class PhysicalAxis:
    """A ``--vary`` range ``user`` over ``[lo, hi]`` computed as the model's own parameter
    ``name`` over ``span`` (increasing).

    ``name = forward(user)`` is the model's ``physical`` map with its other inputs fixed
    (``rule``, e.g. ``delta = Delta/mu``); :meth:`to_user` maps a value of ``name`` back.  When
    ``user`` is the model's own name the axis is the identity (``rule`` empty).  ``monotone``
    says whether the map is finite and strictly monotone on ``[lo, hi]`` (checked on
    :data:`MONOTONE_POINTS` points); a caller refuses the axis otherwise, in its own words,
    and ``span`` and :meth:`to_user` are then meaningless.  ``slope`` is the inverse's
    derivative where the inverse is in closed form (``None`` else).
    """

    user: str
    lo: float
    hi: float
    name: str
    span: tuple[float, float]
    rule: str = ""
    forward: Callable[[float], float] = _float
    inverse: Callable[[float], float] = _float
    monotone: bool = True
    slope: Callable[[float], float] | None = None

    @property
    def mapped(self) -> bool:
        """Whether the axis is computed in another name than the user's."""
        return self.name != self.user

    def to_user(self, s: float) -> float:
        """The value of ``user`` at the value ``s`` of ``name``: the ends of ``span`` give
        ``lo`` and ``hi`` exactly, the rest the inverse map."""
        if not self.mapped:
            return float(s)
        if s == self.forward(self.lo):
            return self.lo
        if s == self.forward(self.hi):
            return self.hi
        return float(self.inverse(s))

    def error(self, s: float, err: float) -> float:
        """An error ``err`` of ``name`` at ``s`` in the units of ``user``: times the
        inverse's derivative ``slope`` (closed form), else its difference quotient over
        ``+-err`` kept inside ``span``."""
        if not self.mapped:
            return err
        if self.slope is not None:
            return abs(float(self.slope(s))) * abs(err)
        h = max(abs(err), 1e-9 * max(1.0, abs(s)))
        a, b = max(s - h, self.span[0]), min(s + h, self.span[1])  # inside the map's domain
        return abs(self.to_user(b) - self.to_user(a)) / (b - a) * abs(err)


def physical_axis(physical: Mapping[str, object], user: str, lo: float, hi: float,
                  fixed: Mapping[str, object]) -> PhysicalAxis:
    """The axis of ``user`` over ``[lo, hi]``: the scaled parameter whose ``physical`` map
    (``{scaled: expression}``, a model's ``physical``) holds ``user``, with the map's other
    inputs at their values in ``fixed`` (read exactly,
    :func:`kbm.parameters.values.parameter_value`); the identity when no map holds ``user``.

    The inverse is the closed form where ``sympy.solve`` gives exactly one and it maps the
    grid's middle value back (``Delta = mu delta``, ``lam = 2 pi/k``: the built-in maps;
    correctly rounded to an ulp or so), else the root of ``forward(x) = s`` on ``[lo, hi]``
    by Brent's method (bracketed there, the map being monotone on it; to ``1e-15 + 4 eps
    |x|``).

    Raises
    ------
    kbm.errors.ParameterError
        If several maps hold ``user``, or an input of its map other than ``user`` is not in
        ``fixed`` (callers check both first, in their command's words).
    """
    import sympy as sp

    lo, hi = float(lo), float(hi)
    maps = {k: sp.sympify(e) for k, e in physical.items()
            if user in {x.name for x in sp.sympify(e).free_symbols}}
    if not maps:
        return PhysicalAxis(user, lo, hi, user, (lo, hi))
    if len(maps) > 1:
        raise ParameterError(f"{user} sets {len(maps)} parameters ({', '.join(sorted(maps))})"
                             f": vary one of them instead")
    (name, expr), = maps.items()
    rule = f"{name} = {sp.sstr(expr)}"
    others = sorted({x.name for x in expr.free_symbols} - {user})
    missing = [o for o in others if fixed.get(o) is None]
    if missing:
        raise ParameterError(f"{rule} needs a value of {missing[0]}: give -p "
                             f"{missing[0]}=VALUE")
    sym, image = sp.Symbol(user), sp.Dummy(name)
    one = expr.subs({sp.Symbol(o): parameter_value(o, fixed[o]) for o in others})
    forward = sp.lambdify(sym, one, "math")
    try:
        solved = sp.solve(sp.Eq(image, one), sym)
    except NotImplementedError:  # no closed form: the bracketed root below
        solved = []
    grid = [lo + (hi - lo) * j / (MONOTONE_POINTS - 1) for j in range(MONOTONE_POINTS)]
    grid[-1] = hi
    try:
        vals = [float(forward(x)) for x in grid]
    except (ZeroDivisionError, ValueError, OverflowError, TypeError):
        vals = [math.nan]
    steps = [b - a for a, b in zip(vals, vals[1:])]
    monotone = all(math.isfinite(v) for v in vals) and bool(steps) and (
        all(d > 0 for d in steps) or all(d < 0 for d in steps))
    span = (min(vals[0], vals[-1]), max(vals[0], vals[-1]))
    inverse = slope = None
    if len(solved) == 1 and monotone:  # kept if it gives back the grid's middle point
        closed = sp.lambdify(image, solved[0], "math")
        mid = MONOTONE_POINTS // 2
        try:
            back = float(closed(vals[mid]))
        except (ZeroDivisionError, ValueError, OverflowError, TypeError):
            back = math.nan
        if abs(back - grid[mid]) <= 1e-9 * (hi - lo):
            inverse = closed
            slope = sp.lambdify(image, sp.diff(solved[0], image), "math")
    if inverse is None:
        def inverse(s: float) -> float:
            from scipy.optimize import brentq

            def gap(x: float) -> float:
                return float(forward(x)) - s

            g_lo, g_hi = gap(lo), gap(hi)
            if g_lo * g_hi > 0:  # s at an end of the span, past it by a rounding, or outside
                ends = [(abs(g), x) for g, x in ((g_lo, lo), (g_hi, hi))
                        if abs(g) <= 8 * 2.0 ** -52 * max(abs(s), *map(abs, span))]
                if ends:
                    return min(ends)[1]
                raise ParameterError(f"{name} = {s:g} is outside [{span[0]:g}, {span[1]:g}], "
                                     f"the range of {rule} over {user} = {lo:g}:{hi:g}")
            return brentq(gap, lo, hi, xtol=1e-15, rtol=4 * 2.0 ** -52)
    return PhysicalAxis(user, lo, hi, name, span, rule,
                        lambda x: float(forward(x)), inverse, monotone, slope)
