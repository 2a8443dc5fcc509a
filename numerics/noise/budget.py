"""The step budget of the noisy runs: one constant for every command (issue 35, "one
constant, one place").

``kbm noise``, ``kbm escape`` and ``kbm friction`` (``--budget``'s default) and ``kbm
spectrum`` (its step limit, :mod:`numerics.spectrum._cost`) refuse a run of more
integration steps than :data:`STEP_BUDGET` before it starts.  It sits here, in the lowest
floor of the noisy code, so that each of them imports the one value.  Before, six places
held a ``2e9`` of their own (``numerics.thermal.stationary.DEFAULT_BUDGET``,
``numerics.thermal.friction.DEFAULT_BUDGET``, ``numerics.spectrum._cost.STEP_LIMIT``, the
``--budget`` option's default, the thermal friction's flags and
``numerics.escape.report.escape_report``'s default) and three help texts "2e9"; the names
stay, bound to this constant, and the help texts print :data:`BUDGET_TEXT`.
"""

from __future__ import annotations

__all__ = ["STEP_BUDGET", "BUDGET_TEXT"]

#: integration steps of one run at most (without ``--budget``)
STEP_BUDGET = 2e9
#: the budget as the options' help prints it ("2e9")
BUDGET_TEXT = f"{STEP_BUDGET:.0e}".replace("e+0", "e")
