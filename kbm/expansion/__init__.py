"""The KBM expansion: the one recursion, its cases and their results.

- :mod:`~kbm.expansion.recursion`: :func:`~kbm.expansion.recursion.kbm_recursion`, the
  order-by-order loop over any :class:`~kbm.algebra.base.RecursionAlgebra`;
- its exact cases: :mod:`~kbm.expansion.one_dof` (:func:`kbm.derive`, one degree of
  freedom, Bessel sums at any order), :mod:`~kbm.expansion.coupled` (``N`` modes with the
  internal resonances of :mod:`~kbm.expansion.resonance`, forced or not) and
  :mod:`~kbm.expansion.forced` (one oscillator near a resonance with its forcing, or at a
  fixed forcing frequency: the coupled algebra at ``N = 1`` with the forcing angle, its
  result in the resonant phase ``phi``);
- their results: :mod:`~kbm.expansion.result`, :mod:`~kbm.expansion.forced_result`,
  :mod:`~kbm.expansion.coupled_result`;
- :mod:`~kbm.expansion.cost`: the size of an exact expansion, estimated before any work.

The sampled cases of the same recursion (any smooth ``F``) are in :mod:`kbm.backend`.
"""
