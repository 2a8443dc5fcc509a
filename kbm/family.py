"""The one family of models: ``x_i'' + omega_i^2 x_i = mu F_i(x, x', theta)``, ``i = 1..N``.

Every model of the package is a member of :class:`OscillatorFamily`, and the number of
degrees of freedom and the forcing are its properties, not its type:

========================================  =====  ========  ===========================
member                                    dof    forced    its engine
========================================  =====  ========  ===========================
:class:`kbm.models.Oscillator`            1      no        :func:`kbm.derive` (Bessel
                                                           sums, any order)
:class:`kbm.forced.ForcedOscillator`      1      yes       :func:`kbm.forced.derive_forced`
:class:`kbm.coupled.CoupledOscillators`   N      either    :func:`kbm.coupled.derive_coupled`
========================================  =====  ========  ===========================

:meth:`kbm.coupled.CoupledOscillators.from_oscillator` writes a member of one degree of
freedom in the general form (``x -> x1``) and
:meth:`~kbm.coupled.CoupledOscillators.to_oscillator` back, so every engine takes either
form (:func:`kbm.bound.bind` converts an ``N = 1`` system for the engines of one degree of
freedom, :func:`numerics.coupled.flow.bind_coupled` an oscillator for the coupled ones;
``tests/test_family.py``), and the general engine gives the same expansion
as the special one (``tests/test_coupled_engine.py``: :func:`kbm.derive` to order 5, and
:func:`kbm.forced.derive_forced` to order 3 on every polynomial forced built-in); every
member binds its parameter values through :func:`kbm.bound.bind`.  The one-degree-of-
freedom engines stay for what the general one does not do (the Bessel sums of
``sin(k x)`` above the first order, :mod:`kbm.coupled.bessel`) and for the byte-stable
derivations, in their faster one- and two-angle algebras.  The three engines and their
numeric backends run one recursion (:func:`kbm.recursion.kbm_recursion`) over the algebra
protocol :class:`kbm.algebra.base.RecursionAlgebra`: ``N = 1`` and the forcing are its cases.

This module imports none of its members (they build on it).
"""

from __future__ import annotations

__all__ = ["OscillatorFamily", "one_degree_form"]


class OscillatorFamily:
    """The base of every model type: ``dof`` and ``forced`` are properties.

    Examples
    --------
    >>> from kbm.models import get_model
    >>> from kbm.coupled import get_coupled_model
    >>> [(m.dof, m.forced) for m in (get_model("vdp"), get_coupled_model("quadratic-1-2"))]
    [(1, False), (2, True)]
    """

    __slots__ = ()

    @property
    def dof(self) -> int:
        """The number ``N`` of degrees of freedom."""
        raise NotImplementedError

    @property
    def forced(self) -> bool:
        """Whether ``F`` holds the forcing angle ``theta = nu t``."""
        raise NotImplementedError


def one_degree_form(model):
    """The form of one degree of freedom of a member, for the engines of one degree of
    freedom: the member itself, or an ``N = 1`` system's
    :meth:`~kbm.coupled.CoupledOscillators.to_oscillator`.

    Raises
    ------
    kbm.errors.ModelError
        For a system of several degrees of freedom (the message names the coupled engines).
    """
    to_oscillator = getattr(model, "to_oscillator", None)
    return to_oscillator() if to_oscillator is not None else model
