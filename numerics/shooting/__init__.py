"""The one shooting and continuation code of :mod:`numerics`, for ``2N``-dimensional flows
(``N = 1`` and forcing are cases: autonomous with the period unknown and a phase condition,
or forced with the period fixed by the drive).

- :mod:`numerics.shooting.acceptance`: the one acceptance standard and its Newton loop;
- :mod:`numerics.shooting.orbit`: :func:`~numerics.shooting.orbit.shoot`, Newton on a
  periodic orbit, and the multipliers of the orbit found;
- :mod:`numerics.shooting.arclength`: pseudo-arclength continuation: the corrector, the
  tangent, the predictor and :func:`~numerics.shooting.arclength.walk`, the one driver of
  the steps along a branch;
- :mod:`numerics.shooting.branch_problem`: the one branch problem (corrector, steps, the
  point at a parameter) and its case for any ``N``;
- :mod:`numerics.shooting.continuation`: the one continuation driver of a branch, and
  :mod:`numerics.shooting.branch_result`, the one branch result and its two JSON layouts;
- :mod:`numerics.shooting.planar`: its case ``N = 1`` with the section eliminated, the
  parameter sensitivity, half-period shooting and the compiled corrector;
- :mod:`numerics.shooting.floquet`: the multipliers of a planar cycle (Liouville);
- :mod:`numerics.shooting.locate`: :func:`~numerics.shooting.locate.locate_zero`, the one
  locator of folds and other special points between two points of a branch.
"""
