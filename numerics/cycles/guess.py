"""Starting guesses for the shooting: the one place where :mod:`numerics.cycles` asks the
analysis.

- :func:`kbm_guess`: the stable cycle of the first-order KBM averaged equations
  with the largest amplitude (:func:`kbm.averaged_rates`), as ``(amplitude,
  period)``; the averaged equations are derived once per model (memoised) and their
  lambdified rates kept on disk with the model templates
  (:mod:`numerics.flow.template_cache`), so a warm run neither derives nor imports
  sympy's printers or scipy; the roots are found by :func:`brentq`, Brent's method
  as :func:`scipy.optimize.brentq` runs it (the same steps, the same floats), ~0.1 ms;
- :func:`energy_cycles`: the cycles of the energy-balance averaging about the
  conservative orbit (:func:`numerics.energy.predict_cycles`, order 1), as ``(x_max,
  period, stable)``, largest first: right where the potential is strong and classical KBM
  fails (the paper's ``Delta = 3``), at ~50-150 ms (one prediction for the stable and
  unstable starts).
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from kbm.errors import KBMError
from kbm.slowflow.roots import amplitude_roots

from numerics._memo import memo

if TYPE_CHECKING:
    from kbm.parameters.bound import BoundModel
    from kbm.model.builtins import Oscillator

__all__ = ["kbm_guess", "energy_cycles", "FirstOrderRates",
           "rates_key"]

#: the record kind and the options of the first-order rates in the template cache
_KIND, _OPTIONS = "rates", "kbm first-order averaged rates|1"


class FirstOrderRates(NamedTuple):
    """The first-order averaged equations as vectorised functions of ``(a, mu, *params)``:
    ``A(a) = mu A_1(a)``, ``dA/da`` and ``omega0 + mu B_1(a)`` (the fields of
    :class:`kbm.AveragedRates` that the guess uses)."""

    params: tuple[str, ...]
    rate: Callable
    slope: Callable
    frequency: Callable


@memo(maxsize=1)
def _kbm_source_digest() -> str:
    """The SHA-256 of the source of :mod:`kbm` (every module: the derivation decides the
    rates) and of this module; part of the record's key (read once a process, ~10 ms)."""
    import kbm

    h = hashlib.sha256()
    for path in sorted(Path(kbm.__file__).parent.rglob("*.py")) + [Path(__file__)]:
        h.update(path.read_bytes())
    return h.hexdigest()


@memo(maxsize=1)
def _guess_digest() -> str:
    """The first 16 hex digits of the SHA-256 of this module's source."""
    return hashlib.sha256(Path(__file__).read_bytes()).hexdigest()[:16]


def rates_key(model: Oscillator) -> str | None:
    """The name of the model's first-order rates in the template cache (``None``: a model
    without a canonical form, whose rates are not stored)."""
    from numerics.flow.template_cache import template_key

    try:
        return template_key(model, f"{_OPTIONS}|{_kbm_source_digest()}")
    except TypeError:
        return None


@memo(maxsize=32)
def _first_order(model: Oscillator) -> FirstOrderRates:
    """The model's first-order rates: from the template cache's record when one is stored,
    else derived (:func:`kbm.derive`, :func:`kbm.averaged_rates`), stored and read back, so
    that a cold and a warm run evaluate the same code."""
    from numerics.flow.template_cache import read_record, write_record

    key = rates_key(model)
    if key is None:  # no canonical form: nothing is stored
        return _derived(model)[0]
    record = read_record(key, _KIND)
    if record is not None:
        try:
            return _from_record(record)
        except Exception:  # noqa: BLE001 - a damaged record is rebuilt, never trusted
            pass
    rates, record = _derived(model, key)
    if record is None:
        return rates
    record = json.loads(json.dumps(record))  # the record as it is read back
    rates = _from_record(record)
    write_record(key, record, _KIND)
    return rates


def _card_rates(bound) -> FirstOrderRates | None:
    """The rates of a model card's bound model (:class:`numerics.flow.card.CardBound`) from
    the record its card names, or ``None`` (then the model is built)."""
    key = getattr(bound, "card", {}).get("rates_key")
    if key is None:
        return None
    from numerics.flow.template_cache import read_record

    record = read_record(key, _KIND)
    if record is None:
        return None
    try:
        return _from_record(record)
    except Exception:  # noqa: BLE001 - a damaged record is rebuilt from the model
        return None


def _derived(model: Oscillator, key: str | None = None) -> tuple[FirstOrderRates, dict | None]:
    """The rates derived now, and their record under ``key`` (``None`` if a function holds an
    infinite sum or a global that cannot be stored)."""
    from kbm import averaged_rates, derive  # imported on use (issue 39)
    from numerics.flow.template_cache import FORMAT, function_record

    r = averaged_rates(derive(model, 1))
    rates = FirstOrderRates(tuple(r.params), r.rate, r.slope, r.frequency)
    funcs = {}
    for name in ("rate", "slope", "frequency"):
        fn = getattr(r, name)
        rec = None if key is None or getattr(fn, "has_sums", True) else \
            function_record(fn.lambdified)
        if rec is None:
            return rates, None
        funcs[name] = rec
    return rates, {"format": FORMAT, "key": key, "params": list(rates.params),
                   "functions": funcs}


def _from_record(record) -> FirstOrderRates:
    from kbm.output.evaluate import vectorised
    from numerics.flow.template_cache import function_from_record

    params = tuple(record["params"])
    names = ("a", "mu", *params)
    return FirstOrderRates(params, *(vectorised(function_from_record(
        record["functions"][f]), names) for f in ("rate", "slope", "frequency")))


def _cycles(rates: FirstOrderRates, m: float, pars: list[float], *, a_max: float = 20.0,
            n_grid: int = 4000) -> list[tuple[float, float, bool]]:
    """``(amplitude, period, stable)`` of the cycles ``0 < a* <= a_max``, as
    :meth:`kbm.AveragedRates.cycles` finds them (sign changes of ``A(a)/a`` on the grid,
    Brent's method to ``1e-14``; roots where ``omega0 + mu B_1 <= 0`` left out)."""
    f, df, phase = rates.rate, rates.slope, rates.frequency
    roots = amplitude_roots(f, m, pars, a_max=a_max, n_grid=n_grid)
    out = []
    for root in roots:
        slope = float(df(root, m, *pars))
        omega = float(phase(root, m, *pars))
        if omega > 0:
            out.append((float(root), 2 * np.pi / omega, slope < 0))
    return out


def kbm_guess(bound: BoundModel, *, stable: bool = True) -> tuple[float, float] | None:
    """The stable (``stable=False``: unstable) first-order KBM cycle with the largest
    amplitude, as ``(amplitude, period)``.

    ``None`` when the averaging does not apply to the model, a value is missing,
    or the first-order averaged equation has no cycle of that stability.

    A model card's bound model (:class:`numerics.flow.card.CardBound`) keeps the answer in
    its card once found (``guess_stable_DIGEST``, ``DIGEST`` of this module's source): a warm run reads the two
    floats and evaluates no rates (whose functions may need :mod:`scipy.special`, e.g.
    SEDF's Bessel ``jv``; issue 39).
    """
    card = getattr(bound, "card", None)
    # the card's key covers kbm/ and numerics/flow/; this module's source names the entry
    name = f"guess_{'stable' if stable else 'unstable'}_{_guess_digest()}"
    if isinstance(card, dict) and name in card:
        kept = card[name]
        if kept is None or (isinstance(kept, list) and len(kept) == 2):
            return None if kept is None else (float(kept[0]), float(kept[1]))
    found = _kbm_guess(bound, stable)
    if isinstance(card, dict) and isinstance(card.get("key"), str):
        from numerics.flow.card import update_card

        update_card(card["key"], **{name: None if found is None else list(found)})
    return found


def _kbm_guess(bound, stable: bool) -> tuple[float, float] | None:
    """:func:`kbm_guess` from the rates."""
    try:
        vals = bound.values
        rates = _card_rates(bound) or _first_order(bound.model)
        if any(p not in vals for p in rates.params) or "mu" not in vals:
            return None
        cycles = [c for c in _cycles(rates, float(vals["mu"]),
                                     [float(vals[p]) for p in rates.params])
                  if c[2] == stable]
    except (KBMError, ArithmeticError, ValueError):
        return None
    if not cycles:
        return None
    amplitude, period, _ = max(cycles, key=lambda c: c[0])
    return amplitude, period


def energy_cycles(bound: BoundModel) -> list[tuple[float, float, bool]]:
    """Every first-order energy-balance cycle as ``(x_max, period, stable)``, largest
    ``x_max`` first (the shooting's starts take the stable and the unstable ones from one
    prediction); empty when the model cannot be split into a confining conservative part
    and a perturbation, or has no cycle (:func:`numerics.energy.predict_cycles`)."""
    from numerics.energy import predict_cycles  # imported on use: scipy.integrate (issue 39)

    bound = bound.full() if hasattr(bound, "full") else bound  # a model card's: the model

    try:
        pred = predict_cycles(bound.model, dict(bound.values), order=1)
    except (KBMError, ArithmeticError, ValueError):  # no guess: the transients still run
        return []
    cycles = sorted(pred.cycles, key=lambda c: -abs(c.amplitude_max))
    return [(c.amplitude_max, c.period, bool(c.stable)) for c in cycles]
