"""Oscillators with an explicit periodic forcing: ``x'' + omega0**2 x = mu F(x, x', theta)``.

``theta = nu t`` is the forcing angle and ``F`` is 2 pi-periodic in it: a polynomial in
``x`` and ``x'`` whose coefficients are trigonometric polynomials in ``theta`` (external
forcing ``h cos(theta)``, parametric forcing ``x cos(theta)``, both).  The forcing
frequency is declared near a resonance ``nu = (p/q) omega0 + mu sigma``
(:class:`Resonance`; ``p/q = 1`` primary, ``1/3`` superharmonic, ``3`` subharmonic,
``2`` principal parametric); the forced KBM engine (:mod:`kbm.forced.engine`) then
averages with the resonant phase ``phi = psi - (q/p) theta``.

Time dependence that is not periodic through ``theta`` is refused with the reason:
``t`` itself (``t*x``, ``exp(t)``), ``theta`` outside ``sin``/``cos`` (``theta*x``) and
``sin``/``cos`` of a non-integer multiple of ``theta`` (not 2 pi-periodic).

Built-in forced models (:func:`get_forced_model`):

``duffing-forced``  ``F = -2 zeta x' - alpha x^3 + h cos(theta)`` (Nayfeh & Mook 4.1), 1/1
``mathieu``         ``F = -x cos(theta)``, ``omega0 = 1/2`` (x'' + (delta + eps cos t) x = 0
                    near delta = 1/4), 2/1
``vdp-forced``      ``F = (1 - x^2) x' + h cos(theta)`` (entrainment), 1/1
``duffing-super``   ``F = -2 zeta x' - alpha x^3 + h cos(theta)``, superharmonic 1/3
``parametric``      ``F = -2 zeta x' - alpha x^3 - h x cos(theta)``, 2/1
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from fractions import Fraction

import sympy as sp

from ..errors import ModelError, NonAutonomousError, ParameterError, UnsupportedTermError
from ..models import Oscillator, get_model
from ..symbols import a, mu, parse, psi, t, x, xdot
from ..values import FrozenMap, parameter_value

__all__ = ["ForcedOscillator", "Resonance", "theta", "phi", "sigma", "nu", "get_forced_model",
           "forced_model_names", "add_forcing", "FORCED_MODELS", "NonPeriodicError"]

#: the forcing angle ``theta = nu t``
theta = sp.Symbol("theta")
#: the resonant phase ``phi = psi - (q/p) theta``
phi = sp.Symbol("phi")
#: the detuning ``sigma``: ``nu = (p/q) omega0 + mu sigma``
sigma = sp.Symbol("sigma")
#: the forcing frequency
nu = sp.Symbol("nu")

_RESERVED = {"a", "psi", "phi", "sigma", "nu", "t"}


class NonPeriodicError(NonAutonomousError):
    """The time dependence of ``F`` is not a 2 pi-periodic function of ``theta = nu t``."""


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


def _check_theta(F: sp.Expr, name: str) -> None:
    """Refuse time dependence that is not 2 pi-periodic in ``theta`` (the reason named)."""
    if t in F.free_symbols:
        bad = [term for term in sp.Add.make_args(sp.expand(F)) if term.has(t)]
        raise NonPeriodicError(
            f"F of model {name!r} depends on the time t itself ({bad[0]}): a forcing must be "
            "2*pi-periodic in theta = nu*t, and a term in t (t*x, exp(t)) grows or decays "
            "instead; write the drive through theta, e.g. h*cos(theta) or x*cos(2*theta)")

    def walk(e: sp.Expr) -> None:
        if not e.has(theta):
            return
        if e == theta:
            raise NonPeriodicError(
                f"F of model {name!r} has theta outside sin/cos: a term that grows with "
                "theta = nu*t is not a periodic forcing; use sin(k*theta), cos(k*theta)")
        if isinstance(e, (sp.sin, sp.cos)):
            arg = sp.expand(e.args[0])
            k = arg.coeff(theta)
            rest = sp.expand(arg - k * theta)
            if rest.has(theta) or rest.has(x, xdot) or not k.is_number:
                raise NonPeriodicError(
                    f"the term {e} of F is not a periodic forcing: the argument of sin/cos "
                    "must be k*theta + constant with an integer k")
            if not k.is_Integer:
                raise NonPeriodicError(
                    f"the term {e} of F is not 2*pi-periodic in theta (k = {k} is not an "
                    "integer); rescale the forcing frequency nu so that every frequency of the "
                    "drive is an integer multiple of nu")
            return
        if e.is_Add or e.is_Mul or (e.is_Pow and e.exp.is_Integer and e.exp > 0):
            for arg in e.args:
                walk(arg)
            return
        raise NonPeriodicError(
            f"the term {e} of F is not a periodic forcing: theta = nu*t may enter only through "
            "sin(k*theta) and cos(k*theta) with integer k (exp, powers of theta, ... are "
            "not 2*pi-periodic)")

    walk(F)


def _check_state(F: sp.Expr, name: str) -> None:
    """``F`` must be a polynomial in ``x``, ``x'`` (its coefficients may hold theta)."""
    for term in sp.Add.make_args(sp.expand(F)):
        for f in sp.Mul.make_args(term):
            if not f.has(x, xdot):
                continue
            if f in (x, xdot) or (f.is_Pow and f.base in (x, xdot) and f.exp.is_Integer
                                  and f.exp > 0):
                continue
            raise UnsupportedTermError(
                f"the term {f} of F (model {name!r}) is not supported by the forced KBM "
                "engine: F must be a polynomial in x and xdot whose coefficients are "
                "trigonometric polynomials in theta (sin(k*x), cos(k*x) are treated by the "
                "autonomous engine only); expand or approximate that term")


@dataclass(frozen=True)
class ForcedOscillator:
    """``x'' + omega0**2 x = mu F(x, x', theta)``, ``theta = nu t``, ``F`` 2 pi-periodic in theta.

    Parameters
    ----------
    name, description
        As for :class:`kbm.models.Oscillator`.
    F
        The right-hand side over ``mu`` (string or sympy expression in ``x``, ``xdot``,
        ``theta`` and parameters).
    omega0
        The linear frequency: a positive rational number or a symbol.
    resonance
        The default declared resonance (``"1/1"``); the analysis may declare another.
    defaults
        Values of parameters that are not given.

    Raises
    ------
    kbm.errors.ModelError
        For ``mu`` in ``F``, a reserved name, or a bad ``omega0``.
    NonPeriodicError
        For time dependence that is not 2 pi-periodic in ``theta`` (the term named).
    kbm.errors.UnsupportedTermError
        For ``F`` that is not polynomial in ``x``, ``xdot``.

    Examples
    --------
    >>> m = get_forced_model("duffing-forced")
    >>> m.F
    -alpha*x**3 + h*cos(theta) - 2*xdot*zeta
    >>> m.with_time().F
    -alpha*x**3 + h*cos(nu*t) - 2*xdot*zeta
    """

    name: str
    F: sp.Expr
    omega0: sp.Expr = sp.Integer(1)
    resonance: Resonance = Resonance(1, 1)
    description: str = ""
    defaults: Mapping[str, sp.Expr] = field(default_factory=dict)

    def __post_init__(self) -> None:
        F = parse(self.F, extra=("theta",)) if isinstance(self.F, str) else sp.sympify(self.F)
        object.__setattr__(self, "F", F)
        w0 = parse(self.omega0) if isinstance(self.omega0, str) else sp.sympify(self.omega0)
        object.__setattr__(self, "omega0", w0)
        object.__setattr__(self, "resonance", Resonance.parse(self.resonance))
        object.__setattr__(self, "defaults",
                           FrozenMap({k: sp.sympify(v) for k, v in self.defaults.items()}))
        if mu in F.free_symbols:
            raise ModelError(f"F of model {self.name!r} contains the small parameter mu; write "
                             "the equation as x'' + omega0^2 x = mu*F with F free of mu")
        for s in F.free_symbols | w0.free_symbols:
            if s.name in _RESERVED - {"t"}:
                raise ModelError(f"the symbol {s.name!r} is reserved (amplitude, phases, "
                                 "detuning and forcing frequency); rename that parameter")
        _check_theta(F, self.name)
        _check_state(F, self.name)
        if w0.has(x, xdot, theta, t):
            raise ModelError(f"omega0 = {w0} must be a constant")
        if w0.is_number:
            if not (w0.is_Rational and w0 > 0):
                raise ModelError(f"omega0 must be a positive rational number (or a symbol) "
                                 f"for the exact forced averaging, got {w0}")
        elif not w0.is_Symbol:
            raise ModelError(f"omega0 must be a positive number or a single symbol, got {w0}")

    @property
    def parameters(self) -> tuple[str, ...]:
        """Names of the parameters of ``F`` and ``omega0`` (sorted)."""
        syms = (self.F.free_symbols | self.omega0.free_symbols) - {x, xdot, theta}
        return tuple(sorted(s.name for s in syms))

    def substitute(self, values: Mapping[str, object]) -> "ForcedOscillator":
        """The model with some parameters replaced by exact values (``mu``, ``sigma`` and
        ``nu`` are not parameters of the model and are ignored)."""
        subs = {}
        for k, v in values.items():
            if k in ("mu", "sigma", "nu"):
                continue
            if k not in self.parameters:
                raise ParameterError(f"unknown parameter {k!r} for model {self.name!r}; its "
                                     f"parameters are {', '.join(self.parameters) or 'none'}")
            subs[sp.Symbol(k)] = parameter_value(k, v)
        return ForcedOscillator(self.name, self.F.subs(subs), self.omega0.subs(subs),
                                self.resonance, self.description,
                                {k: v for k, v in self.defaults.items() if sp.Symbol(k) not in subs})

    def resolve(self, values: Mapping[str, object] | None = None) -> dict[str, sp.Expr]:
        """Exact values of the given parameters (and ``mu``, ``sigma``), defaults filled in."""
        out = {k: parameter_value(k, v) for k, v in (values or {}).items()}
        for k in out:
            if k not in self.parameters and k not in ("mu", "sigma"):
                raise ParameterError(f"unknown parameter {k!r} for model {self.name!r}; its "
                                     f"parameters are {', '.join(self.parameters) or 'none'} "
                                     "(and mu, sigma)")
        for k, v in self.defaults.items():
            out.setdefault(k, v)
        return out

    def frequency(self, resonance: Resonance | str | None = None) -> sp.Expr:
        """``nu = (p/q) omega0 + mu sigma`` as an expression."""
        r = Resonance.parse(resonance) if resonance is not None else self.resonance
        return sp.Rational(r.p, r.q) * self.omega0 + mu * sigma

    def with_time(self, values: Mapping[str, object] | None = None) -> Oscillator:
        """The equivalent non-autonomous :class:`kbm.models.Oscillator` in ``t``.

        ``theta`` becomes ``nu t`` with the forcing frequency ``nu`` a parameter (the
        numerical side binds ``nu = (p/q) omega0 + mu sigma``); ``values`` are substituted
        first.
        """
        model = self.substitute(values) if values else self
        return Oscillator(model.name, model.F.subs(theta, nu * t), omega0=model.omega0,
                          description=model.description or f"forced model {model.name}")


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


# ----------------------------------------------------------------------------- built-ins
_zeta, _alpha, _h = sp.symbols("zeta alpha h")

FORCED_MODELS = {
    "duffing-forced": lambda: ForcedOscillator(
        "duffing-forced", -2 * _zeta * xdot - _alpha * x**3 + _h * sp.cos(theta),
        resonance=Resonance(1, 1),
        description="Duffing x'' + x = mu (-2 zeta x' - alpha x^3 + h cos nu t), "
                    "Nayfeh & Mook sec. 4.1.1 (primary resonance)"),
    "duffing-super": lambda: ForcedOscillator(
        "duffing-super", -2 * _zeta * xdot - _alpha * x**3 + _h * sp.cos(theta),
        resonance=Resonance(1, 3),
        description="Duffing x'' + x = mu (-2 zeta x' - alpha x^3 + h cos nu t) near "
                    "nu = 1/3 (superharmonic resonance; weak forcing: order >= 3)"),
    "mathieu": lambda: ForcedOscillator(
        "mathieu", -x * sp.cos(theta), omega0=sp.Rational(1, 2), resonance=Resonance(2, 1),
        description="Mathieu x'' + (1/4) x = -mu x cos(nu t), i.e. x'' + (delta + eps cos s) x "
                    "= 0 with s = nu t, delta = 1/(4 nu^2), eps = mu/nu^2"),
    "vdp-forced": lambda: ForcedOscillator(
        "vdp-forced", (1 - x**2) * xdot + _h * sp.cos(theta), resonance=Resonance(1, 1),
        description="forced van der Pol x'' - mu (1 - x^2) x' + x = mu h cos nu t "
                    "(entrainment)"),
    "parametric": lambda: ForcedOscillator(
        "parametric", -2 * _zeta * xdot - _alpha * x**3 - _h * x * sp.cos(theta),
        resonance=Resonance(2, 1),
        description="parametrically excited Duffing x'' + x = mu (-2 zeta x' - alpha x^3 "
                    "- h x cos nu t), principal parametric resonance"),
}


def forced_model_names() -> tuple[str, ...]:
    """Names of the built-in forced models."""
    return tuple(FORCED_MODELS)


def get_forced_model(name: str, params: Mapping[str, object] | None = None) -> ForcedOscillator:
    """A built-in forced model (see the module docstring), optionally with parameters set.

    Raises
    ------
    kbm.errors.ModelError
        For an unknown name (the known ones listed).
    """
    try:
        model = FORCED_MODELS[name]()
    except KeyError:
        raise ModelError(f"unknown forced model {name!r}; the built-in forced models are "
                         f"{', '.join(FORCED_MODELS)} (or add a forcing to any model with "
                         "--forcing EXPR in theta)") from None
    return model.substitute(params) if params else model
