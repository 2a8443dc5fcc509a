"""Oscillators with an explicit periodic forcing: ``x'' + omega0**2 x = mu F(x, x', theta)``.

``theta = nu t`` is the forcing angle and ``F`` is 2 pi-periodic in it: a polynomial in
``x`` and ``x'`` whose coefficients are trigonometric polynomials in ``theta`` (external
forcing ``h cos(theta)``, parametric forcing ``x cos(theta)``, both) for the exact engine
(:func:`~kbm.expansion.forced.derive_forced`), or any smooth function such as the washboard force
``sin(k x + theta)`` of a slider seen from its moving stage for the numeric backend
(:func:`~kbm.backend.forced.numeric_derive_forced`).  ``F`` may hold the forcing frequency ``nu``
polynomially (a stage velocity ``v = nu/k``).  The forcing
frequency is declared near a resonance ``nu = (p/q) omega0 + mu sigma``
(:class:`Resonance`; ``p/q = 1`` primary, ``1/3`` superharmonic, ``3`` subharmonic,
``2`` principal parametric); the forced KBM engine (:mod:`kbm.expansion.forced`) then
averages with the resonant phase ``phi = psi - (q/p) theta``.

Time dependence that is not periodic through ``theta`` is refused with the reason:
``t`` itself (``t*x``, ``exp(t)``), ``theta`` outside ``sin``/``cos`` (``theta*x``) and
``sin``/``cos`` of a non-integer multiple of ``theta`` (not 2 pi-periodic).

The built-in forced models are in :mod:`kbm.model.forced_builtins`; the checks of ``F`` in
:mod:`kbm.model.forced_checks`.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from fractions import Fraction

import sympy as sp

from ..errors import ModelError, ParameterError
from ..expansion.resonance import InternalResonance
from .builtins import Oscillator, get_model
from .oscillator import TO_GENERAL, OneDegree
from ..symbols import mu, parse, t, x, xdot
from .forced_checks import NonPeriodicError, check_state, check_theta, is_polynomial, nu, theta

__all__ = ["ForcedOscillator", "Resonance", "theta", "phi", "sigma", "nu", "add_forcing",
           "NonPeriodicError", "LAMBDA"]

#: the resonant phase ``phi = psi - (q/p) theta``
phi = sp.Symbol("phi")
#: the detuning ``sigma``: ``nu = (p/q) omega0 + mu sigma``
sigma = sp.Symbol("sigma")
#: the amplitude ``Lambda = K/(omega0**2 - nu**2)`` of the response to a hard forcing
LAMBDA = sp.Symbol("Lambda")

_RESERVED = {"a", "psi", "phi", "sigma", "nu", "t", "Lambda"}


@dataclass(frozen=True)
class Resonance:
    """The declared resonance ``nu = (p/q) omega0 + mu sigma`` (``p``, ``q`` coprime).

    The response's phase is ``psi = (q/p) theta + phi``; the resonant combinations of the
    two angles are the multiples of ``p psi - q theta = p phi``, and a periodic response has
    the period ``2 pi p / nu`` (``p`` forcing periods).

    Examples
    --------
    >>> Resonance.parse("1/3")
    Resonance(p=1, q=3)
    >>> Resonance.parse("2").ratio
    Fraction(2, 1)
    """

    p: int
    q: int

    def __post_init__(self) -> None:
        for v in (self.p, self.q):
            if not isinstance(v, int) or isinstance(v, bool) or v < 1:
                raise ParameterError(f"a resonance p/q needs positive integers, got "
                                     f"{self.p!r}/{self.q!r}")
        g = Fraction(self.p, self.q)
        if (g.numerator, g.denominator) != (self.p, self.q):
            raise ParameterError(f"write the resonance {self.p}/{self.q} in lowest terms: "
                                 f"{g.numerator}/{g.denominator}")

    @classmethod
    def parse(cls, text: "str | Resonance | tuple") -> "Resonance":
        """From ``"p/q"``, ``"p"``, a pair or a :class:`Resonance`."""
        if isinstance(text, Resonance):
            return text
        if isinstance(text, tuple):
            return cls(*text)
        try:
            r = Fraction(str(text).strip())
        except (ValueError, ZeroDivisionError):
            raise ParameterError(f"--resonance takes p/q with positive integers (e.g. 1/1, "
                                 f"1/3, 2), got {text!r}") from None
        if r <= 0:
            raise ParameterError(f"the resonance p/q must be positive, got {text!r}")
        return cls(r.numerator, r.denominator)

    @property
    def ratio(self) -> Fraction:
        """``p/q``: the forcing frequency over ``omega0`` at exact resonance."""
        return Fraction(self.p, self.q)

    def __str__(self) -> str:
        return f"{self.p}/{self.q}"


class ForcedOscillator(OneDegree):
    """``x'' + omega0**2 x = mu F(x, x', theta)``, ``theta = nu t``, ``F`` 2 pi-periodic in theta:
    the one type :class:`~kbm.model.coupled.CoupledOscillators` at ``N = 1`` with a forcing angle
    (``nu0 = (p/q) omega0``, the detuning ``sigma``, the resonance ``omega0 : nu = q : p``).

    Parameters
    ----------
    name, description
        As for :class:`kbm.model.builtins.Oscillator`.
    F
        The right-hand side over ``mu`` (string or sympy expression in ``x``, ``xdot``,
        ``theta``, parameters and, polynomially, the forcing frequency ``nu``); smooth.
    omega0
        The linear frequency: a positive rational number or a symbol.
    resonance
        The default declared resonance (``"1/1"``); the analysis may declare another.
    defaults
        Values of parameters that are not given.
    hard
        The amplitude ``K`` of a *hard* (order-one) forcing ``K cos(theta)`` on the
        right-hand side, ``x'' + omega0**2 x = mu F + K cos(theta)``, away from the primary
        resonance (Nayfeh & Mook 4.1.2-4.1.3: super- and subharmonic resonances).  The
        averaging shifts ``x = y + Lambda cos(theta)``, ``Lambda = K/(omega0**2 - nu**2)``,
        and expands ``y``.

    Raises
    ------
    kbm.errors.ModelError
        For ``mu`` in ``F``, a reserved name, or a bad ``omega0``.
    NonPeriodicError
        For time dependence that is not 2 pi-periodic in ``theta`` (the term named).
    kbm.errors.UnsupportedTermError
        For ``F`` that is not smooth in ``x``, ``xdot`` (the smooth replacement named) or
        not polynomial in ``nu``.

    Examples
    --------
    >>> m = ForcedOscillator("d", "-2*zeta*xdot - alpha*x**3 + h*cos(theta)")
    >>> m.F
    -alpha*x**3 + h*cos(theta) - 2*xdot*zeta
    >>> m.with_time().F
    -alpha*x**3 + h*cos(nu*t) - 2*xdot*zeta
    """

    case = "forced"

    def __init__(self, name: str, F: object, omega0: object = 1,
                 resonance: "Resonance | str" = Resonance(1, 1), description: str = "",
                 defaults: Mapping[str, object] | None = None, hard: object = 0) -> None:
        F = parse(F, extra=("theta",)) if isinstance(F, str) else sp.sympify(F)
        w0 = parse(omega0) if isinstance(omega0, str) else sp.sympify(omega0)
        res = Resonance.parse(resonance)
        K = parse(hard) if isinstance(hard, str) else sp.sympify(hard)
        if K.has(x, xdot, theta, t, mu) or any(s.name in _RESERVED for s in K.free_symbols):
            raise ModelError(f"the hard forcing amplitude K = {K} must be a constant (numbers "
                             "and parameters, no x, xdot, theta, t, mu or reserved names)")
        self._check_one(name, F, w0, _RESERVED - {"t"}, exact=True, free={nu})
        check_theta(F, name)
        check_state(F, name)
        self._store(name=name, rhs=(F.xreplace(TO_GENERAL),), omegas=(w0,),
                    description=description, defaults=defaults,
                    internal=(InternalResonance(1, 2, res.q, res.p, forcing=True),),
                    nu0=w0 * sp.Rational(res.p, res.q), nu_detuning="sigma",
                    hards=(K,) if K != 0 else ())
        self.__dict__["F"] = F  # the F given, as given

    @property
    def resonance(self) -> Resonance:
        """The declared resonance ``nu = (p/q) omega0 + mu sigma``."""
        r = self.internal[0]  # omega0 : nu = q : p
        return Resonance(r.q, r.p)

    @property
    def is_polynomial(self) -> bool:
        """Whether ``F`` is polynomial in ``x``, ``xdot`` (the exact engine's case); otherwise
        the numeric backend (:func:`kbm.backend.forced.numeric_derive_forced`) applies."""
        return is_polynomial(self.F)

    def with_hard(self, K: object) -> "ForcedOscillator":
        """The model with the hard forcing amplitude ``K`` (in place of its own)."""
        return ForcedOscillator(self.name, self.F, self.omega0, self.resonance,
                                self.description, self.defaults, K)

    def frequency(self, resonance: Resonance | str | None = None) -> sp.Expr:
        """``nu = (p/q) omega0 + mu sigma`` as an expression."""
        r = Resonance.parse(resonance) if resonance is not None else self.resonance
        return sp.Rational(r.p, r.q) * self.omega0 + mu * sigma

    def with_time(self, values: Mapping[str, object] | None = None) -> Oscillator:
        """The equivalent non-autonomous :class:`kbm.model.builtins.Oscillator` in ``t``.

        ``theta`` becomes ``nu t`` with the forcing frequency ``nu`` a parameter (the
        numerical side binds ``nu = (p/q) omega0 + mu sigma``); ``values`` are substituted
        first.
        """
        model = self.substitute(values) if values else self
        return Oscillator(model.name, model.F.subs(theta, nu * t), omega0=model.omega0,
                          description=model.description or f"forced model {model.name}",
                          drive=model.hard * sp.cos(nu * t))

    def hard_response(self, frequency: sp.Expr) -> sp.Expr:
        """``Lambda = K/(omega0**2 - nu**2)``: the amplitude of the response to the hard
        forcing at the forcing frequency ``frequency``."""
        return self.hard / (self.omega0**2 - frequency**2)

    def shifted(self, frequency: sp.Expr) -> sp.Expr:
        """``F(y + Lambda cos(theta), y' - Lambda nu sin(theta), theta)`` (``Lambda`` the
        symbol :data:`LAMBDA`, ``nu`` = ``frequency``): the right-hand side of
        ``y'' + omega0**2 y = mu F`` for ``y = x - Lambda cos(theta)``; ``F`` without a hard
        forcing."""
        if self.hard == 0:
            return self.F
        return sp.expand(self.F.xreplace({x: x + LAMBDA * sp.cos(theta),
                                          xdot: xdot - LAMBDA * frequency * sp.sin(theta)}))


def add_forcing(model: "Oscillator | str", forcing: str | sp.Expr,
                resonance: Resonance | str = "1/1", *,
                name: str | None = None) -> ForcedOscillator:
    """An autonomous model with a periodic forcing added to ``F``: ``F + forcing(x, x', theta)``.

    Examples
    --------
    >>> add_forcing("duffing", "h*cos(theta)").F
    h*cos(theta) - x**3
    """
    if isinstance(model, str):
        model = get_model(model)
    if not model.is_autonomous:
        raise NonPeriodicError(f"model {model.name!r} already depends on t; give the periodic "
                               "part through the forcing in theta instead")
    f = parse(forcing, extra=("theta",)) if isinstance(forcing, str) else forcing
    return ForcedOscillator(name or f"{model.name}+forcing", model.F + f, model.omega0,
                            Resonance.parse(resonance),
                            f"{model.description}, forced with mu*({f})",
                            dict(model.defaults))
