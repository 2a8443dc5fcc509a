"""Floor 2 of :mod:`numerics`: true limit cycles.

- :mod:`numerics.cycles.result`: :class:`LimitCycle`, :class:`Dissipation`;
- :mod:`numerics.cycles.transient`: settling on a cycle from a start;
- :mod:`numerics.cycles.guess`: starting guesses from the averaged equations
  (classical KBM and the energy balance about the conservative orbit);
- :mod:`numerics.cycles.shooting`: :func:`limit_cycle` (Newton on the return map,
  Floquet multipliers, dissipation per cycle) and :func:`limit_cycles` (every
  predicted cycle, stable and unstable, confirmed by shooting), built on
  :mod:`numerics.cycles.newton` (Newton's method and its checks) and
  :mod:`numerics.cycles.finalpass` (the result and its accuracy estimate);
- :mod:`numerics.cycles.acceptance`: the one acceptance standard of every shooting
  (residual relative to the orbit's scale, a small Newton correction, the trivial
  multiplier) and the Newton loop it ends, shared with :mod:`numerics.coupled` and
  :mod:`numerics.forced`;
- :mod:`numerics.cycles.harmonics`: Fourier coefficients by quadrature along the
  integration (no aliasing of the jumps of relaxation cycles);
- :mod:`numerics.cycles.highprec`: cycles to 30 digits and more (mpmath Taylor);
- :mod:`numerics.cycles.sweep`: many cycles on all cores;
- :mod:`numerics.cycles.floquet`: the non-trivial Floquet multiplier from Liouville's
  formula (right at any stiffness);
- :mod:`numerics.cycles.continuation`: branches of cycles in one parameter
  (:func:`continue_cycles`: pseudo-arclength, folds, Hopf and homoclinic ends;
  results in :mod:`numerics.cycles.branch_result`).
"""

from numerics.cycles.branch_result import Branch, BranchPoint, SpecialPoint
from numerics.cycles.continuation import continue_cycles
from numerics.cycles.floquet import floquet_multipliers, nontrivial_multiplier
from numerics.cycles.highprec import limit_cycle_mp
from numerics.cycles.result import Dissipation, LimitCycle
from numerics.cycles.shooting import CycleList, limit_cycle, limit_cycles
from numerics.cycles.sweep import SweepPoint, grid, sweep
from numerics.cycles.transient import transient

__all__ = ["LimitCycle", "Dissipation", "limit_cycle", "limit_cycles", "CycleList",
           "limit_cycle_mp", "transient",
           "sweep", "grid", "SweepPoint", "continue_cycles", "Branch", "BranchPoint",
           "SpecialPoint", "floquet_multipliers", "nontrivial_multiplier"]
