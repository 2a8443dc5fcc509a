"""The model family: ``x_i'' + omega_i^2 x_i = mu F_i(x, x', theta) + drive_i(t)``, ``i = 1..N``.

One type, :class:`~kbm.model.coupled.CoupledOscillators`; one degree of freedom, forced or
not, are its cases (:mod:`kbm.model.family` says how).

- :mod:`~kbm.model.family`: the family and :func:`~kbm.model.family.one_degree_form`;
- :mod:`~kbm.model.coupled`: :class:`~kbm.model.coupled.CoupledOscillators`, the one type;
  its symbols ``x_i, xdot_i, a_i, psi_i`` in :mod:`~kbm.model.variables`, the exact
  non-rational constants of ``F`` in :mod:`~kbm.model.constants`;
- :mod:`~kbm.model.oscillator`: :class:`~kbm.model.oscillator.Oscillator`, one degree of
  freedom; :mod:`~kbm.model.forced`: :class:`~kbm.model.forced.ForcedOscillator` and
  :class:`~kbm.model.forced.Resonance`, with the admissibility checks of
  :mod:`~kbm.model.forced_checks`;
- the built-ins: :mod:`~kbm.model.builtins` (one degree of freedom),
  :mod:`~kbm.model.forced_builtins`, :mod:`~kbm.model.coupled_builtins`; a user's ``F``:
  :mod:`~kbm.model.user_model`;
- :mod:`~kbm.model.smooth_terms`: the terms of ``F`` that are not smooth;
  :mod:`~kbm.model.conservative`: an oscillator split into a conservative force and a small
  damping.
"""
