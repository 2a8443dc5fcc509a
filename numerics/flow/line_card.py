"""Line cards: a built-in model bound along one parameter, kept on disk (issue 39), so that
a warm ``kbm branch`` neither builds the symbolic model nor imports sympy.

:class:`numerics.flow.compiled.CompiledLine` binds a model once along the varied
parameter (:class:`kbm.parameters.bound.ParameterLine`) and converts per value only what changes.
What it reads of the symbolic model is a fixed function of the built-in name, the values
as given, the varied name and the start value: the template (its record in
:mod:`numerics.flow.template_cache`), the float values, the names that change, the
derived scaled values as exact rational expressions (``delta = Delta/mu``), their rates
(lambdified), whether the values are affine in the parameter, whether the field is odd,
and the keys of the compiled flows (the extended flow, the nine-state flow with the
Newton corrector).  A line card holds these; :class:`CardLine` answers as the
:class:`kbm.parameters.bound.ParameterLine` did (the exact values by the same code,
:func:`kbm.parameters.rational_values.line_floats`, on the same expression trees: the same floats).

Cards are read and written only where :func:`numerics.flow.card.use_cards` turns them on
(``kbm branch``); the name is the model card's key (:func:`numerics.flow.card.card_key`:
the format, the source of :mod:`kbm` and :mod:`numerics.flow`, sympy's version, the name
and the values as given) with the varied name and the start value.  A card is written
after the line was bound (refused input is never in a card) and only where the exact path
needs no sympy per value (rational values and expressions, a linear frequency that does
not change); anything a card does not hold builds the line on use (:meth:`CardLine.full`).
"""

from __future__ import annotations

import hashlib
from collections.abc import Callable, Mapping
from fractions import Fraction
from typing import Any

from kbm.parameters.rational_values import line_floats, line_rates

__all__ = ["compiled_line", "source_digest", "line_key", "read_line", "write_line", "CardLine", "remember"]

#: version of the line card's layout (part of the key)
FORMAT = "1"

#: the record kind in the cache folder (``kbm_line_KEY.json``)
_KIND = "line"


def compiled_line(model: object, params: Mapping[str, object] | None, vary: str, at: float):
    """:class:`numerics.flow.compiled.CompiledLine` of ``model`` along ``vary`` from ``at``:
    from its line card where the cards are in use and one is stored (no sympy), else built
    (and its card stored where the cards are in use).  The same values either way."""
    from numerics.flow.compiled import CompiledLine

    key = line_key(model, params, vary, at)
    card = read_line(key)
    if card is not None:
        line = _from_card(card, model, params, vary, at)
        if line is not None:
            line.card_key = key
            return line
    line = CompiledLine(model, params, vary, at)
    line.card_key = key
    write_line(key, line)
    return line


def _from_card(card: Mapping, model, params, vary: str, at: float):
    """The :class:`numerics.flow.compiled.CompiledLine` of a line card (its attributes set
    as ``__init__`` sets them from the symbolic line), or ``None`` if the card or its
    template's record is damaged (then the line is built)."""
    from numerics.flow.card import CardTemplate
    from numerics.flow.compiled import CompiledLine
    from numerics.flow.template import model_template
    from numerics.flow.template_cache import read_record

    def build():
        from kbm.parameters.bound import ParameterLine

        return ParameterLine(model, params, vary, at)

    try:
        line = CardLine(card, build)
        template = CardTemplate(card, read_record(card["template_key"]),
                                lambda: model_template(line.full().base.model))
        floats = {k: float(card["fvals"][k]) for k in template.names}
        autonomous = bool(card["autonomous"])
        odd = card.get("odd")
    except Exception:  # noqa: BLE001 - a damaged card: the line is built anew
        return None
    out = CompiledLine.__new__(CompiledLine)
    out.line, out.template, out._floats, out._autonomous = line, template, floats, autonomous
    out._recent = {}
    out.card_key, out.odd = None, odd if isinstance(odd, bool) else None
    return out


def source_digest(*paths: str) -> str:
    """The SHA-256 of the source files ``paths`` (relative to the project's folder): what a
    record decides besides :mod:`kbm` and :mod:`numerics.flow` (the model card's key)."""
    from pathlib import Path

    root = Path(__file__).resolve().parents[2]
    h = hashlib.sha256()
    for rel in paths:
        h.update((root / rel).read_bytes())
    return h.hexdigest()


def line_key(model: object, params: Mapping[str, object] | None, vary: str,
             at: float) -> str | None:
    """The line card's name, or ``None`` (no card: cards off, a model object, other value
    types)."""
    from numerics.flow.card import card_key

    if not isinstance(vary, str) or type(at) not in (int, float):
        return None
    key = card_key(model, params)
    if key is None:
        return None
    # the odd field is decided by the continuation's problem (numerics/shooting/planar.py)
    code = source_digest("numerics/shooting/planar.py")
    return hashlib.sha256(f"{FORMAT}|{key}|{code}|{vary!r}|{at!r}".encode()).hexdigest()[:32]


def read_line(key: str | None) -> dict | None:
    """The stored line card of ``key`` (``None``: none, unreadable or another format)."""
    if key is None:
        return None
    from numerics.flow.template_cache import read_record

    record = read_record(key, _KIND)
    return record if record is not None and record.get("line") == FORMAT else None


def write_line(key: str | None, cline: Any) -> None:
    """Store the card of ``cline`` (a :class:`numerics.flow.compiled.CompiledLine` built
    from the symbolic model) under ``key``; nothing where the line needs sympy per value or
    a function or the template cannot be stored."""
    if key is None:
        return
    import sympy as sp

    from numerics.flow.card import template_fields
    from numerics.flow.template_cache import function_record, write_record

    line, template = cline.line, cline.template
    if line._slow or line._w0 is not None or line._fractions is None:
        return
    common = template_fields(key, template)
    if common is None:
        return
    rates = {}
    for scaled, f, need in line._rates:
        rec = function_record(f)
        if rec is None:
            return
        rates[scaled] = {"need": list(need), "function": rec}
    ext = sp.srepr(tuple(template.ext_exprs))
    record = {
        **common, "line": FORMAT, "name": line.base.name, "vary": line.vary,
        "fvals": dict(cline._floats), "autonomous": bool(cline._autonomous),
        "changed": list(line.changed), "direct": bool(line._direct),
        "derived": [[scaled, tree] for scaled, tree in line._trees],
        "fractions": {n: [v.numerator, v.denominator] for n, v in line._fractions.items()},
        "given": {k: float(v) for k, v in line._given.items()},
        "rates": rates, "affine": bool(line.affine),
        "sensitivity_key": f"sensitivity-9|{ext}|{template.names}"}
    write_record(key, record, _KIND)


def remember(key: str | None, **more: object) -> None:
    """Add ``more`` entries (``odd``: the field is odd) to a stored line card."""
    from numerics.flow.template_cache import update_record

    update_record(key, more, _KIND, lambda record: record.get("line") == FORMAT)


class _CardBase:
    """The bound model at the start value as a line card knows it: ``name``, float
    ``values``; the :class:`kbm.parameters.bound.BoundModel` itself on use."""

    def __init__(self, name: str, values: Mapping[str, float], full: Callable[[], Any]):
        self.name, self.values, self._full = name, dict(values), full

    def __getattr__(self, name: str):
        if name.startswith("_"):
            raise AttributeError(name)
        return getattr(self._full().base, name)


class CardLine:
    """A :class:`kbm.parameters.bound.ParameterLine` read from a line card: :meth:`floats`,
    :meth:`rates`, ``affine``, ``changed``, ``vary`` and ``base`` without sympy; anything
    else (a value bound exactly, :meth:`__call__`) from the line built on use
    (:meth:`full`)."""

    def __init__(self, record: Mapping, build: Callable[[], Any]):
        from numerics.flow.template_cache import function_from_record

        self.vary = str(record["vary"])
        self.changed = tuple(record["changed"])
        self.affine = bool(record["affine"])
        self._direct = bool(record["direct"])
        self._derived = [(str(s), list(t)) for s, t in record["derived"]]
        self._fractions = {n: Fraction(int(p), int(q)) for n, (p, q) in
                           record["fractions"].items()}
        self._given = {k: float(v) for k, v in record["given"].items()}
        self._rates = [(s, function_from_record(r["function"]), tuple(r["need"]))
                       for s, r in record["rates"].items()]
        self._build = build
        self.base = _CardBase(str(record["name"]), record["fvals"], self.full)

    def full(self):
        """The :class:`kbm.parameters.bound.ParameterLine` itself (imports sympy)."""
        if "_line" not in self.__dict__:
            self._line = self._build()
        return self._line

    def floats(self, value: float) -> dict[str, float]:
        """As :meth:`kbm.parameters.bound.ParameterLine.floats`: the float values of
        :attr:`changed` (the same code, :func:`kbm.parameters.rational_values.line_floats`, on the
        card's trees); an undefined value raises the symbolic line's message."""
        return line_floats(self.vary, value, self._fractions, self._direct, self._derived,
                           lambda _: self.full().floats(value))[0]

    def rates(self, value: float) -> dict[str, float]:
        """As :meth:`kbm.parameters.bound.ParameterLine.rates` (the same code,
        :func:`kbm.parameters.rational_values.line_rates`)."""
        return line_rates(self.vary, value, self._given, self._direct, self._rates)

    def __call__(self, value: float):
        """The model bound at ``vary = value`` (builds the line: sympy)."""
        return self.full()(value)

    def __getattr__(self, name: str):
        if name.startswith("_"):
            raise AttributeError(name)
        return getattr(self.full(), name)
