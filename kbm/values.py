"""Parameter values: exact reading of user input, the read-only mapping models hold, and the
physical names of a model turned into its scaled ones (:func:`scaled_values`)."""

from __future__ import annotations

import numbers
from collections.abc import Iterator, Mapping

import sympy as sp

from .errors import NonFiniteError, ParameterError
from .symbols import parse

__all__ = ["FrozenMap", "parameter_value", "scaled_values"]


class FrozenMap(Mapping):
    """A read-only, hashable mapping (items kept in the order given).

    Used for the mappings held by frozen model objects, so that an
    :class:`Oscillator` or a :class:`BoundModel` can be a dictionary key.
    """

    __slots__ = ("_items", "_dict")

    def __init__(self, items: Mapping | None = None):
        d = dict(items or {})
        object.__setattr__(self, "_dict", d)
        object.__setattr__(self, "_items", tuple(d.items()))

    def __getitem__(self, key):
        return self._dict[key]

    def __iter__(self) -> Iterator:
        return iter(self._dict)

    def __len__(self) -> int:
        return len(self._dict)

    def __hash__(self) -> int:
        return hash(frozenset(self._items))

    def __eq__(self, other) -> bool:
        return isinstance(other, Mapping) and dict(self._items) == dict(other.items())

    def __repr__(self) -> str:
        return f"FrozenMap({self._dict!r})"

    def __setattr__(self, name, value):
        raise AttributeError("FrozenMap is read-only")

    def __reduce__(self):
        return (FrozenMap, (self._dict,))


def parameter_value(name: str, raw: object) -> sp.Expr:
    """Read a parameter value exactly: ``"0.1"`` and ``0.1`` both give ``1/10``."""
    try:
        if isinstance(raw, numbers.Real) and not isinstance(raw, (int, sp.Basic)):
            raw = float(raw)  # also numpy floats
            val = sp.Rational(repr(raw)) if raw == raw and abs(raw) != float("inf") else sp.nan
        elif isinstance(raw, str):
            try:
                val = sp.Rational(raw.strip())
            except ZeroDivisionError:
                val = sp.nan  # "1/0": refused below as not finite
            except (TypeError, ValueError):
                try:
                    val = parse(raw)
                except NonFiniteError:
                    val = sp.nan  # refused below as not finite
        else:  # numbers and sympy objects only: strict, never through str()
            val = sp.sympify(raw, strict=True)
    except Exception as exc:  # noqa: BLE001 - reported with the name
        raise ParameterError(f"parameter {name}: cannot read the value {raw!r} ({exc})") from None
    if not (isinstance(val, sp.Expr) and val.is_number and val.is_real and val.is_finite):
        raise ParameterError(f"parameter {name} must be a finite real number, got {raw!r}")
    return val


def scaled_values(model, values: Mapping[str, object] | None = None, *,
                  use_defaults: bool = True) -> dict[str, sp.Expr]:
    """Exact values of a model's own (scaled) parameters and ``mu`` from the given ones:
    the physical names converted by the model's ``physical`` map (``delta = Delta/mu``,
    which needs ``mu``), the defaults filled in.  The bound form of every member of the
    family (:meth:`kbm.coupled.CoupledOscillators.resolve`, :func:`kbm.bound.bind`).

    Raises
    ------
    kbm.errors.ParameterError
        For an unknown name, a value that is not a finite number, a scaled and a physical
        value of the same parameter, or a physical one without ``mu``.
    """
    values = dict(values or {})
    physical = dict(model.physical)
    phys_names = sorted({s.name for e in physical.values() for s in e.free_symbols}
                        - {"mu"})
    names = set(model.parameters) | {"mu"}
    unknown = sorted(set(values) - names - set(phys_names))
    if unknown:
        extra = f"; or the physical {', '.join(phys_names)}" if phys_names else ""
        raise ParameterError(f"{', '.join(map(repr, unknown))} is not a parameter of "
                             f"{model.name!r} (its parameters: {', '.join(sorted(names))}"
                             f"{extra})")
    given = {k: parameter_value(k, v) for k, v in values.items()}
    for scaled, expr in physical.items():  # e.g. delta = Delta/mu from Delta and mu
        needs = {s.name for s in expr.free_symbols}
        if scaled in given:
            if needs & (set(given) - {"mu"}):
                raise ParameterError(f"give either {scaled} or "
                                     f"{', '.join(sorted(needs - {'mu'}))}, not both")
            continue
        if needs - {"mu"} and needs - {"mu"} <= set(given) | set(model.defaults):
            vals = {sp.Symbol(n): given.get(n, model.defaults.get(n)) for n in needs}
            if any(v is None for v in vals.values()):
                raise ParameterError(f"{scaled} = {expr} needs a value of mu "
                                     "(-p mu=VALUE)")
            given[scaled] = sp.sympify(expr).subs(vals)
    out = {k: v for k, v in given.items() if k in names}
    if use_defaults:
        for name, v in model.defaults.items():
            if name in names:
                out.setdefault(name, sp.sympify(v))
    return out

