"""The two forms of one degree of freedom: :meth:`CoupledOscillators.from_oscillator` and
:meth:`CoupledOscillators.to_oscillator`.

A system of one degree of freedom is the case ``N = 1`` of :class:`CoupledOscillators`
and, for the engines of one degree of freedom, a :class:`kbm.models.Oscillator` or
:class:`kbm.forced.ForcedOscillator` (which also carry a symbolic frequency, a stage's pull
and the paper's gain factor).  The two conversions are exact and inverse
(``tests/test_family.py``); they are attached to :class:`CoupledOscillators` when
:mod:`kbm.coupled` is imported, and :func:`kbm.family.one_degree_form` applies them.
"""

from __future__ import annotations

from dataclasses import replace

import sympy as sp

from ..errors import ModelError
from ..symbols import x, xdot
from .model import CoupledOscillators, positions, velocities
from .resonance import InternalResonance

__all__ = ["from_oscillator", "to_oscillator"]


def from_oscillator(cls, model) -> CoupledOscillators:
    """The case ``N = 1`` of a :class:`kbm.models.Oscillator` (``x -> x1``,
    ``xdot -> xdot1``).

    A frequency written with a parameter that has a default (the sliders'
    ``Omega = 1``) takes that value: the coupled family's frequencies are exact
    rationals, fixed with the resonances they declare.

    A driven model (a stage that pulls, ``drive = Omega^2 v t``) keeps its drive, and
    :meth:`to_oscillator` is its inverse.

    Raises
    ------
    kbm.errors.ModelError
        For a frequency that is not a rational number.
    """
    from ..forced.model import ForcedOscillator

    w0 = sp.sympify(model.omega0)
    fixed = {s_.name for s_ in w0.free_symbols} & set(model.defaults)
    if fixed:
        sub = {sp.Symbol(n): sp.sympify(model.defaults[n]) for n in fixed}
        extra = {} if isinstance(model, ForcedOscillator) else \
            {"drive": model.drive.subs(sub), "stage_relative": model.stage_relative.subs(sub),
             "gain_factor": model.gain_factor.subs(sub)}
        model = replace(model, F=model.F.subs(sub), omega0=w0.subs(sub),
                        defaults={k: v for k, v in model.defaults.items() if k not in fixed},
                        **extra)
    if isinstance(model, ForcedOscillator):
        return _forced_case(cls, model)
    (x1,), (v1,) = positions(1), velocities(1)
    return cls(model.name, (model.F.subs({x: x1, xdot: v1}, simultaneous=True),),
               (model.omega0,), model.description, dict(model.defaults),
               physical=dict(model.physical),
               drive=(model.drive,) if model.drive != 0 else ())


def to_oscillator(self: CoupledOscillators):
    """The one-degree-of-freedom representation of an ``N = 1`` system (``x1 -> x``,
    ``xdot1 -> xdot``): a :class:`kbm.models.Oscillator`, or a
    :class:`kbm.forced.ForcedOscillator` for a forced one (its resonance ``omega0 : nu``
    from ``nu0``, its detuning ``sigma``); the inverse of :meth:`from_oscillator`, so that
    every engine of one degree of freedom takes the system.

    Raises
    ------
    kbm.errors.ModelError
        For more than one degree of freedom (the message names the coupled numerics), or a
        forcing detuning not named ``sigma``.
    """
    from ..forced.model import ForcedOscillator, Resonance
    from ..models import Oscillator

    if self.dof != 1:
        raise ModelError(f"{self.name!r} has {self.dof} degrees of freedom and the "
                         "one-degree-of-freedom engines take one: use the coupled ones "
                         "(kbm.coupled.derive_coupled; numerics.coupled: coupled_cycle, "
                         "continue_coupled, forced_response)")
    (x1,), (v1,) = positions(1), velocities(1)
    F = self.F[0].subs({x1: x, v1: xdot}, simultaneous=True)
    if not self.forced:
        return Oscillator(name=self.name, F=F, omega0=self.omega0[0],
                          description=self.description, physical=dict(self.physical),
                          defaults=dict(self.defaults),
                          drive=self.drive[0] if self.drive else 0)
    if self.nu_detuning not in (None, "sigma"):
        raise ModelError(f"{self.name!r} names its forcing detuning {self.nu_detuning!r}; "
                         "the one-degree-of-freedom forced engine names it sigma")
    ratio = self.nu0 / self.omega0[0]  # nu = (p/q) omega0 + mu sigma
    return ForcedOscillator(self.name, F, self.omega0[0],
                            Resonance(int(ratio.p), int(ratio.q)), self.description,
                            dict(self.defaults), self.hard[0] if self.hard else 0)


def _forced_case(cls, model) -> CoupledOscillators:
    """``N = 1`` with the forcing angle: ``nu = (p/q) omega0 + mu sigma`` of the declared
    resonance is ``omega0 : nu = q : p`` between the mode and the forcing."""
    res = model.resonance
    (x1,), (v1,) = positions(1), velocities(1)
    nu0 = model.omega0 * sp.Rational(res.p, res.q)
    return cls(model.name, (model.F.subs({x: x1, xdot: v1}, simultaneous=True),),
               (model.omega0,), model.description, dict(model.defaults),
               internal=(InternalResonance(1, 2, res.q, res.p, forcing=True),), nu0=nu0,
               nu_detuning="sigma", hard=(model.hard,) if model.hard != 0 else ())


CoupledOscillators.from_oscillator = classmethod(from_oscillator)
CoupledOscillators.to_oscillator = to_oscillator
