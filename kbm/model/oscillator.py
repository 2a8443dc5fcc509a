"""The oscillator type ``x'' + w0^2 x = eps F(x, x') + drive(t)``, defined once, symbolically.

:class:`Oscillator` is the case ``N = 1`` without a forcing angle of the one model type
:class:`kbm.model.coupled.CoupledOscillators` (its data are that type's, in the state ``x1``,
``xdot1``; ``F``, ``omega0``, ``drive`` and ``stage_relative`` are their names for one degree
of freedom, in ``x``, ``xdot``).  The right-hand side ``F`` is a sympy expression in the symbols ``x``, ``xdot`` (and ``t`` for a driven, non-autonomous model) and
named parameters; the small parameter is ``mu`` (the paper's mu, epsilon in the textbooks).
Its structure (conservative and dissipative forces, the dissipation integrand split by sign,
paper eqs. 10-11), its stage drive (paper eq. 3) and the mapping of physical parameter names
to scaled ones live here; the built-in models that instantiate it are in :mod:`kbm.model.builtins`,
a user's model in :mod:`kbm.model.user_model`.

References
----------
M. D'Acunto, "Friction force for self-excited systems", eqs. (3), (10)-(12).
"""

from __future__ import annotations

from collections.abc import Mapping
from functools import cached_property

import sympy as sp

from ..errors import ModelError, NonAutonomousError
from .coupled import CoupledOscillators
from .variables import positions, velocities
from ..symbols import mu, parse, t, x, xdot
from ..parameters.values import parameter_value

__all__ = ["Oscillator", "OneDegree", "TO_GENERAL", "TO_ONE"]

(_X1,), (_V1,) = positions(1), velocities(1)
_THETA = sp.Symbol("theta")
#: the state of one degree of freedom in the one type's symbols, and back
TO_GENERAL, TO_ONE = {x: _X1, xdot: _V1}, {_X1: x, _V1: xdot}


def _expr(value: object) -> sp.Expr:
    """A sympy expression from code or user input: strings through the safe :func:`parse`,
    numbers and sympy objects as they are (never through ``str()``)."""
    if isinstance(value, str):
        return parse(value)
    try:
        return sp.sympify(value, strict=True)
    except sp.SympifyError:
        raise ModelError(f"cannot read {value!r} as an expression") from None


class OneDegree(CoupledOscillators):
    """The cases ``N = 1`` of the one type (:class:`Oscillator`,
    :class:`kbm.model.forced.ForcedOscillator`): its data under the names of one degree of
    freedom, in ``x``, ``xdot``."""

    @staticmethod
    def _check_one(name: str, F: sp.Expr, w0: sp.Expr, reserved: set[str], *,
                   exact: bool, free: frozenset = frozenset()) -> None:
        """The checks of ``F`` and ``omega0`` both cases make (``exact``: a rational
        frequency, for the exact forced averaging; ``free``: symbols ``F`` may hold).

        Raises
        ------
        kbm.errors.ModelError
            For ``mu`` in ``F``, a ``reserved`` name, or ``omega0`` not a positive
            (rational) number or a symbol.
        """
        if mu in F.free_symbols:
            raise ModelError(f"F of model {name!r} contains the small parameter mu; write "
                             "the equation as x'' + omega0^2 x = mu*F with F free of mu")
        for s in (F.free_symbols - free) | w0.free_symbols:
            if s.name in reserved:
                raise ModelError(f"the symbol {s.name!r} is reserved (the KBM amplitude, "
                                 "phases, detuning and forcing frequency); rename that "
                                 "parameter")
        if w0.free_symbols & {x, xdot, t, _THETA}:
            raise ModelError(f"omega0 = {w0} must be a constant (not of the state or time)")
        kind = "rational" if exact else "real"
        if w0.is_number and not (w0.is_real and w0 > 0 and (w0.is_Rational or not exact)):
            raise ModelError(f"omega0 must be a positive {kind} number (or a symbol), got "
                             f"omega0 = {w0}" + (" (the exact forced averaging)" if exact
                                                 else ""))
        if not (w0.is_number or w0.is_Symbol):
            raise ModelError(f"omega0 must be a positive number or a single symbol, got {w0}")

    @cached_property
    def F(self) -> sp.Expr:
        """``F(x, xdot[, t or theta])``: the right-hand side over ``mu``."""
        return self.rhs[0].xreplace(TO_ONE)

    @property
    def omega0(self) -> sp.Expr:
        """The linear frequency: a positive number or a symbol."""
        return self.omegas[0]

    @property
    def drive(self) -> sp.Expr:
        """The order-one drive of ``t`` (a stage's pull ``Omega^2 v t``); 0 for none."""
        return self.drives[0] if self.drives else sp.Integer(0)

    @property
    def hard(self) -> sp.Expr:
        """The amplitude ``K`` of a hard forcing ``K cos(theta)``; 0 for none."""
        return self.hards[0] if self.hards else sp.Integer(0)

    @property
    def stage_relative(self) -> sp.Expr:
        """The part of ``F`` attached to a pulling stage (in ``x``); 0 for none."""
        return self.relative[0].xreplace(TO_ONE) if self.relative else sp.Integer(0)


class Oscillator(OneDegree):
    """The oscillator ``x'' + omega0**2 x = mu F(x, xdot[, t]) + drive(t)``: the one type
    :class:`~kbm.model.coupled.CoupledOscillators` at ``N = 1``, without a forcing angle.

    Parameters
    ----------
    name
        Short name (used on the command line and in generated files).
    F
        The right-hand side divided by the small parameter ``mu``.
    omega0
        Linear natural frequency; a positive rational number or a symbol.
    description
        One line saying what the model is and where it comes from.
    physical
        For models with a physical parametrisation (the paper's eqs. 3, 12):
        each scaled parameter as an expression in the physical ones, e.g.
        ``{"delta": Delta/mu, "k": 2*pi/lam}``.
    defaults
        Values used for parameters that are not given (e.g. ``Omega = 1``,
        as in the paper).
    drive
        An external force of order one that depends on ``t`` only (the
        stage's pull ``Omega^2 v t`` of the paper's eq. 3); 0 for the
        autonomous oscillators the averaging treats.
    gain_factor
        A parameter that multiplies every energy-supplying term of the
        dissipation integrand (the paper's eq. 11, ``Gamma = beta Gamma_+ -
        Gamma_-``, has ``gain_factor = beta``); 1 when there is none.
    stage_relative
        The part of ``F`` that, when a stage pulls the spring at velocity ``v``
        (:meth:`with_stage_velocity`), depends on the spring's extension ``x - v t``
        instead of on ``x`` (a self-excitation attached to the stage); 0 for the
        paper's models, whose ``F`` keeps the substrate position ``x``.

    Raises
    ------
    kbm.errors.ModelError
        If ``F`` contains ``mu``, ``omega0**2`` is not positive, or a symbol
        name is reserved.

    Examples
    --------
    >>> from kbm.model.builtins import get_model
    >>> vdp = get_model("vdp")
    >>> vdp.F
    xdot*(1 - x**2)
    >>> vdp.acceleration()
    mu*xdot*(1 - x**2) - x
    """

    case = "one"

    def __init__(self, name: str, F: object, omega0: object = 1, description: str = "",
                 physical: Mapping[str, sp.Expr] | None = None,
                 defaults: Mapping[str, object] | None = None, drive: object = 0,
                 gain_factor: object = 1, stage_relative: object = 0) -> None:
        F = sp.sympify(parse(F) if not isinstance(F, sp.Basic) else F)
        w0, drive, rel = _expr(omega0), _expr(drive), _expr(stage_relative)
        if drive.free_symbols & {x, xdot, mu}:
            raise ModelError(f"the drive {drive} of model {name!r} must depend on t and "
                             "parameters only")
        if rel != 0 and x not in rel.free_symbols:
            raise ModelError(f"stage_relative = {rel} of model {name!r} must be a part of F "
                             "that depends on x (it is re-evaluated at the spring extension "
                             "x - v t when the stage moves)")
        self._check_one(name, F, w0, {"a", "psi"}, exact=False)
        self._store(name=name, rhs=(F.xreplace(TO_GENERAL),), omegas=(w0,),
                    description=description, physical=physical,
                    defaults={k: _expr(v) for k, v in (defaults or {}).items()},
                    drives=(drive,) if drive != 0 else (), gain_factor=_expr(gain_factor),
                    relative=(rel.xreplace(TO_GENERAL),) if rel != 0 else ())
        self.__dict__["F"] = F  # the F given, as given (the derivations print it)

    def require_autonomous(self, what: str = "the KBM averaging") -> None:
        """Raise :class:`NonAutonomousError` if ``F`` depends on ``t``."""
        if not self.is_autonomous:
            raise NonAutonomousError(
                f"{what} needs an autonomous model, but {self.name!r} depends on t explicitly "
                f"(mu*F + drive = {self.acceleration() + self.omega0**2 * x}); "
                "set the stage velocity v = 0 or drop the time-dependent term (a drive "
                "periodic in t is treated by kbm.model.forced: kbm response --forcing EXPR in "
                "theta)")

    def acceleration(self) -> sp.Expr:
        """``x''`` as an expression: ``-omega0**2 x + mu F + drive``."""
        return -self.omega0**2 * x + mu * self.F + self.drive

    def conservative_force(self) -> sp.Expr:
        """The part of ``mu F`` that depends on ``x`` (and ``t``) only, without the drive."""
        return mu * self.F.subs(xdot, 0)

    def dissipative_force(self) -> sp.Expr:
        """The part of ``mu F`` that vanishes at ``x' = 0`` (damping and self-excitation).

        A sum of terms, powers of sums kept whole: the stage-attached excitation of
        ``sedf_comoving`` pulled at ``v`` stays ``-beta mu (x - v t)^2 x'``.

        Examples
        --------
        >>> from kbm.model.builtins import get_model
        >>> get_model("sedf").dissipative_force()
        -beta*mu*x**2*xdot + mu*xdot
        """
        return sp.expand(mu * self.F - self.conservative_force(), multinomial=False)

    def dissipation_parts(self) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
        """The dissipation integrand ``-D x'`` split by the sign of its terms' coefficients.

        ``D`` is :meth:`dissipative_force`; returns ``(plus, minus, factor)`` with
        ``-D x' = factor*plus - minus`` (paper eqs. 10-11: ``Gamma = beta Gamma_+ -
        Gamma_-``).  ``factor`` is :attr:`gain_factor` when it divides every
        positive term, else 1.

        Examples
        --------
        >>> from kbm.model.builtins import get_model
        >>> get_model("sedf").dissipation_parts()
        (mu*x**2*xdot**2, mu*xdot**2, beta)
        """
        # powers of sums stay whole (multinomial=False): the stage-attached excitation
        # beta (x - v t)^2 x'^2 is one energy-supplying term, not three of mixed signs
        integrand = sp.expand(-self.dissipative_force() * xdot, multinomial=False)
        plus, minus = [], []
        for term in sp.Add.make_args(integrand):
            coeff = term.as_coeff_Mul()[0]
            (plus if coeff > 0 else minus).append(term)
        plus_e, minus_e = sp.Add(*plus), -sp.Add(*minus)
        g = self.gain_factor
        if g != 1 and plus and all(sp.expand(term / g).free_symbols.isdisjoint(g.free_symbols)
                                   for term in plus):
            return sp.expand(plus_e / g), minus_e, g
        return plus_e, minus_e, sp.Integer(1)

    def with_stage_velocity(self, v: object) -> "Oscillator":
        """The driven variant pulled by a stage at velocity ``v`` (paper eq. 3).

        The spring ``Omega^2 (x - v t)`` adds the drive ``omega0^2 v t``; ``v = 0``
        returns the model unchanged; a :class:`sympy.Symbol` keeps ``v`` a parameter.
        A :attr:`stage_relative` part of ``F`` is re-evaluated at ``x - v t``.

        Raises
        ------
        kbm.errors.ParameterError
            If ``v`` is not a finite real number.
        """
        # a symbol keeps v a parameter (one compiled template for every stage velocity)
        vv = v if isinstance(v, sp.Symbol) else parameter_value("v", v)
        if vv == 0:
            return self
        rel = self.stage_relative
        moved = rel.subs(x, x - vv * t)
        return Oscillator(self.name, self.F - rel + moved, self.omega0,
                          self.description.replace("with v = 0", f"with v = {vv}"),
                          self.physical, self.defaults, self.omega0**2 * vv * t,
                          self.gain_factor, moved)
