"""Weakly nonlinear oscillators ``x'' + w0^2 x = eps F(x, x')``, defined once, symbolically.

Every model of the toolkit is an :class:`Oscillator`: the right-hand side ``F``
is a sympy expression in the symbols ``x``, ``xdot`` (and ``t`` for a driven,
non-autonomous model) and named parameters; the small parameter is ``mu``
(the paper's mu, epsilon in the textbooks).  The averaging in :mod:`kbm`
and the integrators in :mod:`numerics` both start from this one definition.

Built-in models (names used on the command line):

``vdp``               van der Pol, ``F = (1 - x^2) x'``
``duffing``           Duffing, ``F = -x^3``
``rayleigh``          Rayleigh, ``F = (1 - x'^2/3) x'`` (its velocity is a van der Pol variable)
``linear_damping``    ``F = -2 zeta x'``
``linear_stiffness``  ``F = -kappa x``
``sedf``              paper eq. (3), self-excited slider: ``F = -(beta x^2 - 1) x' - delta sin(k x)``
``cdc``               paper eq. (12), constant-damping slider: ``F = -x' - delta sin(k x)``
``sedf_comoving``     the SEDF with its self-excitation attached to the stage: equal to ``sedf``
                      at ``v = 0``; pulled, ``F = -(beta (x - v t)^2 - 1) x' - delta sin(k x)``

For ``sedf`` and ``cdc``, ``w0 = Omega``, ``delta = Delta/mu`` and ``k = 2 pi/lam``
(the scaled KBM form of the paper's physical parameters).  With a stage
velocity ``v != 0`` the spring pulls with ``Omega^2 (v t - x)``: the model gets
the drive ``Omega^2 v t`` (not multiplied by ``mu``) on the right-hand side,
``x'' + w0^2 x = mu F + drive(t)``, and is non-autonomous.

The paper's SEDF measures its self-excitation ``mu (beta x^2 - 1) x'`` by the
position ``x`` on the substrate, so a slider pulled over many wells meets an ever
larger damping ``mu beta x^2`` (its friction grows without bound, the paper's Fig. 6)
and has no steady sliding state.  ``sedf_comoving`` attaches the self-excitation to
the stage instead (it is measured by the spring's extension ``x - v t``, the
deflection of a tip from its support), which is invariant under
``x -> x + lam, t -> t + lam/v`` and so has friction laws
(:mod:`numerics.sliding`).

Parameter values are read by :mod:`kbm.values` and bound to a model once by
:mod:`kbm.bound` (:func:`kbm.bound.bind`), which builds on this module (never the other
way round).  This module is longer than
the project's ~350-line guide because it holds the model type together with the
catalogue of built-in models that instantiate it (half of it docstrings); the two
change together.

References
----------
M. D'Acunto, "Friction force for self-excited systems", eqs. (3), (4), (12).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace

import sympy as sp

from .errors import ModelError, NonAutonomousError, ParameterError
from .family import OscillatorFamily
from .symbols import mu, parse, t, x, xdot
from .values import FrozenMap, parameter_value

__all__ = ["Oscillator", "FrozenMap", "MODELS", "SLIDERS", "get_model",
           "custom_model", "check_state_names", "STATE_LIKE_NAMES", "parameter_value",
           "model_names"]

_STATE = {x, xdot, t}


def _expr(value: object) -> sp.Expr:
    """A sympy expression from code or user input: strings through the safe :func:`parse`,
    numbers and sympy objects as they are (never through ``str()``)."""
    if isinstance(value, str):
        return parse(value)
    try:
        return sp.sympify(value, strict=True)
    except sp.SympifyError:
        raise ModelError(f"cannot read {value!r} as an expression") from None


def _sorted_names(symbols) -> tuple[str, ...]:
    return tuple(sorted(s.name for s in symbols))


@dataclass(frozen=True)
class Oscillator(OscillatorFamily):
    """The oscillator ``x'' + omega0**2 x = mu F(x, xdot[, t]) + drive(t)``.

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
    >>> vdp = get_model("vdp")
    >>> vdp.F
    xdot*(1 - x**2)
    >>> vdp.acceleration()
    mu*xdot*(1 - x**2) - x
    """

    name: str
    F: sp.Expr
    omega0: sp.Expr = sp.Integer(1)
    description: str = ""
    physical: Mapping[str, sp.Expr] = field(default_factory=dict)
    defaults: Mapping[str, sp.Expr] = field(default_factory=dict)
    drive: sp.Expr = sp.Integer(0)
    gain_factor: sp.Expr = sp.Integer(1)
    stage_relative: sp.Expr = sp.Integer(0)

    def __post_init__(self) -> None:
        F = parse(self.F) if not isinstance(self.F, sp.Basic) else self.F
        w0 = _expr(self.omega0)
        object.__setattr__(self, "F", sp.sympify(F))
        object.__setattr__(self, "omega0", w0)
        drive = _expr(self.drive)
        object.__setattr__(self, "drive", drive)
        if drive.free_symbols & {x, xdot, mu}:
            raise ModelError(f"the drive {drive} of model {self.name!r} must depend on t and "
                             "parameters only")
        object.__setattr__(self, "physical", FrozenMap(self.physical))
        object.__setattr__(self, "defaults",
                           FrozenMap({k: _expr(v) for k, v in self.defaults.items()}))
        object.__setattr__(self, "gain_factor", _expr(self.gain_factor))
        rel = _expr(self.stage_relative)
        object.__setattr__(self, "stage_relative", rel)
        if rel != 0 and x not in rel.free_symbols:
            raise ModelError(f"stage_relative = {rel} of model {self.name!r} must be a part of F "
                             "that depends on x (it is re-evaluated at the spring extension "
                             "x - v t when the stage moves)")
        if mu in self.F.free_symbols:
            raise ModelError(f"F of model {self.name!r} contains the small parameter mu; "
                             "write the equation as x'' + omega0^2 x = mu*F with F free of mu")
        for s in (self.F.free_symbols | w0.free_symbols):
            if s.name in ("a", "psi"):
                raise ModelError(f"the symbol {s.name!r} is reserved for the KBM amplitude/phase; "
                                 "rename that parameter")
        if w0.free_symbols & _STATE:
            raise ModelError(f"omega0 = {w0} depends on the state; it must be a constant")
        if w0.is_number:
            if not (w0.is_real and w0 > 0):
                raise ModelError(f"omega0 must be a positive real number (omega0**2 > 0), got omega0 = {w0}")
        elif not isinstance(w0, sp.Symbol):
            raise ModelError(f"omega0 must be a positive number or a single symbol, got {w0}")

    # -- structure --------------------------------------------------------------------
    @property
    def parameters(self) -> tuple[str, ...]:
        """Names of the parameters of ``F``, ``omega0`` and the drive (sorted)."""
        syms = self.F.free_symbols | self.omega0.free_symbols | self.drive.free_symbols
        return _sorted_names(syms - _STATE)

    @property
    def dof(self) -> int:
        """One degree of freedom (:class:`kbm.family.OscillatorFamily`)."""
        return 1

    @property
    def forced(self) -> bool:
        """``False``: no forcing angle (a stage drive is ``drive``, not a forcing)."""
        return False

    @property
    def is_autonomous(self) -> bool:
        """``False`` when ``F`` or the drive depends on the time ``t`` explicitly."""
        return t not in (self.F.free_symbols | self.drive.free_symbols)

    def require_autonomous(self, what: str = "the KBM averaging") -> None:
        """Raise :class:`NonAutonomousError` if ``F`` depends on ``t``."""
        if not self.is_autonomous:
            raise NonAutonomousError(
                f"{what} needs an autonomous model, but {self.name!r} depends on t explicitly "
                f"(mu*F + drive = {self.acceleration() + self.omega0**2 * x}); "
                "set the stage velocity v = 0 or drop the time-dependent term (a drive "
                "periodic in t is treated by kbm.forced: kbm response --forcing EXPR in theta)")

    def acceleration(self) -> sp.Expr:
        """``x''`` as an expression: ``-omega0**2 x + mu F + drive``."""
        return -self.omega0**2 * x + mu * self.F + self.drive

    def conservative_force(self) -> sp.Expr:
        """The part of ``mu F`` that depends on ``x`` (and ``t``) only, without the drive."""
        return mu * self.F.subs(xdot, 0)

    def dissipative_force(self) -> sp.Expr:
        """The part of ``mu F`` that vanishes at ``x' = 0`` (damping and self-excitation)."""
        return sp.expand(mu * self.F - self.conservative_force())

    def dissipation_parts(self) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
        """The dissipation integrand ``-D x'`` split by the sign of its terms' coefficients.

        ``D`` is :meth:`dissipative_force`; returns ``(plus, minus, factor)`` with
        ``-D x' = factor*plus - minus`` (paper eqs. 10-11: ``Gamma = beta Gamma_+ -
        Gamma_-``).  ``factor`` is :attr:`gain_factor` when it divides every
        positive term, else 1.

        Examples
        --------
        >>> get_model("sedf").dissipation_parts()
        (mu*x**2*xdot**2, mu*xdot**2, beta)
        """
        # powers of sums stay whole (multinomial=False): the stage-attached excitation
        # beta (x - v t)^2 x'^2 is one energy-supplying term, not three of mixed signs
        damping = mu * self.F - self.conservative_force()
        integrand = sp.expand(-damping * xdot, multinomial=False)
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
        return replace(self, drive=self.omega0**2 * vv * t, F=self.F - rel + moved,
                       stage_relative=moved,
                       description=self.description.replace("with v = 0", f"with v = {vv}"))

    # -- parameters -------------------------------------------------------------------
    def resolve(self, values: Mapping[str, object] | None = None,
                *, use_defaults: bool = True) -> dict[str, sp.Expr]:
        """Map given parameter values (scaled or physical names) to the model's parameters.

        Parameters
        ----------
        values
            Numbers (or sympy expressions, or strings) by name.  Physical names
            of the paper (``Delta``, ``lam``) are converted with :attr:`physical`,
            which may need ``mu``.  ``mu`` itself is passed through.
        use_defaults
            Fill parameters that are not given from :attr:`defaults`.

        Returns
        -------
        dict
            Values by name of the model's own parameters (and ``mu`` if given).

        Raises
        ------
        kbm.errors.ParameterError
            For an unknown name, a value that is not a finite real number, or a
            physical parameter given without ``mu``.
        """
        values = dict(values or {})
        known = set(self.parameters) | {"mu"}
        phys_names: set[str] = set()
        for expr in self.physical.values():
            phys_names |= {s.name for s in sp.sympify(expr).free_symbols}
        out: dict[str, sp.Expr] = {}
        for name, raw in values.items():
            if name not in known and name not in phys_names:
                raise ParameterError(
                    f"unknown parameter {name!r} for model {self.name!r}; "
                    f"its parameters are {', '.join(sorted(known | phys_names))}")
            val = parameter_value(name, raw)
            out[name] = val
        for scaled, expr in self.physical.items():
            expr = sp.sympify(expr)
            need = {s.name for s in expr.free_symbols}
            given = need & set(out)
            if scaled in out and given - {"mu"}:
                raise ParameterError(f"give either {scaled} or {', '.join(sorted(given - {'mu'}))}, "
                                     "not both")
            if given - {"mu"} and scaled not in out:
                missing = need - set(out)
                if missing:
                    raise ParameterError(
                        f"{scaled} = {expr} needs {', '.join(sorted(missing))} as well")
                val = sp.sympify(expr.subs({sp.Symbol(n): out[n] for n in need}))
                if not (val.is_finite and val.is_real):
                    zero = sorted(n for n in need if out[n] == 0)
                    raise ParameterError(
                        f"{scaled} = {expr} is undefined for "
                        f"{', '.join(f'{n} = {out[n]}' for n in sorted(need))}"
                        + (f": give {' and '.join(zero)} != 0" if zero else ""))
                out[scaled] = val
        for name in list(out):
            if name in phys_names and name not in known:
                del out[name]
        if use_defaults:
            for name, val in self.defaults.items():
                out.setdefault(name, val)
        return out

    def substitute(self, values: Mapping[str, object]) -> "Oscillator":
        """The same model with some parameters replaced by values (see :meth:`resolve`)."""
        vals = self.resolve(values, use_defaults=False)
        subs = {sp.Symbol(k): v for k, v in vals.items() if k != "mu"}
        return Oscillator(
            name=self.name,
            F=self.F.subs(subs),
            omega0=sp.sympify(self.omega0).subs(subs),
            description=self.description,
            physical={k: v for k, v in self.physical.items() if k not in vals},
            defaults={k: v for k, v in self.defaults.items() if k not in vals},
            drive=self.drive.subs(subs),
            gain_factor=self.gain_factor.subs(subs),
            stage_relative=self.stage_relative.subs(subs),
        )




# ----------------------------------------------------------------------------- built-ins
_beta, _delta, _k, _Omega, _v = sp.symbols("beta delta k Omega v")
_zeta, _kappa, _Delta, _lam = sp.symbols("zeta kappa Delta lam")


def _vdp() -> Oscillator:
    return Oscillator("vdp", (1 - x**2) * xdot,
                      description="van der Pol oscillator x'' - mu (1 - x^2) x' + x = 0")


def _duffing() -> Oscillator:
    return Oscillator("duffing", -x**3, description="Duffing oscillator x'' + x + mu x^3 = 0")


def _rayleigh() -> Oscillator:
    return Oscillator("rayleigh", (1 - xdot**2 / 3) * xdot,
                      description="Rayleigh oscillator x'' - mu (1 - x'^2/3) x' + x = 0")


def _linear_damping() -> Oscillator:
    return Oscillator("linear_damping", -2 * _zeta * xdot,
                      description="linearly damped oscillator x'' + 2 mu zeta x' + x = 0 (exact)")


def _linear_stiffness() -> Oscillator:
    return Oscillator("linear_stiffness", -_kappa * x,
                      description="stiffness perturbation x'' + (1 + mu kappa) x = 0 (exact)")


_PHYSICAL = {"delta": _Delta / mu, "k": 2 * sp.pi / _lam}


def _sedf() -> Oscillator:
    return Oscillator(
        "sedf", -(_beta * x**2 - 1) * xdot - _delta * sp.sin(_k * x), omega0=_Omega,
        description="self-excited slider on a periodic potential, paper eq. (3) with v = 0: "
                    "x'' + mu (beta x^2 - 1) x' + Delta sin(2 pi x/lam) + Omega^2 x = 0",
        physical=_PHYSICAL, defaults={"Omega": 1}, gain_factor=_beta)


def _cdc() -> Oscillator:
    return Oscillator(
        "cdc", -xdot - _delta * sp.sin(_k * x), omega0=_Omega,
        description="constant-damping slider, paper eq. (12) with v = 0: "
                    "x'' + mu x' + Delta sin(2 pi x/lam) + Omega^2 x = 0",
        physical=_PHYSICAL, defaults={"Omega": 1})


def _sedf_comoving() -> Oscillator:
    excitation = -(_beta * x**2 - 1) * xdot
    return Oscillator(
        "sedf_comoving", excitation - _delta * sp.sin(_k * x), omega0=_Omega,
        description="self-excited slider with the self-excitation attached to the stage, with "
                    "v = 0: x'' + mu (beta (x - v t)^2 - 1) x' + Delta sin(2 pi x/lam) "
                    "+ Omega^2 (x - v t) = 0",
        physical=_PHYSICAL, defaults={"Omega": 1}, gain_factor=_beta,
        stage_relative=excitation)


#: the built-in models that have a stage (their spring can be pulled at a velocity v)
SLIDERS = ("sedf", "cdc", "sedf_comoving")


def _drive_variant(model: Oscillator, v: object) -> Oscillator:
    if model.name not in SLIDERS:
        raise ParameterError(f"unknown parameter 'v' for model {model.name!r}; only the "
                             f"sliders {' and '.join(SLIDERS)} have a stage velocity")
    return model.with_stage_velocity(v)


MODELS = {
    "vdp": _vdp,
    "duffing": _duffing,
    "rayleigh": _rayleigh,
    "linear_damping": _linear_damping,
    "linear_stiffness": _linear_stiffness,
    "sedf": _sedf,
    "cdc": _cdc,
    "sedf_comoving": _sedf_comoving,
}


def model_names() -> tuple[str, ...]:
    """Names of the built-in models."""
    return tuple(MODELS)


def get_model(name: str, params: Mapping[str, object] | None = None) -> Oscillator:
    """A built-in model, optionally with some parameters set.

    Parameters
    ----------
    name
        One of :func:`model_names`.
    params
        Parameter values by name; physical names (``Delta``, ``lam``) are
        converted to the scaled ones (``delta = Delta/mu``, ``k = 2 pi/lam``),
        which needs ``mu``.  A stage velocity ``v`` other than 0 (sedf, cdc)
        adds the spring drive ``Omega^2 v t`` and makes the model
        non-autonomous: the averaging refuses it, the integrators accept it.

    Raises
    ------
    kbm.errors.ModelError
        For an unknown model name.
    kbm.errors.ParameterError
        For an unknown parameter or a bad value.

    Examples
    --------
    >>> get_model("sedf", {"beta": 1, "Delta": "3/20", "mu": "1/10", "lam": 1}).F
    xdot*(1 - x**2) - 3*sin(2*pi*x)/2
    """
    try:
        model = MODELS[name]()
    except KeyError:
        raise ModelError(f"unknown model {name!r}; the built-in models are "
                         f"{', '.join(MODELS)} (or give your own F with custom_model)") from None
    params = dict(params or {})
    v = params.pop("v", None)
    if v is not None:
        model = _drive_variant(model, v)
    if params:
        model = model.substitute(params)
    return model


def custom_model(rhs: str | sp.Expr, *, omega0: object = 1, name: str = "custom") -> Oscillator:
    """A user's oscillator ``x'' + omega0**2 x = mu F`` from the expression ``F``.

    Parameters
    ----------
    rhs
        ``F`` as a string or sympy expression in ``x``, ``xdot`` and parameters.
    omega0
        The linear natural frequency (default 1).

    Raises
    ------
    kbm.errors.ModelError
        If the expression cannot be read or uses ``mu``, ``a`` or ``psi``, or
        ``omega0`` is not a positive number (or an expression in parameters).

    Examples
    --------
    >>> custom_model("-x**3 + (1 - x**2)*xdot").F
    -x**3 + xdot*(1 - x**2)
    """
    w0 = omega0
    if isinstance(omega0, str):
        try:  # a decimal number is read exactly: "1.5" is 3/2
            w0 = sp.Rational(omega0.strip())
        except (TypeError, ValueError, ZeroDivisionError):  # "1/0" is refused by parse
            w0 = parse(omega0)
    w0 = _expr(w0)
    if w0.has(x, xdot):
        raise ModelError(f"omega0 must not depend on x or xdot, got {omega0!r}")
    if w0.is_number and not (w0.is_real and w0.is_finite and w0 > 0):
        raise ModelError(f"omega0 must be a positive number (the linear frequency), got "
                         f"{omega0!r}")
    F = parse(rhs)
    check_state_names(F, rhs)
    return Oscillator(name, F, omega0=w0,
                      description=f"user model x'' + {omega0}^2 x = mu ({rhs})")


#: names a user may mean as the state but that would be read as parameters: refused in a
#: user's F with the state variables named (``v`` is also the stage velocity of the sliders)
STATE_LIKE_NAMES = ("v", "y", "u", "dx", "xd", "xp", "dxdt", "vel", "velocity", "x_dot",
                    "xprime", "dotx", "ydot", "X", "Xdot", "xdot_", "xddot")


def check_state_names(F: sp.Expr, text: object = None) -> None:
    """Refuse a user's ``F`` (other than 0) that depends on neither ``x`` nor ``xdot``, or uses a name that
    reads as a state variable (:data:`STATE_LIKE_NAMES`), naming the state variables.

    Without this, ``"v - v**3/3"`` (Rayleigh's damping meant in the velocity) is read with
    ``v`` as a parameter: F is then a constant and the averaging answers ``A_1 = 0``
    silently.

    Raises
    ------
    kbm.errors.ModelError
    """
    shown = F if text is None else text
    bad = sorted(s.name for s in F.free_symbols if s.name in STATE_LIKE_NAMES)
    if bad:
        raise ModelError(f"F = {shown} uses {', '.join(map(repr, bad))}, which would be read as "
                         "a parameter: the state variables are x (displacement) and xdot "
                         "(velocity), and t (time) for a driven model; write e.g. "
                         "'xdot - xdot**3/3'")
    if F != 0 and not F.has(x, xdot):  # F = 0 is the harmonic oscillator, exactly
        raise ModelError(f"F = {shown} depends on neither x nor xdot, so the averaging has "
                         "nothing to act on: the state variables are x (displacement) and "
                         "xdot (velocity), e.g. '(1 - x**2)*xdot'")

