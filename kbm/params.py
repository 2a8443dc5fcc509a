"""The names of a model's parameters, physical and scaled, and the noise ``D`` or ``T = D/mu``.

One place answers, for every model and command, which parameter names are valid and how
the physical ones of the paper map to the scaled ones the engines use (eqs. 3 and 12):
``delta = Delta/mu`` and ``k = 2 pi/lam``, and back, ``Delta = mu delta`` and
``lam = 2 pi/k``.  Where noise ``sqrt(2 D) xi`` applies, its intensity may be given as
``D`` or as the temperature ``T = kT = D/mu`` of a linearly damped oscillator
(fluctuation-dissipation, Kubo 1966: ``<x'^2> = kT`` for unit mass).

:class:`ParameterNames` is what a command checks the user's names against
(:meth:`ParameterNames.check`), and :func:`scaled_values` the one binding layer of every
model (both defined in :mod:`kbm.values`, below the model types, and re-exported here); :func:`lookup` finds a built-in model of any kind by name
(the one-degree-of-freedom, forced and coupled ones) with a message that lists them all.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping

from typing import TYPE_CHECKING

from .errors import ModelError, ParameterError
from .values import (NOISE_NAMES, ParameterNames, closest, parameter_value,
                     scaled_values)

if TYPE_CHECKING:
    import sympy as sp

__all__ = ["NOISE_NAMES", "ParameterNames", "names_of", "lookup", "builtin_names",
           "to_physical", "noise_from", "closest", "scaled_values"]

def _members(name: str):
    """The built-in of any kind called ``name``, or ``None``."""
    from .models import MODELS, get_model

    if name in MODELS:
        return get_model(name)
    from .coupled.builtins import get_coupled_model, is_coupled_name
    from .forced.builtins import FORCED_MODELS, get_forced_model

    if name in FORCED_MODELS:
        return get_forced_model(name)
    if is_coupled_name(name):
        return get_coupled_model(name)
    return None


def builtin_names(kinds: Iterable[str] = ("one", "forced", "coupled")) -> dict[str, list[str]]:
    """The built-in model names by kind: ``one`` degree of freedom, ``forced``, ``coupled``."""
    from .coupled.builtins import coupled_model_names
    from .forced.builtins import FORCED_MODELS
    from .models import MODELS

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
    from .models import MODELS

    kinds = tuple(kinds)
    found = _members(name)
    if "one" in kinds and name in MODELS:  # before the other catalogues, which import
        return found                       # slowly (0.26 s: issue 39)
    table = builtin_names(kinds)
    ok = found is not None and any(
        name in table[k] or (k == "coupled" and name.startswith("sedf-chain-"))
        for k in kinds)
    if ok:
        return found
    every = [n for k in kinds for n in table[k]]
    near = closest(name, every)
    lists = "; ".join(f"{_KIND_WORDS[k]}: {', '.join(table[k])}" for k in kinds)
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


def noise_from(values: Mapping[str, object]) -> tuple[dict[str, object], sp.Expr | None, str]:
    """``(values without the noise, D, the name given)`` from ``D`` or ``T = D/mu``.

    ``D`` is ``None`` when neither is given, and as given (unread) when given as ``D``;
    ``T`` is read here, and needs ``mu > 0`` (the temperature of the linear damping
    ``mu x'``).

    Raises
    ------
    kbm.errors.ParameterError
        For both given, a negative ``T`` (named ``T``), or ``T`` without ``mu > 0``.
    """
    rest = dict(values)
    if "D" in rest and "T" in rest:
        raise ParameterError("give the noise as D or as T = D/mu, not both")
    if "D" in rest:  # read and checked where it is used (its own messages)
        return rest, rest.pop("D"), "D"
    if "T" in rest:
        raw = rest.pop("T")
        val = parameter_value("T", raw)
        if val < 0:
            raise ParameterError(f"T = {raw} is negative; the temperature kT = D/mu must be "
                                 "finite and >= 0 (T = 0 is the deterministic model)")
        if "mu" not in rest:
            raise ParameterError("T = D/mu needs mu: give -p mu=VALUE, or the noise as "
                                 "-p D=VALUE")
        mu = parameter_value("mu", rest["mu"])
        if not mu > 0:
            raise ParameterError(f"T = D/mu is the temperature of the damping mu x' and "
                                 f"needs mu > 0, got mu = {rest['mu']}; give -p D=VALUE")
        return rest, val * mu, "T"
    return rest, None, ""

