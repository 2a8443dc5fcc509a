"""The one model type: ``x_i'' + omega_i**2 x_i = mu F_i(x, x', theta) + drive_i(t)``, i = 1..N.

:class:`CoupledOscillators` holds every model of the package: the number ``N`` of degrees
of freedom (:attr:`~CoupledOscillators.dof`), the forcing angle ``theta = nu t``
(:attr:`~CoupledOscillators.forced`, ``nu = nu0 + mu sigma``) and the stage drive
(:attr:`~CoupledOscillators.drives`) are properties of its data, not types.  Its general
accessors are :attr:`~CoupledOscillators.rhs` (the ``F_i`` in ``x1..xN``,
``xdot1..xdotN``), :attr:`~CoupledOscillators.omegas`, :attr:`~CoupledOscillators.drives`
and :attr:`~CoupledOscillators.hards`, which every engine of ``N`` degrees of freedom
reads; ``F``, ``omega0``, ``drive``, ``hard`` are their names for a system built as such.
The cases ``N = 1`` are subclasses that keep the names of one degree of freedom (``F`` in
``x``, ``xdot``): :class:`kbm.model.oscillator.Oscillator` (autonomous, or pulled by a stage)
and :class:`kbm.model.forced.ForcedOscillator` (a forcing angle), so that no conversion stands
between a model and any engine.

The linear frequencies ``omega_i`` of a system built here are positive rationals:
commensurate frequencies are *internal resonances*, which the averaging must know exactly
(:class:`~kbm.expansion.resonance.InternalResonance`); a detuning is written in ``F`` (as a
stiffness ``-2 omega_j sigma x_j``) or declared with the resonance.  (A case ``N = 1`` may
name its frequency by a parameter, the sliders' ``Omega``: :meth:`~CoupledOscillators.\
with_frequencies` puts its value in for the engines that need the number.)

The symbols ``x_i``, ``xdot_i``, ``a_i``, ``psi_i`` and the check of the right-hand sides'
names are in :mod:`kbm.model.variables` (the symbols importable from here too).
"""

from __future__ import annotations

from fractions import Fraction
from math import lcm

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import sympy as sp

from ..errors import ModelError, ParameterError
from ..symbols import mu, parse, t
from ..parameters.values import FrozenMap, parameter_value, scaled_values
from ..expansion.resonance import InternalResonance
from .variables import MAX_DOF, amplitudes, phases, positions, read_exprs, read_system, velocities

__all__ = ["CoupledOscillators", "positions", "velocities", "amplitudes", "phases",
           "MAX_DOF"]

_THETA, _NU = sp.Symbol("theta"), sp.Symbol("nu")


@dataclass(frozen=True, init=False)
class CoupledOscillators:
    """The system ``x_i'' + omega_i**2 x_i = mu F_i(x1..xN, xdot1..xdotN, theta)``.

    Parameters
    ----------
    name
        Short name (command line, generated files).
    F
        The right-hand sides divided by ``mu``, one per degree of freedom, in
        ``x1..xN``, ``xdot1..xdotN`` and parameters (:attr:`rhs`).
    omega0
        The linear frequencies, positive rationals, one per degree of freedom (:attr:`omegas`).
    description
        One line saying what the model is and where it comes from.
    defaults
        Values of parameters that are not given.
    nu0, nu_detuning
        A periodic forcing: ``F`` may hold ``cos(k theta)``, ``sin(k theta)`` with
        ``theta = nu t``, ``nu = nu0 + mu sigma`` (``sigma`` named ``nu_detuning``; ``None``:
        ``nu = nu0`` exactly).  ``nu0`` is a positive rational; the forcing angle is the
        mode ``N + 1`` of the resonance declarations (``"1:1@2,F"``: ``omega_2 : nu = 1 : 1``).
    drive
        Order-one forces of time and parameters, one per degree of freedom (the stage's
        pull ``Omega^2 v t`` of pulled sliders), added to ``x_i''`` (:attr:`drives`); empty:
        none.  ``F`` may then hold ``t`` too (a self-excitation attached to the stage); such
        a model is integrated, not averaged.
    hard
        The amplitudes ``K_i`` of a *hard* (order-one) forcing ``K_i cos(theta)`` on each
        degree of freedom (Nayfeh & Mook 1979, sec. 4.1.2-4.1.3: super- and subharmonic
        resonances; :attr:`hards`); empty: none.  The averaging shifts ``x_i`` by the forced
        response ``Lambda_i cos(theta)``, ``Lambda_i = K_i/(omega_i^2 - nu^2)``.
    physical
        For models with a physical parametrisation (the SEDF sliders): each scaled parameter
        as an expression in physical ones and ``mu``, e.g. ``{"delta": Delta/mu,
        "k": 2*pi/lam}``; :func:`kbm.parameters.bound.bind` accepts either name.
    internal
        The internal resonances the model is meant to be averaged with (a built-in's own;
        ``kbm derive --internal`` adds others).
    gain_factor
        A parameter that multiplies every energy-supplying term of the dissipation
        integrand (the paper's eq. 11: ``beta``); 1 when there is none.
    stage_relative
        The parts of ``F_i`` that a pulling stage re-evaluates at the spring's extension
        (:meth:`kbm.model.oscillator.Oscillator.with_stage_velocity`); empty: none.

    Raises
    ------
    kbm.errors.ModelError
        For a count of ``F`` and ``omega0`` that differ, ``mu`` or a reserved name in
        ``F``, a state variable beyond ``N``, a frequency that is not a positive rational,
        or more than :data:`MAX_DOF` degrees of freedom.

    Examples
    --------
    >>> m = CoupledOscillators("two", ("(1 - x1**2)*xdot1 + c*(xdot2 - xdot1)",
    ...                               "(1 - x2**2)*xdot2 + c*(xdot1 - xdot2)"), (1, 1))
    >>> m.dof, m.parameters
    (2, ('c',))
    """

    #: which case of the type a class is: ``"system"`` (named as such), ``"one"``
    #: (:class:`kbm.model.builtins.Oscillator`), ``"forced"``
    #: (:class:`kbm.model.forced.ForcedOscillator`)
    case = "system"

    name: str
    rhs: tuple
    omegas: tuple
    description: str
    defaults: FrozenMap
    internal: tuple
    physical: FrozenMap
    nu0: object
    nu_detuning: str | None
    drives: tuple
    hards: tuple
    gain_factor: sp.Expr
    relative: tuple

    def __init__(self, name: str, F: Sequence, omega0: Sequence, description: str = "",
                 defaults: Mapping[str, object] | None = None, internal: Sequence = (),
                 physical: Mapping[str, object] | None = None, nu0: object = None,
                 nu_detuning: str | None = None, drive: Sequence = (), hard: Sequence = (),
                 *, gain_factor: object = 1, stage_relative: Sequence = ()) -> None:
        F, w, nu0, internal, drive, hard = read_system(name, F, omega0, nu0, internal, drive,
                                                      hard)
        self._store(name=name, rhs=F, omegas=w, description=description, defaults=defaults,
                    internal=internal, physical=physical, nu0=nu0, nu_detuning=nu_detuning,
                    drives=drive, hards=hard, gain_factor=gain_factor,
                    relative=read_exprs(stage_relative, len(F), "stage parts"))

    def _store(self, *, name: str, rhs: Sequence, omegas: Sequence, description: str = "",
               defaults: Mapping | None = None, internal: Sequence = (),
               physical: Mapping | None = None, nu0: object = None,
               nu_detuning: str | None = None, drives: Sequence = (), hards: Sequence = (),
               gain_factor: object = 1, relative: Sequence = ()) -> None:
        """Set the fields from checked data (each constructor checks its own; :meth:`_with`
        copies), the mappings read into exact, read-only ones."""
        values = dict(locals())
        del values["self"]
        values.update(
            defaults=FrozenMap({k: v if isinstance(v, sp.Basic) else parameter_value(k, v)
                                for k, v in (defaults or {}).items()}),
            physical=FrozenMap({k: parse(v) if isinstance(v, str) else sp.sympify(v)
                                for k, v in (physical or {}).items()}),
            gain_factor=parse(gain_factor) if isinstance(gain_factor, str)
            else sp.sympify(gain_factor))
        for key in self.__dataclass_fields__:
            value = values[key]
            object.__setattr__(self, key, tuple(value) if isinstance(value, (list, tuple))
                               else value)

    def _with(self, **changes) -> "CoupledOscillators":
        """A copy of the same class with some fields replaced."""
        new = object.__new__(type(self))
        new._store(**{**{k: getattr(self, k) for k in self.__dataclass_fields__}, **changes})
        return new

    # -- the names of a system built as such (tuples; scalars in the cases N = 1) ---------
    F = property(lambda self: self.rhs, doc="The right-hand sides ``F_i`` (:attr:`rhs`).")
    omega0 = property(lambda self: self.omegas, doc="The frequencies (:attr:`omegas`).")
    drive = property(lambda self: self.drives, doc="The order-one drives (:attr:`drives`).")
    hard = property(lambda self: self.hards, doc="The hard forcings (:attr:`hards`).")

    # -- structure --------------------------------------------------------------------
    @property
    def dof(self) -> int:
        """The number ``N`` of degrees of freedom."""
        return len(self.rhs)

    @property
    def state(self) -> tuple[sp.Symbol, ...]:
        """``(x1, ..., xN, xdot1, ..., xdotN)``: the symbols of :attr:`rhs`."""
        return positions(self.dof) + velocities(self.dof)

    @property
    def parameters(self) -> tuple[str, ...]:
        """The names of the parameters of the right-hand sides, drives, hard forcings and
        symbolic frequencies, and the :attr:`detunings` (sorted)."""
        syms = set().union(*[f.free_symbols for f in (*self.rhs, *self.drives, *self.hards,
                                                      *self.omegas)]) \
            - set(self.state) - {t} - ({_THETA, _NU} if self.forced else set())
        return tuple(sorted({s.name for s in syms} | set(self.detunings)))

    @property
    def detunings(self) -> tuple[str, ...]:
        """The names of the declared detunings (the forcing's ``sigma``, the internal
        resonances'), sorted: parameters the averaged slow flow keeps symbolic."""
        return tuple(sorted(({self.nu_detuning} | {r.detuning for r in self.internal})
                            - {None}))

    @property
    def forced(self) -> bool:
        """Whether the system is driven through ``theta = nu t``."""
        return self.nu0 is not None

    @property
    def forcing_ratios(self) -> tuple[Fraction, ...]:
        """``omega_i/nu0`` exactly (a forced system)."""
        ratios = [sp.sympify(w / self.nu0) for w in self.omegas]
        return tuple(Fraction(int(r.p), int(r.q)) for r in ratios)

    @property
    def response_periods(self) -> int:
        """How many forcing periods ``2 pi/nu`` a periodic response spans: the least common
        denominator of :attr:`forcing_ratios` (2 when a mode answers at ``nu/2``)."""
        return lcm(*[r.denominator for r in self.forcing_ratios])

    def with_frequencies(self, values: Mapping[str, object] | None = None
                         ) -> "CoupledOscillators":
        """The model with the parameters of its frequencies put in (from ``values``, else
        the defaults: the sliders' ``Omega = 1``), for the engines that need exact rational
        frequencies; the model itself when they are numbers already.

        Raises
        ------
        kbm.errors.ModelError
            For a frequency parameter without a value.
        """
        names = sorted({s.name for w in (*self.omegas, self.nu0) if w is not None
                        for s in sp.sympify(w).free_symbols})
        if not names:
            return self
        values = dict(values or {})
        missing = [n for n in names if n not in values and n not in self.defaults]
        if missing:
            raise ModelError(f"the frequency of {self.name!r} needs a value of "
                             f"{', '.join(missing)} (-p {missing[0]}=VALUE)")
        return self.substitute({n: values.get(n, self.defaults.get(n)) for n in names})

    def resolve(self, values: Mapping[str, object] | None = None, *,
                use_defaults: bool = True) -> dict[str, sp.Expr]:
        """Exact values of the model's parameters (and ``mu``) from the given ones, physical
        names converted (``delta = Delta/mu``) and the defaults filled in: the one binding
        layer, :func:`kbm.parameters.values.scaled_values` (:func:`kbm.parameters.bound.bind` binds
        its result).

        Raises
        ------
        kbm.errors.ParameterError
            For an unknown name (the valid ones listed), a value that is not a finite number,
            a scaled and a physical value of the same parameter, or a physical one without
            ``mu``.
        """
        return scaled_values(self, values, use_defaults=use_defaults)

    def substitute(self, params: Mapping[str, object]) -> "CoupledOscillators":
        """The same model (of the same class) with parameter values put in, exact (``"0.1"``
        is ``1/10``), physical names converted (:meth:`resolve`); ``mu`` is not in the
        model and is passed over.

        Raises
        ------
        kbm.errors.ParameterError
            For a name that is not a parameter of the model, or a declared detuning (the
            averaged slow flow is a function of it).
        kbm.errors.ModelError
            For a value that makes a linear frequency not positive.
        """
        vals = self.resolve(params, use_defaults=False)
        vals.pop("mu", None)
        kept = sorted(set(vals) & set(self.detunings))
        if kept:
            raise ParameterError(f"the detuning {', '.join(kept)} stays symbolic in the "
                                 "averaging (the slow flow is a function of it)")
        sub = {sp.Symbol(k): v for k, v in vals.items()}
        omegas = tuple(sp.sympify(w).subs(sub) for w in self.omegas)
        bad = [w for w in omegas if w.is_number and not (w.is_real and w > 0)]
        if bad:
            raise ModelError(f"the linear frequency of {self.name!r} must be positive, got "
                             f"omega0 = {bad[0]}")
        keep = lambda m: FrozenMap({k: v for k, v in m.items() if k not in vals})  # noqa: E731
        return self._with(
            rhs=tuple(e.subs(sub) for e in self.rhs), omegas=omegas,
            drives=tuple(e.subs(sub) for e in self.drives),
            hards=tuple(e.subs(sub) for e in self.hards),
            relative=tuple(e.subs(sub) for e in self.relative),
            nu0=None if self.nu0 is None else sp.sympify(self.nu0).subs(sub),
            gain_factor=self.gain_factor.subs(sub), defaults=keep(self.defaults),
            physical=keep(self.physical))

    def with_internal(self, resonances: Sequence[object]) -> "CoupledOscillators":
        """The model with further declared internal resonances."""
        extra = tuple(r if isinstance(r, InternalResonance) else
                      InternalResonance.parse(r, self.dof, forced=self.forced)
                      for r in resonances)
        internal = read_system(self.name, self.rhs, self.omegas, self.nu0,
                               self.internal + extra, self.drives, self.hards)[3]
        return self._with(internal=internal)  # checked as the constructor checks them

    def frequencies(self) -> tuple[sp.Expr, ...]:
        """The linear frequencies with the declared detunings: ``omega_j + mu sigma`` for a
        resonance ``omega_i : omega_j`` declared with the detuning ``sigma``."""
        w = list(self.omegas)
        for r in self.internal:
            if r.detuning and not r.forcing:
                w[r.j - 1] = w[r.j - 1] + mu * sp.Symbol(r.detuning)
        return tuple(w)

    def accelerations(self) -> tuple[sp.Expr, ...]:
        """``x_i'' = -omega_i**2 x_i + mu F_i + K_i cos(theta)`` as expressions (``omega_i``
        with its declared detuning, :meth:`frequencies`; ``K_i`` the hard forcing)."""
        drive = self.drives or (0,) * self.dof
        hard = self.hards or (0,) * self.dof
        return tuple(-w**2 * xi + mu * f + d + k * sp.cos(_THETA) for w, xi, f, d, k in
                     zip(self.frequencies(), positions(self.dof), self.rhs, drive, hard))

    @property
    def is_autonomous(self) -> bool:
        """Whether the system does not depend on the time ``t`` explicitly."""
        return self.autonomous()

    def autonomous(self, values: Mapping[str, object] | None = None) -> bool:
        """Whether the system does not depend on ``t`` explicitly at ``values`` (a stage at
        ``v = 0`` does not pull)."""
        exprs = [*self.rhs, *self.drives]
        if values:
            sub = {sp.Symbol(k): v for k, v in values.items()}
            exprs = [sp.expand(e.subs(sub)) for e in exprs]
        return not any(e.has(t) for e in exprs)

    def physical_hint(self, name: str) -> str:
        """``", or the physical -p Delta=VALUE (delta = Delta/mu)"`` for a scaled parameter
        with a physical form, for the message that asks for its value; empty otherwise."""
        expr = self.physical.get(name)
        if expr is None:
            return ""
        inputs = sorted({s.name for s in sp.sympify(expr).free_symbols} - {"mu"})
        return (f", or the physical {' and '.join(f'-p {n}=VALUE' for n in inputs)}"
                f" ({name} = {expr})")

    def stage_parameters(self) -> tuple[str, ...]:
        """The parameters whose value 0 removes the time ``t`` from ``F`` and the drives,
        where ``t`` enters polynomially (the stage velocity ``v`` of the pulled sliders,
        ``x - v t``), sorted; empty for an autonomous system, or one whose time dependence
        no such parameter switches off."""
        terms = [term for e in (*self.rhs, *self.drives)
                 for term in sp.Add.make_args(sp.expand(e)) if term.has(t)]
        if not terms or not all(term.is_polynomial(t) for term in terms):
            return ()  # a stage pulls with v t; sin(t) is a time dependence of its own
        names = set.intersection(*[{s.name for s in term.free_symbols} for term in terms])
        names -= {s.name for s in self.state} | {t.name}
        return tuple(sorted(p for p in names
                            if not any(term.subs(sp.Symbol(p), 0).has(t) for term in terms)))

    def at_rest(self, values: Mapping[str, object] | None = None) -> "CoupledOscillators":
        """The autonomous system of a stage at rest: the :meth:`stage_parameters` put in
        at their given (``values``) or default values when that removes ``t``
        (``sedf-dimer`` at its default ``v = 0``); an autonomous system is returned as it is.

        Raises
        ------
        kbm.errors.ModelError
            When those values leave ``t`` in the system (a stage that pulls).
        """
        if self.autonomous():
            return self
        values = dict(values or {})
        stage = {p: values.get(p, self.defaults.get(p)) for p in self.stage_parameters()}
        if any(v is None for v in stage.values()) or not self.autonomous(stage):
            shown = ", ".join(f"{p} = {v}" for p, v in stage.items() if v is not None)
            why = (f" (a stage that pulls{' at ' + shown if shown else ''})" if stage
                   else " explicitly")
            raise ModelError(f"{self.name!r} depends on the time t{why}; the averaging treats "
                             "autonomous systems and periodic forcing through theta: "
                             + (f"give {' and '.join(f'{p}=0' for p in stage)} or " if stage
                                else "write a periodic forcing in theta = nu t, or ")
                             + "integrate it (kbm cycle, kbm friction)")
        return self.substitute(stage)
