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
  locator of folds and other special points between two points of a branch;
  :mod:`numerics.shooting.special`: the period doublings and Neimark-Sacker points of a
  branch of forced responses located by it.

Its cases for ``N`` coupled oscillators (the flow of :mod:`numerics.flow.coupled_flow`) and
for one forced oscillator (the flow of :mod:`numerics.flow.forced_system`):

- :mod:`numerics.shooting.coupled_orbit`: :func:`~numerics.shooting.coupled_orbit.coupled_cycle`
  and :func:`~numerics.shooting.coupled_orbit.forced_response`, the periodic orbits of ``N``
  coupled oscillators with all ``2N`` Floquet multipliers;
- :mod:`numerics.shooting.coupled_branch`: their branches in one parameter
  (:func:`~numerics.shooting.coupled_branch.continue_coupled`, ``kbm branch`` and
  ``kbm response`` of ``N`` degrees of freedom);
- :mod:`numerics.shooting.forced_orbit`: the response of a forced oscillator at the fixed
  period ``2 pi p/nu`` (:func:`~numerics.shooting.forced_orbit.periodic_response`);
- :mod:`numerics.shooting.forced_branch`: its frequency-response curve continued in the
  detuning (:func:`~numerics.shooting.forced_branch.numeric_response`).
"""
