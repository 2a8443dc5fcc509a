"""The step budget of the noisy runs: one constant for every command (issue 35, "one
constant, one place").

``kbm noise``, ``kbm escape`` and ``kbm friction`` (``--budget``'s default) and ``kbm
spectrum`` (its step limit, :mod:`numerics.spectrum._cost`) refuse a run of more
integration steps than :data:`STEP_BUDGET` before it starts.  It sits here, in the lowest
floor of the noisy code, so that each of them imports the one value (before, six places
held a ``2e9`` of their own and three help texts "2e9"); the help texts print
:data:`BUDGET_TEXT`.  The cost
budgets of the Fokker-Planck solves (``--fp-budget``'s defaults) sit here too, so that
the command line prints them without importing the solvers.
"""

from __future__ import annotations

__all__ = ["STEP_BUDGET", "BUDGET_TEXT", "FP_BUDGET", "FP_DEFAULT_BUDGET", "ESCAPE_FP_BUDGET"]

#: integration steps of one run at most (without ``--budget``)
STEP_BUDGET = 2e9
#: the budget as the options' help prints it ("2e9")
BUDGET_TEXT = f"{STEP_BUDGET:.0e}".replace("e+0", "e")

#: the largest cost ``n_Hermite n_Chebyshev^2`` of the stationary Kramers solve of
#: ``kbm noise`` (:func:`numerics.thermal._kramers_outputs.fokker_planck_moments`;
#: ``n_Hermite (n_Chebyshev/2)^2`` for a model solved folded, :mod:`numerics.fokker_planck._parity`): the SEDF at rest,
#: Delta = 3, D = mu/2, states six digits there (mu = 0.1: 1.1e-8 on 128 x 448, 3 s CPU;
#: mu = 0.02: 5.4e-7 on 182 x 740, 10 s; mu = 0.01: 2.9e-7 on 258 x 1040, 26-32 s, the
#: climb up to 2.8 times this budget, numerics.fokker_planck._stationary_orthonormal)
FP_BUDGET = 2.5e7
#: the same without ``--method fokker-planck`` (the moments are reported when affordable)
FP_DEFAULT_BUDGET = 2.5e7
#: the largest cost of the escape rate's Kramers solves
#: (:func:`numerics.fokker_planck.kramers_escape`'s ``max_cost``, ``kbm escape --fp-budget``)
ESCAPE_FP_BUDGET = 3e7
