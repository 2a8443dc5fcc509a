"""Where :func:`numerics.cycles.limit_cycles` starts: the energy-balance predictions and
whether the model is odd-symmetric (:func:`seeds`), kept on disk for the commands (issue 39).

The predictions (:func:`numerics.energy.predict_cycles`: the conservative split, its phase
portrait, the orbits' integrals and the balance's roots) and the symmetry test
(:func:`odd_symmetric`, sympy's ``simplify``) are fixed functions of the bound model, the
order and the source.  Where the command line turns the model cards on
(:func:`numerics.flow.card.use_cards`, ``kbm branch``), they are stored as a record of the
template cache (:mod:`numerics.flow.template_cache`, kind ``seeds``): each predicted
cycle's ``(x_max, period)`` (floats round-trip through JSON exactly) and the symmetry.  A
warm run reads them and imports neither :mod:`numerics.energy` nor ``scipy.integrate``,
``scipy.optimize``, ``scipy.fft``; the full prediction is computed on use only
(:attr:`Seeds.prediction`, a printed ``--all`` list or a failure's description).  The cold
run starts from the record as read back, so both run from the same floats.

The record's name is the SHA-256 of the model's canonical form and its bound values
(:func:`numerics.flow.template_cache.template_key`), the order, and the source of
:mod:`kbm`, :mod:`numerics.flow`, :mod:`numerics.energy` and this module.
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path
from typing import Any, Callable

from numerics._memo import memo

__all__ = ["Seeds", "seeds", "odd_symmetric", "StoredPrediction"]

#: the record kind in the cache folder (``kbm_seeds_KEY.json``)
_KIND = "seeds"


def odd_symmetric(bound: Any) -> bool:
    """Whether ``x -> -x`` maps the model to itself: ``f(-x, -x') = -f(x, x')`` for the
    acceleration at the bound parameter values."""
    import sympy as sp

    from kbm.symbols import x as X, xdot as V

    bound = bound.full() if hasattr(bound, "full") else bound  # a model card's
    f = bound.model.acceleration().subs(bound.subs())
    if f.has(sp.Symbol("t")):
        return False
    return sp.simplify(f.subs({X: -X, V: -V}, simultaneous=True) + f) == 0


class StoredPrediction:
    """A predicted cycle read from the record: its ``amplitude_max`` and ``period`` (what
    the shooting starts from); :meth:`resolve` gives the
    :class:`numerics.energy.PredictedCycle` itself (computing the prediction)."""

    def __init__(self, amplitude_max: float, period: float, index: int,
                 prediction: Callable[[], Any]):
        self.amplitude_max, self.period = float(amplitude_max), float(period)
        self._index, self._prediction = index, prediction

    def resolve(self):
        """The prediction's cycle of the same index (the same floats)."""
        return self._prediction().cycles[self._index]


class Seeds:
    """The starts of :func:`numerics.cycles.limit_cycles`.

    Attributes
    ----------
    cycles : list
        The predicted cycles (each with ``amplitude_max``, ``period``): the
        :class:`numerics.energy.PredictedCycle` objects, or :class:`StoredPrediction`.
    odd : bool
        :func:`odd_symmetric` of the bound model.
    prediction
        The :class:`numerics.energy.EnergyPrediction`, or a function that computes it.
    """

    def __init__(self, cycles: list, odd: bool, prediction: Any):
        self.cycles, self.odd, self.prediction = cycles, bool(odd), prediction


@memo(maxsize=1)
def _source_digest() -> str:
    """The SHA-256 of the source that decides the seeds: :mod:`kbm`, :mod:`numerics.flow`,
    :mod:`numerics.energy` and this module."""
    import kbm

    here = Path(__file__).resolve().parent
    h = hashlib.sha256()
    files = (sorted(Path(kbm.__file__).parent.rglob("*.py"))
             + sorted((here.parent / "flow").glob("*.py"))
             + sorted((here.parent / "energy").glob("*.py")) + [Path(__file__)])
    for path in files:
        h.update(path.read_bytes())
    return h.hexdigest()


def seeds_key(bound: Any, order: int) -> str | None:
    """The record's name for ``bound`` at ``order`` (``None``: no canonical form); for a
    model card's bound model (:class:`numerics.flow.card.CardBound`), named by its card."""
    from numerics.flow.template_cache import _canonical, template_key

    card = getattr(bound, "card", None)
    if isinstance(card, dict):
        text = f"{_KIND}|{int(order)}|card {card.get('key')}|{_source_digest()}"
        return hashlib.sha256(text.encode()).hexdigest()[:32]

    try:
        return template_key(bound.model, f"{_KIND}|{int(order)}|{_canonical(dict(bound.values))}"
                                         f"|{_source_digest()}")
    except TypeError:
        return None


def _predict(bound: Any, order: int, potential: Any):
    from numerics.energy import predict_cycles  # on use: scipy.integrate (issue 39)

    bound = bound.full() if hasattr(bound, "full") else bound  # a card's: the exact values
    return predict_cycles(bound.model, dict(bound.values), order=order, potential=potential)


def seeds(bound: Any, order: int = 1, potential: Any = None) -> Seeds:
    """The predicted cycles and the symmetry of ``bound``: from the stored record where the
    model cards are in use and one is stored, else computed (and, with the cards in use,
    stored and read back)."""
    from numerics.flow.card import _ON

    key = seeds_key(bound, order) if _ON[0] and potential is None else None
    if key is None:
        pred = _predict(bound, order, potential)
        return Seeds(list(pred.cycles), odd_symmetric(bound), pred)
    from numerics.flow.template_cache import FORMAT, read_record, write_record

    made: dict = {}

    def prediction():
        if "pred" not in made:
            made["pred"] = _predict(bound, order, None)
        return made["pred"]

    record = read_record(key, _KIND)
    try:
        return _from_record(record, prediction)
    except (TypeError, KeyError, ValueError):  # missing or damaged: computed, stored
        pass
    pred = prediction()
    record = {"format": FORMAT, "key": key, "odd": odd_symmetric(bound),
              "cycles": [[float(p.amplitude_max), float(p.period)] for p in pred.cycles]}
    record = json.loads(json.dumps(record))  # the record as it is read back
    write_record(key, record, _KIND)
    return _from_record(record, prediction)


def _from_record(record: Any, prediction: Callable[[], Any]) -> Seeds:
    cycles = [StoredPrediction(float(a), float(T), i, prediction)
              for i, (a, T) in enumerate(record["cycles"])]
    if not isinstance(record["odd"], bool):
        raise ValueError("damaged record")
    return Seeds(cycles, record["odd"], prediction)
