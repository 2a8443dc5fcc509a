"""Coupled oscillators in time: the compiled 2N flow, periodic orbits with 2N multipliers,
and the locking of self-excited oscillators.

- :mod:`numerics.coupled.flow`: :func:`coupled_flow` (state, monodromy, divergence);
- :mod:`numerics.coupled.cycle`: :func:`coupled_cycle`, shooting with Floquet multipliers
  (accepted by the standard of :mod:`numerics.shooting.acceptance`);
- :mod:`numerics.coupled.continuation`: branches in one parameter (the shooting problem and
  its corrector in :mod:`numerics.shooting.branch_problem`, the records in
  :mod:`numerics.shooting.branch_result`); :mod:`numerics.coupled.fold`
  the fold of a branch near a cycle (the true locking edges of
  :mod:`numerics.coupled.locking`);
- :mod:`numerics.coupled.slow_flow`: the averaged slow flow as numbers and Newton on its
  locked states; :mod:`numerics.coupled.lock_start`: the value inside the asked interval
  that ``kbm lock`` follows the locked state from, and a physical name's axis.
"""

from .cycle import CoupledCycle, ForcedCoupledResponse, coupled_cycle, forced_response
from .flow import CoupledFlow, bind_coupled, coupled_flow

__all__ = ["CoupledCycle", "coupled_cycle", "ForcedCoupledResponse", "forced_response", "CoupledFlow", "coupled_flow", "bind_coupled"]
