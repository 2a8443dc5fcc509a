"""The one shooting and continuation code of :mod:`numerics`, for ``2N``-dimensional flows.

A periodic orbit is a fixed point of the time-``T`` map of a flow in ``2N`` dimensions:
autonomous (``N = 1`` included) with the period unknown and a phase condition on a
section, or forced with the period fixed by the drive.  Every shooting and continuation of
the toolkit is a thin case of the modules here:

- :mod:`numerics.shooting.acceptance`: the one acceptance standard (residual relative to
  the orbit's scale, a Newton correction that tells an orbit from a residual minimum near a
  fold, the trivial multiplier) and the Newton loop it ends;
- :mod:`numerics.shooting.orbit`: :func:`~numerics.shooting.orbit.shoot`, Newton on the
  periodic orbit of a ``2N`` flow (autonomous or forced), and the multipliers and
  amplitudes of the orbit found;
- :mod:`numerics.shooting.arclength`: pseudo-arclength continuation: Keller's corrector on
  a hyperplane, the tangent, the predictor, and :func:`~numerics.shooting.arclength.walk`,
  the one driver of the steps along a branch (the branches of :mod:`numerics.cycles` and
  :mod:`numerics.coupled`, and the approach to a fold).

Its users: :func:`numerics.cycles.limit_cycle`, :func:`numerics.cycles.continue_cycles`,
:func:`numerics.coupled.coupled_cycle`, :func:`numerics.coupled.forced_response`,
:func:`numerics.coupled.continuation.continue_coupled`, :mod:`numerics.coupled.fold`
(``locate_fold``, ``true_edges``) and :func:`numerics.forced.periodic_response`.
"""
