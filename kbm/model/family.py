"""The one model type: ``x_i'' + omega_i^2 x_i = mu F_i(x, x', theta) + drive_i(t)``, ``i = 1..N``.

Every model of the package is an instance of one type,
:class:`kbm.model.coupled.CoupledOscillators` (:mod:`kbm.model.coupled`), which holds the data:
the right-hand sides ``F_i``, the frequencies ``omega_i``, the forcing angle ``theta = nu
t`` (``nu = nu0 + mu sigma``, with hard forcings ``K_i cos(theta)``), the stage drive, the
physical parametrisation and the defaults.  The number ``N`` of degrees of freedom
(``dof``), the forcing (``forced``) and the stage drive (``drives``) are properties of an
instance, not types.  The cases of one degree of freedom are subclasses that keep the
names of one degree of freedom (``F`` in ``x``, ``xdot``; ``omega0``, ``drive``, ``hard``
scalars), so that the ~200 places that read them, and the byte-stable derivations, are
unchanged:

- :class:`~kbm.model.oscillator.Oscillator`: ``dof`` 1, not forced; its engine
  :func:`kbm.derive` (Bessel sums, any order);
- :class:`~kbm.model.forced.ForcedOscillator`: ``dof`` 1, forced; its engine
  :func:`~kbm.expansion.forced.derive_forced` (the coupled algebra at ``N = 1`` with the
  forcing angle, its result in the resonant phase ``phi``);
- :class:`~kbm.model.coupled.CoupledOscillators`: ``dof`` N, forced or not; its engine
  :func:`~kbm.expansion.coupled.derive_coupled`.

No conversion stands between a model and an engine: every engine of ``N`` degrees of
freedom reads the general accessors (``rhs``, ``omegas``, ``drives``, ``hards``, ``nu0``)
of any instance, a case ``N = 1`` included (``tests/test_family.py``), and the general
engine gives the same expansion as the special one (``tests/test_coupled_engine.py``:
:func:`kbm.derive` to order 5; ``tests/test_coupled_forced.py``:
:func:`kbm.expansion.forced.derive_forced` to order 3 on every polynomial forced built-in).
Every instance binds its parameter values through one layer:
:func:`kbm.parameters.values.scaled_values` turns physical names into scaled ones (``delta =
Delta/mu``) and :func:`kbm.parameters.bound.bind` binds them.  The forced engine is the
general one's algebra at ``N = 1`` with the forcing angle
(:class:`kbm.algebra.forced.ForcedAlgebra`); the unforced engine of one degree of freedom
stays for what the general one does not do (the Bessel sums of ``sin(k x)`` above the first
order, :mod:`kbm.algebra.coupled_bessel`) and for the byte-stable derivations, in its faster
one-angle algebras; all of them run one recursion
(:func:`kbm.expansion.recursion.kbm_recursion`) over the algebra protocol
:class:`kbm.algebra.base.RecursionAlgebra`.

This module imports none of the types (they build on it).
"""

from __future__ import annotations

from ..errors import ModelError

__all__ = ["one_degree_form"]


def one_degree_form(model):
    """The instance itself when it has one degree of freedom (every engine of one degree
    of freedom takes any such instance as it is).

    Raises
    ------
    kbm.errors.ModelError
        For a system of several degrees of freedom (the message names the coupled engines).
    """
    if model.dof != 1:
        raise ModelError(f"{model.name!r} has {model.dof} degrees of freedom and the "
                         "one-degree-of-freedom engines take one: use the coupled ones "
                         "(kbm.expansion.coupled.derive_coupled; numerics.shooting: coupled_cycle, "
                         "continue_coupled, forced_response)")
    return model
