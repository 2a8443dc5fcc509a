"""Strict JSON from results: NaN and infinities become ``null`` (shared by every ``to_json``
of both packages and by the command line's JSON output), and :func:`json_fields`, the
field dump a result's ``to_json`` is made of."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import fields
from typing import Any

__all__ = ["finite", "json_fields"]


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


def _plain(value: Any) -> Any:
    """A field's JSON form, one level deep: a mapping as a dict, a tuple as a list, a numpy
    array as nested lists; anything else as it is."""
    if isinstance(value, Mapping):
        return dict(value)
    if isinstance(value, tuple):
        return list(value)
    if getattr(value, "ndim", 0):  # a numpy array (numpy is not imported here)
        return value.tolist()
    return value


def json_fields(obj: Any, *names: str, **extra: Any) -> dict:
    """``{name: obj.name}`` for ``names`` in their order (default: every dataclass field of
    ``obj``), each in its JSON form (mappings as dicts, tuples as lists, numpy arrays as
    nested lists), then the keys of ``extra``.

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
    return {**{n: _plain(getattr(obj, n)) for n in names}, **extra}
