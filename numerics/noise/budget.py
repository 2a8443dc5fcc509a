"""The step budget of the noisy runs: one constant for every command (issue 35, "one
constant, one place").

``kbm noise``, ``kbm escape`` and ``kbm friction`` (``--budget``'s default) and ``kbm
spectrum`` (its step limit, :mod:`numerics.spectrum._cost`) refuse a run of more
integration steps than :data:`STEP_BUDGET` before it starts.  It sits here, in the lowest
floor of the noisy code, so that each of them imports the one value (before, four modules
each held a ``2e9`` of their own: ``numerics.thermal.stationary.DEFAULT_BUDGET``,
``numerics.thermal.friction.DEFAULT_BUDGET``, ``numerics.spectrum._cost.STEP_LIMIT`` and
the ``--budget`` option; those names stay, bound to this constant).
"""

from __future__ import annotations

__all__ = ["STEP_BUDGET"]

#: integration steps of one run at most (without ``--budget``)
STEP_BUDGET = 2e9
