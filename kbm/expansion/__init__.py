"""The KBM expansion: the one recursion, its cases and their results.

- :mod:`~kbm.expansion.recursion`: :func:`~kbm.expansion.recursion.kbm_recursion`, the
  order-by-order loop over any :class:`~kbm.algebra.base.RecursionAlgebra`;
- its exact cases: :mod:`~kbm.expansion.one_dof` (:func:`kbm.derive`, one degree of
  freedom), :mod:`~kbm.expansion.forced` (a forcing angle near a resonance),
  :mod:`~kbm.expansion.coupled` (``N`` modes with the internal resonances of
  :mod:`~kbm.expansion.resonance`);
- their results: :mod:`~kbm.expansion.result`, :mod:`~kbm.expansion.forced_result`,
  :mod:`~kbm.expansion.coupled_result`;
- :mod:`~kbm.expansion.cost`: the size of an exact expansion, estimated before any work.

The sampled cases of the same recursion (any smooth ``F``) are in :mod:`kbm.backend`.
"""
