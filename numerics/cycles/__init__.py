"""Floor 2 of :mod:`numerics`: true limit cycles.

- :mod:`numerics.cycles.result`: :class:`LimitCycle`, :class:`Dissipation`;
- :mod:`numerics.cycles.transient`: settling on a cycle from a start;
- :mod:`numerics.cycles.guess`: starting guesses from the averaged equations
  (classical KBM and the energy balance about the conservative orbit);
- :mod:`numerics.cycles.shooting`: :func:`limit_cycle` (Newton on the return map,
  Floquet multipliers, dissipation per cycle), built on :mod:`numerics.cycles.newton`
  (the case ``N = 1`` of the one shooting, :mod:`numerics.shooting.orbit`, and its
  checks) and :mod:`numerics.cycles.finalpass` (the result and its accuracy estimate);
- :mod:`numerics.cycles.every_cycle`: :func:`limit_cycles` (every predicted cycle, stable
  and unstable, confirmed by shooting), started from :mod:`numerics.cycles.seeds` (the
  predictions and the symmetry, kept on disk for the commands);
- :mod:`numerics.cycles.harmonics`: Fourier coefficients by quadrature along the
  integration (no aliasing of the jumps of relaxation cycles);
- :mod:`numerics.cycles.highprec`: cycles to 30 digits and more (mpmath Taylor);
- :mod:`numerics.cycles.sweep`: many cycles on all cores;
- ``floquet_multipliers``, ``nontrivial_multiplier`` (:mod:`numerics.shooting.floquet`):
  the non-trivial Floquet multiplier from Liouville's formula (right at any stiffness);
- :mod:`numerics.cycles.continuation`: branches of cycles in one parameter
  (:func:`continue_cycles`: the case ``N = 1`` of the one driver,
  :mod:`numerics.shooting.continuation`, with folds, Hopf and homoclinic ends; the
  shooting problem of a branch in :mod:`numerics.shooting.planar`, results in
  :mod:`numerics.shooting.branch_result`; Brent's bounded minimiser and a Gauss--Legendre rule
  without scipy in :mod:`numerics.cycles.localmin`).
"""

from kbm._lazy import keep_objects, lazy_names

#: the public names, each imported from its module on first use (PEP 562): ``kbm cycle``
#: imports the shooting, not the continuation, the sweeps or mpmath (issue 39)
_LAZY = {
    **dict.fromkeys(("Branch", "BranchPoint", "SpecialPoint"), "numerics.shooting.branch_result"),
    "continue_cycles": "numerics.cycles.continuation",
    **dict.fromkeys(("floquet_multipliers", "nontrivial_multiplier"), "numerics.shooting.floquet"),
    "limit_cycle_mp": "numerics.cycles.highprec",
    **dict.fromkeys(("Dissipation", "LimitCycle"), "numerics.cycles.result"),
    **dict.fromkeys(("CycleList", "limit_cycles"), "numerics.cycles.every_cycle"),
    "limit_cycle": "numerics.cycles.shooting",
    **dict.fromkeys(("SweepPoint", "grid", "sweep"), "numerics.cycles.sweep"),
    "transient": "numerics.cycles.transient",
}

#: ``numerics.cycles.sweep`` and ``.transient`` are the functions, also once the modules of
#: the same names are imported (as when ``__init__`` imported them eagerly)
keep_objects(__name__, ("sweep", "transient"))

__getattr__, __dir__ = lazy_names(__name__, globals(), _LAZY)

__all__ = ["LimitCycle", "Dissipation", "limit_cycle", "limit_cycles", "CycleList",
           "limit_cycle_mp", "transient",
           "sweep", "grid", "SweepPoint", "continue_cycles", "Branch", "BranchPoint",
           "SpecialPoint", "floquet_multipliers", "nontrivial_multiplier"]
