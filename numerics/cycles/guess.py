"""Starting guesses for the shooting: the one place where :mod:`numerics.cycles` asks the engine.

:func:`kbm_guess` is the stable cycle of the first-order KBM averaged equations
with the largest amplitude (:func:`kbm.averaged_rates`), as ``(amplitude,
period)``.  The averaged equations are derived once per model (memoised).
"""

from __future__ import annotations

from kbm import AveragedRates, averaged_rates, derive
from kbm.errors import KBMError
from kbm.models import BoundModel, Oscillator

from numerics._memo import memo

__all__ = ["kbm_guess"]


@memo(maxsize=32)
def _first_order(model: Oscillator) -> AveragedRates:
    return averaged_rates(derive(model, 1))


def kbm_guess(bound: BoundModel) -> tuple[float, float] | None:
    """The stable first-order KBM cycle with the largest amplitude, as ``(amplitude, period)``.

    ``None`` when the averaging does not apply to the model, a value is missing,
    or the first-order averaged equation has no stable cycle.
    """
    try:
        vals = bound.values
        rates = _first_order(bound.model)
        need = {p: vals[p] for p in rates.params if p in vals}
        if len(need) != len(rates.params) or "mu" not in vals:
            return None
        cycles = [c for c in rates.cycles({"mu": vals["mu"], **need}) if c.stable]
    except KBMError:
        return None
    if not cycles:
        return None
    c = max(cycles, key=lambda c: c.amplitude)
    return c.amplitude, c.period
