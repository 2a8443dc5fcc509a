"""``N`` weakly coupled oscillators ``x_i'' + omega_i**2 x_i = mu F_i(x, x')``, i = 1..N.

:class:`CoupledOscillators` is the model of :mod:`kbm.coupled`; the state variables are
``x1, ..., xN`` and ``xdot1, ..., xdotN``.  One degree of freedom is the case ``N = 1``
(:meth:`CoupledOscillators.from_oscillator` turns a :class:`kbm.models.Oscillator` into
it, with ``x -> x1``), and the coupled recursion reproduces the one-degree-of-freedom
expansion exactly there (``tests/test_coupled_engine.py``).

The linear frequencies ``omega_i`` are positive rationals: commensurate frequencies are
*internal resonances*, which the averaging must know exactly
(:class:`~kbm.coupled.resonance.InternalResonance`); a detuning is written in ``F`` (as a
stiffness ``-2 omega_j sigma x_j``) or declared with the resonance.

The symbols ``x_i``, ``xdot_i``, ``a_i``, ``psi_i`` and the check of the right-hand sides'
names are in :mod:`kbm.coupled.variables` (the symbols importable from here too).
"""

from __future__ import annotations

from fractions import Fraction
from math import lcm

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import sympy as sp

from ..errors import ModelError, ParameterError
from ..family import OscillatorFamily
from ..symbols import mu, parse, t
from ..values import FrozenMap, parameter_value
from .resonance import InternalResonance
from .variables import amplitudes, check_right_hand_sides, phases, positions, velocities

__all__ = ["CoupledOscillators", "positions", "velocities", "amplitudes", "phases",
           "MAX_DOF", "coupled_custom"]

#: most degrees of freedom a model may have (the compiled flows and shooting are 2N
#: dimensional; the symbolic averaging has its own, lower, limit)
MAX_DOF = 256


def _frequency(value: object, i: int | str) -> sp.Rational:
    name = i if isinstance(i, str) else f"omega{i}"
    w = parameter_value(name, value) if not isinstance(value, sp.Basic) else value
    if not (w.is_Rational and w > 0):
        raise ModelError(f"{name} must be a positive rational number (internal resonances "
                         f"are exact ratios of the frequencies), got {value!r}")
    return w


@dataclass(frozen=True)
class CoupledOscillators(OscillatorFamily):
    """The system ``x_i'' + omega_i**2 x_i = mu F_i(x1..xN, xdot1..xdotN)``.

    Parameters
    ----------
    name
        Short name (command line, generated files).
    F
        The right-hand sides divided by ``mu``, one per degree of freedom, in
        ``x1..xN``, ``xdot1..xdotN`` and parameters.
    omega0
        The linear frequencies, positive rationals, one per degree of freedom.
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
        pull ``Omega^2 v t`` of pulled sliders), added to ``x_i''``; empty: none.  ``F``
        may then hold ``t`` too (a self-excitation attached to the stage); such a model is
        integrated, not averaged.
    hard
        The amplitudes ``K_i`` of a *hard* (order-one) forcing ``K_i cos(theta)`` on each
        degree of freedom (Nayfeh & Mook 1979, sec. 4.1.2-4.1.3: super- and subharmonic
        resonances); empty: none.  The averaging shifts ``x_i`` by the forced response
        ``Lambda_i cos(theta)``, ``Lambda_i = K_i/(omega_i^2 - nu^2)`` (the symbols
        ``Lambda1, ..`` in its results).
    physical
        For models with a physical parametrisation (the SEDF sliders): each scaled parameter
        as an expression in physical ones and ``mu``, e.g. ``{"delta": Delta/mu,
        "k": 2*pi/lam}``; :func:`numerics.coupled.bind_coupled` accepts either name.
    internal
        The internal resonances the model is meant to be averaged with (a built-in's own;
        ``kbm derive --internal`` adds others).

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

    name: str
    F: tuple
    omega0: tuple
    description: str = ""
    defaults: Mapping[str, object] = field(default_factory=dict)
    internal: tuple = ()
    physical: Mapping[str, object] = field(default_factory=dict)
    nu0: object = None
    nu_detuning: str | None = None
    drive: tuple = ()
    hard: tuple = ()

    def __post_init__(self) -> None:
        if isinstance(self.F, (str, sp.Basic)) or not isinstance(self.F, Sequence):
            raise ModelError("F must be a sequence of right-hand sides, one per degree of "
                             "freedom")
        F = tuple(parse(f) if isinstance(f, str) else sp.sympify(f) for f in self.F)
        n = len(F)
        if not 1 <= n <= MAX_DOF:
            raise ModelError(f"a coupled model has 1 to {MAX_DOF} degrees of freedom, got {n}")
        w = self.omega0
        if not isinstance(w, Sequence) or isinstance(w, str):
            w = (w,)
        if len(w) != n:
            raise ModelError(f"{n} right-hand sides but {len(w)} frequencies omega0: give one "
                             f"frequency per degree of freedom (e.g. --omega0 "
                             f"{','.join(['1'] * n)})")
        w = tuple(_frequency(v, i) for i, v in enumerate(w, 1))
        object.__setattr__(self, "F", F)
        object.__setattr__(self, "omega0", w)
        object.__setattr__(self, "defaults",
                           FrozenMap({k: parameter_value(k, v) if not isinstance(v, sp.Basic)
                                      else v for k, v in self.defaults.items()}))
        nu0 = None
        if self.nu0 is not None:
            nu0 = _frequency(self.nu0, "nu0")
        object.__setattr__(self, "nu0", nu0)
        forced = nu0 is not None
        internal = tuple(r if isinstance(r, InternalResonance) else
                         InternalResonance.parse(r, n, forced=forced) for r in self.internal)
        for r in internal:
            r.check(w + ((nu0,) if forced else ()))
        object.__setattr__(self, "internal", internal)
        drive = tuple(parse(d) if isinstance(d, str) else sp.sympify(d) for d in self.drive)
        if drive and len(drive) != n:
            raise ModelError(f"{n} right-hand sides but {len(drive)} drives; give one per "
                             "degree of freedom")
        for d in drive:
            if d.free_symbols & (set(positions(n)) | set(velocities(n)) | {mu}):
                raise ModelError(f"the drive {d} must depend on t and parameters only")
        object.__setattr__(self, "drive", drive)
        hard = tuple(parse(k) if isinstance(k, str) else sp.sympify(k) for k in self.hard)
        if hard and len(hard) != n:
            raise ModelError(f"{n} right-hand sides but {len(hard)} hard forcing amplitudes; "
                             "give one per degree of freedom (0 for none)")
        if any(k != 0 for k in hard) and not forced:
            raise ModelError("a hard forcing K_i cos(theta) needs the forcing frequency: give "
                             "nu0 (theta = nu t, nu = nu0 + mu sigma)")
        for k in hard:
            if k.free_symbols & (set(positions(n)) | set(velocities(n))
                                 | {mu, t, sp.Symbol("theta"), sp.Symbol("nu")}):
                raise ModelError(f"the hard forcing amplitude {k} must be a constant (numbers "
                                 "and parameters)")
        object.__setattr__(self, "hard", hard if any(k != 0 for k in hard) else ())
        object.__setattr__(self, "physical",
                           FrozenMap({k: parse(v) if isinstance(v, str) else sp.sympify(v)
                                      for k, v in self.physical.items()}))
        check_right_hand_sides(F, self.name, forced)

    # -- structure --------------------------------------------------------------------
    @property
    def dof(self) -> int:
        """The number ``N`` of degrees of freedom."""
        return len(self.F)

    @property
    def state(self) -> tuple[sp.Symbol, ...]:
        """``(x1, ..., xN, xdot1, ..., xdotN)``."""
        return positions(self.dof) + velocities(self.dof)

    @property
    def parameters(self) -> tuple[str, ...]:
        """The names of the parameters of the right-hand sides (sorted)."""
        syms = set().union(*[f.free_symbols for f in (*self.F, *self.drive, *self.hard)]) \
            - set(self.state) - {sp.Symbol("theta"), sp.Symbol("nu"), t}
        names = {s.name for s in syms}
        if self.nu_detuning:
            names.add(self.nu_detuning)
        names |= {r.detuning for r in self.internal if r.detuning}
        return tuple(sorted(names))

    @property
    def forced(self) -> bool:
        """Whether the system is driven through ``theta = nu t``."""
        return self.nu0 is not None

    @property
    def forcing_ratios(self) -> tuple[Fraction, ...]:
        """``omega_i/nu0`` exactly (a forced system)."""
        nu0 = Fraction(int(self.nu0.p), int(self.nu0.q))
        return tuple(Fraction(int(w.p), int(w.q)) / nu0 for w in self.omega0)

    @property
    def response_periods(self) -> int:
        """How many forcing periods ``2 pi/nu`` a periodic response spans: the least common
        denominator of :attr:`forcing_ratios` (2 when a mode answers at ``nu/2``)."""
        return lcm(*[r.denominator for r in self.forcing_ratios])

    def resolve(self, values: Mapping[str, object] | None = None, *,
                use_defaults: bool = True) -> dict[str, sp.Expr]:
        """Exact values of the model's parameters (and ``mu``) from the given ones, physical
        names converted (``delta = Delta/mu``) and the defaults filled in: the bound form of
        every member of the family (:func:`kbm.bound.bind`).

        Raises
        ------
        kbm.errors.ParameterError
            For an unknown name, a value that is not a finite number, a scaled and a
            physical value of the same parameter, or a physical one without ``mu``.
        """
        values = dict(values or {})
        physical = dict(self.physical)
        phys_names = sorted({s.name for e in physical.values() for s in e.free_symbols}
                            - {"mu"})
        names = set(self.parameters) | {"mu"}
        unknown = sorted(set(values) - names - set(phys_names))
        if unknown:
            extra = f"; or the physical {', '.join(phys_names)}" if phys_names else ""
            raise ParameterError(f"{', '.join(map(repr, unknown))} is not a parameter of "
                                 f"{self.name!r} (its parameters: {', '.join(sorted(names))}"
                                 f"{extra})")
        given = {k: parameter_value(k, v) for k, v in values.items()}
        for scaled, expr in physical.items():  # e.g. delta = Delta/mu from Delta and mu
            needs = {s.name for s in expr.free_symbols}
            if scaled in given:
                if needs & (set(given) - {"mu"}):
                    raise ParameterError(f"give either {scaled} or "
                                         f"{', '.join(sorted(needs - {'mu'}))}, not both")
                continue
            if needs - {"mu"} and needs - {"mu"} <= set(given) | set(self.defaults):
                vals = {sp.Symbol(n): given.get(n, self.defaults.get(n)) for n in needs}
                if any(v is None for v in vals.values()):
                    raise ParameterError(f"{scaled} = {expr} needs a value of mu "
                                         "(-p mu=VALUE)")
                given[scaled] = sp.sympify(expr).subs(vals)
        out = {k: v for k, v in given.items() if k in names}
        if use_defaults:
            for name, v in self.defaults.items():
                if name in names:
                    out.setdefault(name, sp.sympify(v))
        return out

    def substitute(self, params: Mapping[str, object]) -> "CoupledOscillators":
        """The model with parameter values put in (exact: ``"0.1"`` is ``1/10``).

        Raises
        ------
        kbm.errors.ParameterError
            For a name that is not a parameter of the model.
        """
        detunings = {self.nu_detuning} | {r.detuning for r in self.internal}
        unknown = sorted(set(params) - set(self.parameters))
        kept = sorted(set(params) & (detunings - {None}))
        if kept:
            raise ParameterError(f"the detuning {', '.join(kept)} stays symbolic in the "
                                 "averaging (the slow flow is a function of it)")
        if unknown:
            raise ParameterError(f"{', '.join(map(repr, unknown))} is not a parameter of "
                                 f"{self.name!r} (its parameters: "
                                 f"{', '.join(self.parameters) or 'none'})")
        sub = {sp.Symbol(k): parameter_value(k, v) for k, v in params.items()}
        return CoupledOscillators(self.name, tuple(f.subs(sub) for f in self.F), self.omega0,
                                  self.description, self.defaults, self.internal,
                                  self.physical, self.nu0, self.nu_detuning,
                                  tuple(d.subs(sub) for d in self.drive),
                                  tuple(k.subs(sub) for k in self.hard))

    def with_internal(self, resonances: Sequence[object]) -> "CoupledOscillators":
        """The model with further declared internal resonances."""
        extra = tuple(r if isinstance(r, InternalResonance) else
                      InternalResonance.parse(r, self.dof, forced=self.forced)
                      for r in resonances)
        return CoupledOscillators(self.name, self.F, self.omega0, self.description,
                                  self.defaults, self.internal + extra, self.physical,
                                  self.nu0, self.nu_detuning, self.drive, self.hard)

    def frequencies(self) -> tuple[sp.Expr, ...]:
        """The linear frequencies with the declared detunings: ``omega_j + mu sigma`` for a
        resonance ``omega_i : omega_j`` declared with the detuning ``sigma``."""
        w = list(self.omega0)
        for r in self.internal:
            if r.detuning and not r.forcing:
                w[r.j - 1] = w[r.j - 1] + mu * sp.Symbol(r.detuning)
        return tuple(w)

    def accelerations(self) -> tuple[sp.Expr, ...]:
        """``x_i'' = -omega_i**2 x_i + mu F_i + K_i cos(theta)`` as expressions (``omega_i``
        with its declared detuning, :meth:`frequencies`; ``K_i`` the hard forcing)."""
        drive = self.drive or (0,) * self.dof
        hard = self.hard or (0,) * self.dof
        theta = sp.Symbol("theta")
        return tuple(-w**2 * xi + mu * f + d + k * sp.cos(theta) for w, xi, f, d, k in
                     zip(self.frequencies(), positions(self.dof), self.F, drive, hard))

    def is_autonomous(self, values: Mapping[str, object] | None = None) -> bool:
        """Whether the system does not depend on ``t`` explicitly (at ``values``: a stage at
        ``v = 0`` does not pull)."""
        exprs = [*self.F, *self.drive]
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
        terms = [term for e in (*self.F, *self.drive)
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
        if self.is_autonomous():
            return self
        values = dict(values or {})
        stage = {p: values.get(p, self.defaults.get(p)) for p in self.stage_parameters()}
        if any(v is None for v in stage.values()) or not self.is_autonomous(stage):
            shown = ", ".join(f"{p} = {v}" for p, v in stage.items() if v is not None)
            why = (f" (a stage that pulls{' at ' + shown if shown else ''})" if stage
                   else " explicitly")
            raise ModelError(f"{self.name!r} depends on the time t{why}; the averaging treats "
                             "autonomous systems and periodic forcing through theta: "
                             + (f"give {' and '.join(f'{p}=0' for p in stage)} or " if stage
                                else "write a periodic forcing in theta = nu t, or ")
                             + "integrate it (kbm cycle, kbm friction)")
        return self.substitute(stage)


def coupled_custom(rhs: Sequence[str], omega0: Sequence[object] | str | None = None, *,
                   name: str = "custom", nu0: object = None,
                   detuning: str = "sigma") -> CoupledOscillators:
    """A user's system from one right-hand side per degree of freedom.

    ``omega0`` is a list or a comma-separated string (``"1,3"``); default all 1.  With
    ``nu0`` the right-hand sides may hold the forcing angle ``theta = nu t``,
    ``nu = nu0 + mu detuning``.

    Raises
    ------
    kbm.errors.ModelError
        For mismatched counts (both are named), unreadable expressions, or a right-hand
        side that uses none of the state variables.
    """
    n = len(rhs)
    if omega0 is None:
        w: Sequence[object] = ["1"] * n
    elif isinstance(omega0, str):
        w = [s.strip() for s in omega0.split(",")]
    else:
        w = list(omega0)
    if len(w) != n:
        raise ModelError(f"{n} right-hand sides (--rhs) but {len(w)} frequencies (--omega0 "
                         f"{omega0}): give one frequency per degree of freedom")
    model = CoupledOscillators(name, tuple(rhs), tuple(w),
                               description=f"user system of {n} degrees of freedom",
                               nu0=nu0, nu_detuning=detuning if nu0 is not None else None)
    state = set(model.state)
    for i, f in enumerate(model.F, 1):
        if f != 0 and not (f.free_symbols & state):
            raise ModelError(f"F{i} = {rhs[i - 1]} depends on none of the state variables "
                             f"{', '.join(map(str, model.state))}: write the system in them "
                             "(one --rhs per degree of freedom)")
    return model
