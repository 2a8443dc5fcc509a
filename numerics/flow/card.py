"""Model cards: what a numerical command needs of a bound built-in model, kept on disk
(issue 39), so that a warm run neither builds the symbolic model nor imports sympy.

A card holds, for one built-in name and one set of parameter values as given: the model's
name, the float values of its parameters in the template's order (and of every bound value,
from :func:`kbm.parameters.values.scaled_values` by way of :func:`kbm.parameters.bound.bind`), the
key of its template's record (:mod:`numerics.flow.template_cache`), the keys of its compiled flows
(the extended flow, the harmonics' quadrature), whether it is autonomous and whether its
acceleration holds ``mu`` (``mu = 0``: conservative), and what the commands add (the key of
the first-order rates, the text of the parameters).  Its name is the SHA-256 of the format,
the name, the values as given, the source of :mod:`kbm` and :mod:`numerics.flow` and
sympy's version (:func:`card_key`).

Cards are used where :func:`use_cards` turns them on (``kbm cycle`` does).  A card is
written only after the model was bound and compiled (so input that is refused is
never in a card, and gives the same message on every run); a warm run reads it and builds a
:class:`numerics.flow.compiled.CompiledModel` from the template's stored functions
(:class:`CardTemplate`).  Whatever needs the symbolic model (a flow not built ahead of
time, the high-precision integrator, the energy-balance guess) builds it on use
(:meth:`CardTemplate.full`, :meth:`CardBound.full`), with sympy; the numbers are the same.
"""

from __future__ import annotations

import hashlib
import importlib.util
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

from numerics._memo import memo

__all__ = ["use_cards", "card_key", "card_model", "name_model", "model_of", "read_card",
           "write_card", "update_card", "template_fields", "CardTemplate", "CardBound",
           "FORMAT"]

#: version of the card's layout (part of the key)
FORMAT = "1"

#: the record kind in the cache folder (``kbm_card_KEY.json``)
_KIND = "card"

#: whether cards are read and written in this process (:func:`use_cards`: the command line
#: turns them on; a library sweep over thousands of values writes none)
_ON = [False]


def use_cards(on: bool = True) -> None:
    """Read and write model cards in this process (``kbm cycle`` turns them on)."""
    _ON[0] = bool(on)


@memo(maxsize=1)
def _digest() -> str:
    """The SHA-256 of the source of :mod:`kbm` and :mod:`numerics.flow` and of sympy's
    version (read from its installed metadata's folder name, without importing it)."""
    import kbm

    h = hashlib.sha256()
    here = Path(__file__).parent
    for path in sorted(Path(kbm.__file__).parent.rglob("*.py")) + sorted(here.glob("*.py")):
        h.update(path.read_bytes())
    spec = importlib.util.find_spec("sympy")
    if spec is not None and spec.origin:
        site = Path(spec.origin).parent.parent
        h.update(" ".join(sorted(p.name for p in site.glob("sympy-*.dist-info"))).encode())
    return h.hexdigest()


#: the specs of the models built from one (``--rhs``) in this process, by the model's id
_SPECS: dict[int, tuple] = {}


def name_model(model: object, spec: tuple) -> None:
    """Card ``model`` (built by :func:`kbm.model.user_model.custom_model` from ``spec``,
    ``("--rhs", RHS, OMEGA0)``) under its spec."""
    _SPECS[id(model)] = (model, spec)


def model_of(spec: object) -> object:
    """What :func:`kbm.parameters.bound.bind` takes for a card's spec: a built-in name as it is,
    the model of ``("--rhs", RHS, OMEGA0)`` built (with sympy)."""
    if isinstance(spec, tuple):
        from kbm.model.user_model import custom_model

        return custom_model(spec[1], omega0=spec[2])
    return spec


def _spec(name: object) -> object:
    """A built-in name, or the spec of a model named by :func:`name_model`, or ``None``."""
    if isinstance(name, str):
        return name
    if isinstance(name, tuple) and len(name) == 3 and name[0] == "--rhs" and \
            isinstance(name[1], str) and type(name[2]) in (str, int, float):
        return name
    known = _SPECS.get(id(name))
    return known[1] if known is not None and known[0] is name else None


def card_key(name: object, params: Mapping[str, object] | None) -> str | None:
    """The card's name for a built-in ``name`` (or a spec ``("--rhs", RHS, OMEGA0)``, or a
    model named by :func:`name_model`) and ``params`` as given (strings, ints or floats),
    or ``None`` where there is no card (another model object, other value types, cards
    not in use: :func:`use_cards`)."""
    name = _spec(name) if _ON[0] else None
    if name is None:
        return None
    items = []
    for k, v in (params or {}).items():
        if type(v) not in (str, int, float) or not isinstance(k, str):
            return None
        items.append((k, type(v).__name__, repr(v)))
    text = f"{FORMAT}|{_digest()}|{name!r}|{sorted(items)!r}"
    return hashlib.sha256(text.encode()).hexdigest()[:32]


def read_card(key: str | None) -> dict | None:
    """The stored card of ``key`` (``None``: no key, missing or unreadable)."""
    if key is None:
        return None
    from numerics.flow.template_cache import read_record

    return read_record(key, _KIND)


def write_card(key: str | None, bound: Any, cm: Any, **more: object) -> None:
    """Store the card of ``bound`` (a :class:`kbm.parameters.bound.BoundModel`) and ``cm`` (its
    :class:`numerics.flow.compiled.CompiledModel`) under ``key``, with ``more`` entries;
    nothing where the template's record is not stored (its functions cannot be kept)."""
    if key is None:
        return
    import sympy as sp

    from numerics.flow.template_cache import write_record

    template = cm.template
    common = template_fields(key, template)
    if common is None:
        return
    record = {**common, "card": FORMAT, "name": cm.name,
              "values": {k: float(v) for k, v in bound.values.items()},
              "fvals": dict(cm.values), "autonomous": bool(cm.autonomous),
              "has_mu": bool(template.model.acceleration().has(sp.Symbol("mu"))), **more}
    write_record(key, record, _KIND)


def template_fields(key: str, template: Any) -> dict | None:
    """The entries of a model or line card stored under ``key`` that its symbolic
    ``template`` decides (the record's format and key, the template's key and names, the
    extended flow's key, the acceleration), or ``None`` where the template's record is not
    stored (its functions cannot be kept: no card)."""
    import sympy as sp

    from numerics.flow.template_cache import FORMAT as RECORD, read_record, template_key

    try:
        tkey = template_key(template.model)
    except TypeError:
        return None
    if read_record(tkey) is None:
        return None
    return {"format": RECORD, "key": key, "template_key": tkey, "names": list(template.names),
            "flow_key": f"extended|{sp.srepr(tuple(template.ext_exprs))}|{template.names}",
            "acc_srepr": sp.srepr(template.model.acceleration())}


def update_card(key: str | None, **more: object) -> None:
    """Add ``more`` entries to a stored card (nothing if there is none)."""
    from numerics.flow.template_cache import update_record

    update_record(key, more, _KIND)


class CardTemplate:
    """A :class:`numerics.flow.compiled.ModelTemplate` read from a card: its numerical
    functions from the template's record, its symbolic fields (``model``,
    ``dissipation_expr``, ``ext_exprs``, ``ext_symbols``) built on use (:meth:`full`)."""

    def __init__(self, card: Mapping, record: Mapping, rebuild: Callable[[], Any]):
        from numerics.flow.template_cache import function_from_record

        self.names = tuple(record["names"])
        if self.names != tuple(card["names"]):
            raise ValueError("the card and the template's record disagree")
        for f in ("f_ext", "f_acc", "f_jac", "f_energy", "f_w0", "f_factor"):
            setattr(self, f, function_from_record(record["functions"][f]))
        self.flow_key, self.acc_srepr = str(card["flow_key"]), str(card["acc_srepr"])
        #: the key of the nine-state flow with the Newton corrector (a line card's)
        self.sensitivity_key = card.get("sensitivity_key")
        self._rebuild = rebuild

    def full(self):
        """The template built from the symbolic model (imports sympy)."""
        if "_full" not in self.__dict__:
            self._full = self._rebuild()
        return self._full

    def cached_flow(self, key: str | None = None):
        """The extended flow (or the flow cached under ``key``) built ahead of time, without
        sympy or numba, or ``None`` (:func:`numerics.flow.jit.cached_flow`)."""
        from numerics.flow.jit import cached_flow

        return cached_flow(self.flow_key if key is None else key)

    def __getattr__(self, name: str):
        if name in ("model", "dissipation_expr", "ext_exprs", "ext_symbols") and \
                "_rebuild" in self.__dict__:
            return getattr(self.full(), name)
        raise AttributeError(name)


class CardBound:
    """A bound model read from a card: its ``name``, float ``values`` and ``has_mu``; the
    :class:`kbm.parameters.bound.BoundModel` itself built on use (:meth:`full`)."""

    def __init__(self, card: Mapping, rebuild: Callable[[], Any]):
        self.name = str(card["name"])
        self.values = {k: float(v) for k, v in card["values"].items()}
        self.has_mu = bool(card["has_mu"])
        self.card = card
        self._rebuild = rebuild

    @property
    def model(self):
        """The symbolic model (imports sympy)."""
        return self.full().model

    def full(self):
        """The :class:`kbm.parameters.bound.BoundModel` (imports sympy)."""
        if "_full" not in self.__dict__:
            self._full = self._rebuild()
        return self._full


def card_model(name: object, params: Mapping[str, object] | None):
    """``(bound, compiled)`` of a built-in model (or a spec, :func:`card_key`) from its
    card, or ``None`` (no card, or its
    template's record is missing or damaged: then the caller binds and compiles)."""
    key = card_key(name, params)
    card = read_card(key)
    if card is None or card.get("card") != FORMAT:
        return None
    from numerics.flow.compiled import _assemble
    from numerics.flow.template_cache import read_record

    def bind_now():
        from kbm.parameters.bound import bind

        return bind(model_of(name), params)

    def template_now():
        from numerics.flow.template import model_template

        return model_template(bind_now().model)

    try:
        record = read_record(card["template_key"])
        template = CardTemplate(card, record, template_now)
        bound = CardBound(card, bind_now)
        fvals = {k: float(card["fvals"][k]) for k in template.names}
        cm = _assemble(bind_now, bound.name, template, fvals, bool(card["autonomous"]))
    except Exception:  # noqa: BLE001 - a damaged card or record: bound and compiled anew
        return None
    return bound, cm
