"""Starting guesses for the shooting: the one place where :mod:`numerics.cycles` asks the
analysis.

- :func:`kbm_guess`: the stable cycle of the first-order KBM averaged equations
  with the largest amplitude (:func:`kbm.averaged_rates`), as ``(amplitude,
  period)``; the averaged equations are derived once per model (memoised), so
  this costs ~0.1 ms;
- :func:`energy_guesses`: the stable cycles of the energy-balance averaging about
  the conservative orbit (:func:`numerics.energy.predict_cycles`, order 1), as
  ``(x_max, period)``, largest first: right where the potential is strong and
  classical KBM fails (the paper's ``Delta = 3``), at ~50-150 ms.
"""

from __future__ import annotations

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
    """
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
