"""Two-parameter bifurcation diagrams (issue 38): codim-1 curves continued, codim-2 points
located, averaged curves beside the true ones.

- :mod:`numerics.bifurcation.result`: :class:`Curve`, :class:`Codim2Point`,
  :class:`Diagram` (the JSON contract and the figure);
- :mod:`numerics.bifurcation.curve`: :func:`continue_curve`, pseudo-arclength continuation
  of a curve of zeros of ``G: R^(n+1) -> R^n`` (converged points, step control, bounds,
  test functions and their zeros, progress, store and resume;
  :mod:`~numerics.bifurcation.corrector`: its bordered Newton corrector and tangent);
- :mod:`numerics.bifurcation.path`: the records of a path (:class:`PathPoint`,
  :class:`TestEvent`, :class:`CurvePath`);
- :mod:`numerics.bifurcation.oned`: the diagram of an autonomous one-degree-of-freedom
  model (:mod:`~numerics.bifurcation.run`: its run state and shared geometry;
  :mod:`~numerics.bifurcation.autonomous`: the defining systems;
  :mod:`~numerics.bifurcation.connections`: homoclinic and heteroclinic curves;
  :mod:`~numerics.bifurcation.saddle_node_loop`: their ends on folds of equilibria;
  :mod:`~numerics.bifurcation.cycle_folds`: folds of cycles;
  :mod:`~numerics.bifurcation.hopf_folds`: the fold of small cycles into its Bautin point;
  :mod:`~numerics.bifurcation.averaged`: the averaged curves;
  :mod:`~numerics.bifurcation.store`: the paths kept for resume);
- :mod:`numerics.bifurcation.forced`: the fold, period-doubling and Neimark–Sacker curves
  of a forced oscillator's periodic responses (cusp, Bogdanov–Takens, strong resonances),
  the slow flow's curves at orders 1–3 beside them
  (:mod:`numerics.bifurcation.forced_averaged`);
- :mod:`numerics.bifurcation.coupled`: the locking tongue of coupled self-excited
  oscillators as the fold curves of the locked cycle, and the averaged tongue;
- :mod:`numerics.bifurcation.twoway`: what these two share (a curve continued both ways
  from its seed, codim-2 points named and merged, true-to-averaged distances).
"""

from kbm._lazy import lazy_names

_LAZY = {
    **dict.fromkeys(("Curve", "Codim2Point", "Diagram"), "numerics.bifurcation.result"),
    **dict.fromkeys(("continue_curve", "CurvePath", "PathPoint", "TestEvent"),
                    "numerics.bifurcation.curve"),
}

__getattr__, __dir__ = lazy_names(__name__, globals(), _LAZY)

__all__ = ["Curve", "Codim2Point", "Diagram", "continue_curve", "CurvePath", "PathPoint",
           "TestEvent"]
