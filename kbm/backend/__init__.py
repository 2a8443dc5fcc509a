"""The numeric backend: the one recursion on samples, for any smooth ``F``.

- :mod:`~kbm.backend.sampled`: the one sampled backend of one degree of freedom, forced or
  not (the grid algebra :mod:`kbm.algebra.grid`), and
  :mod:`~kbm.backend.sampling`, what the sampled backends share (input, resolution);
- its cases: :mod:`~kbm.backend.one_dof` (:func:`kbm.numeric_derive`),
  :mod:`~kbm.backend.forced` with its result :mod:`~kbm.backend.forced_result`, and
  :mod:`~kbm.backend.functions`, callable results;
- any ``N`` (the jets of :mod:`kbm.algebra.coupled_jets`): :mod:`~kbm.backend.jets`, any
  order at one point of the amplitudes, evaluated at given amplitudes for one degree of
  freedom by :mod:`~kbm.backend.pointwise` (:func:`kbm.derive_values`), and
  :mod:`~kbm.backend.coupled`, the first order on an amplitude grid.
"""
