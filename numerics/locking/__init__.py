"""Frequency locking: the edges of the locking region of self-excited oscillators, averaged
against true, for a pair (or more) of coupled oscillators and for one oscillator entrained
by a drive.

- :mod:`numerics.locking.mutual`: :func:`~numerics.locking.mutual.locking_region`, the
  locking region of coupled self-excited oscillators (``kbm lock``), averaged against true;
- :mod:`numerics.locking.start`: where ``kbm lock`` starts to follow the locked state,
  and the steps of the following;
- :mod:`numerics.locking.slow_flow`: the averaged slow flow of a coupled system as
  numbers, and Newton on its fixed points (the averaged locked states);
- :mod:`numerics.locking.fold`: the fold of a branch of cycles near a cycle
  (:func:`~numerics.locking.fold.locate_fold`) and the true locking edges there
  (:func:`~numerics.locking.fold.true_edges`), on the one continuation of
  :mod:`numerics.shooting`;
- :mod:`numerics.locking.entrainment`: the entrainment (locking) boundary of a forced
  self-excited oscillator, predicted and true.
"""
