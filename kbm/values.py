"""Parameter values: exact reading of user input, and the read-only mapping models hold."""

from __future__ import annotations

import numbers
from collections.abc import Iterator, Mapping

import sympy as sp

from .errors import NonFiniteError, ParameterError
from .symbols import parse

__all__ = ["FrozenMap", "parameter_value"]


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
