"""What is done with a slow flow: its cycles, steady states, series and continuation.

- :mod:`~kbm.slowflow.averaged`: limit cycles of the averaged equations;
  :mod:`~kbm.slowflow.roots`: the roots of ``A(a) = 0`` without sympy or scipy;
- series of the limit cycle in ``mu``: :mod:`~kbm.slowflow.series` (exact),
  :mod:`~kbm.slowflow.numeric_series` (floating point, high order),
  :mod:`~kbm.slowflow.cycle_series` (Lindstedt-Poincare on the cycle), and their
  resummation, :mod:`~kbm.slowflow.resum`;
- the forced slow flow: :mod:`~kbm.slowflow.steady` (fixed points, stability, response
  curves, folds), :mod:`~kbm.slowflow.resultant` (every fixed point by resultants),
  :mod:`~kbm.slowflow.tongues` (transition curves of parametric resonance);
- continuation: :mod:`~kbm.slowflow.continuation` (pseudo-arclength for ``G(u) = 0``) on
  the toolkit's one driver, :mod:`~kbm.slowflow.arclength`.
"""
