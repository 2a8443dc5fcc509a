"""The one JSON layer of results (both packages): :func:`finite`, strict JSON (NaN and
infinities as ``null``, also the command line's JSON output) and :func:`strict_text`, its
text as every command and file writes it; :class:`Rendered`, a result
whose ``to_json`` is declared by a layout of its attributes; :func:`json_fields` and
:func:`jsonable`, the same rules for a ``to_json`` that adds computed keys;
:func:`complex_json` and :func:`complex_pairs`, complex numbers (multipliers, eigenvalues)."""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from dataclasses import fields
from typing import Any, ClassVar

__all__ = ["finite", "strict_text", "json_fields", "jsonable", "Rendered", "complex_json", "complex_pairs"]


def finite(obj: Any) -> Any:
    """``obj`` with every non-finite float replaced by ``None`` (dicts, lists, tuples walked).

    Examples
    --------
    >>> finite({"a": [1.0, float("nan")], "b": float("inf")})
    {'a': [1.0, None], 'b': None}
    """
    if isinstance(obj, dict):
        return {k: finite(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [finite(v) for v in obj]
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def strict_text(obj: Any) -> str:
    """``obj`` as the toolkit writes JSON (printed or to a file): :func:`finite`, strict
    (``allow_nan=False``), indented by 2, keys in their order as built, ending in a newline
    (tests/test_strict_json.py)."""
    return json.dumps(finite(obj), indent=2, allow_nan=False) + "\n"


def complex_json(z: complex) -> float | list[float]:
    """A complex number in JSON: a real one a number, else ``[re, im]``.

    Examples
    --------
    >>> complex_json(0.5 + 0j), complex_json(0.5 - 2j)
    (0.5, [0.5, -2.0])
    """
    return float(z.real) if z.imag == 0 else [float(z.real), float(z.imag)]


def complex_pairs(zs: Any) -> list[list[float]]:
    """Complex numbers as ``[re, im]`` pairs, a real one too (eigenvalues, multipliers)."""
    return [[float(z.real), float(z.imag)] for z in zs]


def _value(value: Any, as_given: bool) -> Any:
    """``value``'s JSON form: a result (anything with ``to_json()``) as its JSON; a mapping
    as floats by sorted key, or, ``as_given``, in its order (keys as strings) with values by
    these rules; a tuple or list as a list; a numpy array or scalar as plain lists and
    numbers; a complex number by :func:`complex_json`; anything else as it is."""
    if hasattr(value, "to_json"):
        return value.to_json()
    if isinstance(value, Mapping):
        if as_given:
            return {str(k): _value(v, True) for k, v in value.items()}
        return {k: float(v) for k, v in sorted(value.items())}
    if isinstance(value, (tuple, list)):
        return [_value(v, as_given) for v in value]
    if isinstance(value, complex):
        return complex_json(value)
    if hasattr(value, "tolist"):  # numpy (not imported here)
        return value.tolist()
    return value


def jsonable(value: Any) -> Any:
    """``value`` in plain JSON types by the rules of :class:`Rendered` with mappings as given
    (keys as strings), NaN and infinities as ``null``.

    Examples
    --------
    >>> jsonable({1: (0.5, float("nan")), "z": [1j]})
    {'1': [0.5, None], 'z': [[0.0, 1.0]]}
    """
    return finite(_value(value, True))


class Rendered:
    """A result whose JSON form is declared: the attributes :attr:`layout` names, in that
    order (an empty layout: every dataclass field), NaN and infinities as ``null``.

    A nested result is rendered by its ``to_json``, a tuple or list as a list, numpy arrays
    and scalars as plain lists and numbers, a complex number by :func:`complex_json`, a
    mapping as floats by sorted key or, with :attr:`mappings_as_given`, in its order (keys as
    strings) with its values by these rules.

    Examples
    --------
    >>> from dataclasses import dataclass
    >>> @dataclass
    ... class Fold(Rendered):
    ...     parameter: float
    ...     multipliers: tuple
    ...     params: dict
    ...     layout = ("multipliers", "parameter", "params")
    >>> Fold(float("nan"), (1 + 0j, 0.5 + 0.1j), {"mu": 1, "beta": 2}).to_json()
    {'multipliers': [1.0, [0.5, 0.1]], 'parameter': None, 'params': {'beta': 2.0, 'mu': 1.0}}
    """

    layout: ClassVar[tuple[str, ...]] = ()
    #: mappings rendered in their order with their values as they are (``dict(params)``),
    #: rather than as floats by sorted key
    mappings_as_given: ClassVar[bool] = False

    def to_json(self) -> dict:
        """The attributes of :attr:`layout` (NaN and infinities as ``null``)."""
        names = self.layout or tuple(f.name for f in fields(self))
        return finite({k: _value(getattr(self, k), self.mappings_as_given) for k in names})


def json_fields(obj: Any, *names: str, **extra: Any) -> dict:
    """``{name: obj.name}`` for ``names`` in their order (default: every dataclass field of
    ``obj``), each in its JSON form (the rules of :class:`Rendered` with mappings as given:
    results by their ``to_json``, tuples as lists, numpy arrays as nested lists), then the
    keys of ``extra`` (non-finite numbers kept).

    Examples
    --------
    >>> from dataclasses import dataclass
    >>> @dataclass
    ... class Point:
    ...     x: float
    ...     window: tuple
    >>> json_fields(Point(1.0, (0, 2)))
    {'x': 1.0, 'window': [0, 2]}
    >>> json_fields(Point(1.0, (0, 2)), "window", note="ok")
    {'window': [0, 2], 'note': 'ok'}
    """
    names = names or tuple(f.name for f in fields(obj))
    return {**{n: _value(getattr(obj, n), True) for n in names}, **extra}
