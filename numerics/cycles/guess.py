"""Starting guesses for the shooting: the one place where :mod:`numerics.cycles` asks the
analysis.

- :func:`kbm_guess`: the stable cycle of the first-order KBM averaged equations
  with the largest amplitude (:func:`kbm.averaged_rates`), as ``(amplitude,
  period)``; the averaged equations are derived once per model (memoised), so
  this costs ~0.1 ms; the guess is also kept on disk (:func:`numerics.flow.jit.cache_dir`)
  under the SHA-256 of the model's canonical form and the parameter values, so that a
  warm ``kbm cycle`` neither derives nor imports scipy's root finder (issue 39);
- :func:`energy_guesses`: the stable cycles of the energy-balance averaging about
  the conservative orbit (:func:`numerics.energy.predict_cycles`, order 1), as
  ``(x_max, period)``, largest first: right where the potential is strong and
  classical KBM fails (the paper's ``Delta = 3``), at ~50-150 ms.
"""

from __future__ import annotations

import hashlib
import json
import os
import sys
from collections.abc import Mapping
from dataclasses import fields, is_dataclass
from typing import TYPE_CHECKING

from kbm.errors import KBMError

from numerics._memo import memo

if TYPE_CHECKING:
    from kbm import AveragedRates
    from kbm.bound import BoundModel
    from kbm.models import Oscillator

__all__ = ["kbm_guess", "energy_guesses"]


@memo(maxsize=32)
def _first_order(model: Oscillator) -> AveragedRates:
    from kbm import averaged_rates, derive  # imported on use (issue 39)

    return averaged_rates(derive(model, 1))


def kbm_guess(bound: BoundModel, *, stable: bool = True) -> tuple[float, float] | None:
    """The stable (``stable=False``: unstable) first-order KBM cycle with the largest
    amplitude, as ``(amplitude, period)``.

    ``None`` when the averaging does not apply to the model, a value is missing,
    or the first-order averaged equation has no cycle of that stability.

    The first call of a process reads the guess from the cache folder when it is there (it
    was computed by this function from the same model and values and stored as the exact
    floats: the cache changes the time, never the result) and stores it otherwise.  Once
    :mod:`scipy.optimize` is imported the saving is gone, and the guess is computed.
    """
    if _root_finder_imported():
        return _kbm_guess(bound, stable)
    path = _guess_path(bound, stable)
    try:
        stored = json.loads(path.read_text())
        if stored["key"] == path.stem:
            return None if stored["guess"] is None else tuple(stored["guess"])
    except (OSError, ValueError, KeyError, TypeError):
        pass
    guess = _kbm_guess(bound, stable)
    try:
        tmp = path.with_suffix(f".{os.getpid()}.tmp")
        tmp.write_text(json.dumps({"key": path.stem, "guess": guess}))
        os.replace(tmp, path)
    except OSError:
        pass  # an unwritable cache costs time only
    return guess


def _root_finder_imported() -> bool:
    """Whether :mod:`scipy.optimize` (the averaged cycles' root finder) is imported."""
    return "scipy.optimize" in sys.modules


#: version of the stored guesses (part of their key)
_GUESS_VERSION = "1"


def _canonical(value: object) -> str:
    """A canonical text of a model's field: ``srepr`` of sympy objects, recursively through
    mappings, sequences and dataclasses; ``repr`` of anything else."""
    import sympy as sp

    if isinstance(value, sp.Basic):
        return sp.srepr(value)
    if isinstance(value, Mapping):
        items = sorted((_canonical(k), _canonical(v)) for k, v in value.items())
        return "{" + ",".join(f"{k}:{v}" for k, v in items) + "}"
    if isinstance(value, (tuple, list)):
        return "(" + ",".join(_canonical(v) for v in value) + ")"
    if is_dataclass(value) and not isinstance(value, type):
        return (f"{type(value).__qualname__}("
                + ",".join(f"{f.name}={_canonical(getattr(value, f.name))}"
                           for f in fields(value)) + ")")
    return repr(value)


def _guess_path(bound: BoundModel, stable: bool):
    """Where the guess of ``bound`` is stored: the SHA-256 of the model's canonical form,
    its parameter values and the stability sought."""
    from numerics.flow.jit import cache_dir

    text = (f"{_GUESS_VERSION}|{stable}|{_canonical(bound.model)}|"
            f"{_canonical(dict(bound.values))}")
    return cache_dir() / f"kbm_guess_{hashlib.sha256(text.encode()).hexdigest()[:24]}.json"


def _kbm_guess(bound: BoundModel, stable: bool) -> tuple[float, float] | None:
    """:func:`kbm_guess` computed: the first-order averaged rates and their cycles."""
    try:
        vals = bound.values
        rates = _first_order(bound.model)
        need = {p: vals[p] for p in rates.params if p in vals}
        if len(need) != len(rates.params) or "mu" not in vals:
            return None
        cycles = [c for c in rates.cycles({"mu": vals["mu"], **need}) if c.stable == stable]
    except (KBMError, ArithmeticError, ValueError):
        return None
    if not cycles:
        return None
    c = max(cycles, key=lambda c: c.amplitude)
    return c.amplitude, c.period


def energy_guesses(bound: BoundModel, *, stable_only: bool = True) -> list[tuple[float, float]]:
    """The first-order energy-balance cycles as ``(x_max, period)``, largest ``x_max`` first.

    Empty when the model cannot be split into a confining conservative part and a
    perturbation, or has no cycle (:func:`numerics.energy.predict_cycles`).
    """
    from numerics.energy import predict_cycles  # imported on use: scipy.integrate (issue 39)

    try:
        pred = predict_cycles(bound.model, dict(bound.values), order=1)
    except (KBMError, ArithmeticError, ValueError):  # no guess: the transients still run
        return []
    cycles = [c for c in pred.cycles if c.stable or not stable_only]
    cycles.sort(key=lambda c: -abs(c.amplitude_max))
    return [(c.amplitude_max, c.period) for c in cycles]
