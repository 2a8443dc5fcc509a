"""Short text for result objects: the ``__repr__`` a user sees in a shell or notebook
(a line like the command line's, never the sample arrays)."""

from __future__ import annotations

import math
from collections.abc import Mapping

__all__ = ["params_text", "num", "cell", "html_table", "multipliers_text"]


def num(value: object, digits: int = 10) -> str:
    """A float in ``digits`` significant digits (``nan`` as is), complex as ``a+bj``."""
    if isinstance(value, complex):
        return f"{value.real:.{digits}g}{value.imag:+.{digits}g}j" if value.imag else \
            num(value.real, digits)
    try:
        v = float(value)
    except (TypeError, ValueError):
        return str(value)
    return "nan" if math.isnan(v) else f"{v:.{digits}g}"


def cell(value: float | None, fmt: str) -> str:
    """A table cell: ``value`` in ``fmt``, or ``--`` where it is ``None`` (the JSON's
    ``null``: no simulation, no gap)."""
    return "--" if value is None else format(value, fmt)


def multipliers_text(values, digits: int = 6) -> str:
    """Floquet multipliers as the command line prints them: ``0.5, -0.1+0.2i`` (``digits``
    significant digits; a real one without its zero imaginary part)."""
    return ", ".join(f"{z.real:.{digits}g}" + (f"{z.imag:+.{digits}g}i" if z.imag else "")
                     for z in values)


def params_text(params: Mapping[str, object], limit: int = 6) -> str:
    """``mu=0.1, Delta=1.5, ...`` (at most ``limit`` names)."""
    items = [f"{k}={num(v, 6)}" for k, v in list(params.items())[:limit]]
    if len(params) > limit:
        items.append("...")
    return ", ".join(items)


def html_table(title: str, rows: list[tuple[str, str]]) -> str:
    """A two-column HTML table for a notebook's ``_repr_html_``."""
    from html import escape

    body = "".join(f"<tr><th style='text-align:left'>{escape(k)}</th><td>{escape(v)}</td></tr>"
                   for k, v in rows)
    return f"<table><caption>{escape(title)}</caption>{body}</table>"
