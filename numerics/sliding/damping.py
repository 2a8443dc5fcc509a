"""The damping's derivative ``dD/dx' = -mu dF/dx'`` of a slider model, derived once from its
symbolic ``F`` (sympy), for the stiffness estimate of :mod:`numerics.sliding.stiffness` and
the runaway rate of the friction map (:meth:`numerics.sliding.driven.DrivenSystem.damping`).

The model is defined once, in :mod:`kbm` (:func:`kbm.model.builtins.get_model`, or any
:class:`~kbm.model.oscillator.Oscillator` with a spring ``omega0``); this module
differentiates its ``F`` with respect to the velocity, splits the result by frame (the part of
``F`` attached to the stage, :attr:`~kbm.model.oscillator.Oscillator.stage_relative`, is
measured by the spring's extension ``x - v t``), lambdifies it once per model
(:func:`numerics._memo.memo`, as :mod:`numerics.sliding.driven` does for the equations) and
prints it for the messages.  It also derives the pieces of the envelope: the first-order KBM
amplitude ``A`` of the self-excited cycle (the stable positive root of the first-order
amplitude rate ``A_1(a)`` of :func:`kbm.derive`, the toolkit's one recursion), the largest
pinning force, and whether the spring can pull the slider through its stage-attached
damping.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np
import sympy as sp

from kbm import derive
from kbm.errors import KBMError, ParameterError
from kbm.model.builtins import Oscillator, get_model
from kbm.parameters.bound import bind
from kbm.symbols import a as _A, mu as MU, x as X, xdot as V

from numerics._memo import memo

__all__ = ["DampingDerivative", "damping_derivative", "damping_text", "damping_rate",
           "amplitude", "follows_stage", "scaled_values"]

#: the spring's extension ``x - v t`` (the variable of a stage-attached damping)
_Z = sp.Symbol("x_rel")


@dataclass(frozen=True, eq=False)
class DampingDerivative:
    """``dD/dx' = -mu dF/dx'`` of one slider model, split by frame, with its envelope's pieces.

    Attributes
    ----------
    lab, stage
        The derivative of the lab-frame part of ``mu F`` (in ``x, xdot``) and of its
        stage-attached part (in ``x_rel = x - v t`` and ``xdot``), so ``dD/dx' = lab(x) +
        stage(x - v t)``.
    text
        ``|dD/dx'|`` for the messages, printed from the same expressions.
    rate
        ``rate(values, x, xdot, x - v t)``: ``|dD/dx'|`` at a state (``values`` the scaled
        parameters).
    grid, states
        ``grid(values, x, xdot, x - v t)``: ``dD/dx'`` (signed) on numpy arrays, and whether
        it depends on each of ``x, xdot, x - v t``.
    power
        The coefficients (highest power first) of the first-order amplitude rate ``A_1(a)``
        of :func:`kbm.derive` (``a' = mu A_1(a)``; ``A_1 = -<F sin phi>/omega0`` on the cycle
        ``x = a cos phi``, whose positive roots are those of the mean power of the
        dissipative force), a polynomial in ``a`` (empty if not).
    omega, pinning, stage_force
        The spring's ``omega0``, the largest pinning force (``sin``, ``cos`` at 1) and
        ``stage_force(values, z, xdot)``: the stage-attached part of ``mu F`` at the spring's
        extension ``z`` (numpy).
    """

    lab: sp.Expr
    stage: sp.Expr
    text: str
    rate: Callable
    grid: Callable
    states: tuple[bool, bool, bool]
    power: tuple
    omega: Callable
    pinning: Callable
    stage_force: Callable


def _lambdified(expr: sp.Expr) -> Callable[[Mapping], float]:
    """``expr`` of the parameters as a function of a mapping of their values."""
    free = tuple(sorted(str(s) for s in expr.free_symbols))
    f = sp.lambdify([sp.Symbol(n) for n in free], expr, modules="math")

    def value(vals: Mapping[str, float]) -> float:
        try:
            return float(f(*(vals[n] for n in free)))
        except KeyError as e:
            raise ParameterError(f"the damping's estimate needs the parameter {e.args[0]}; "
                                 f"give it with -p {e.args[0]}=VALUE") from None
    return value


def _text(lab: sp.Expr, stage: sp.Expr) -> str:
    """``|dD/dx'| = mu |...|`` printed from the derivative (sympy's order, ``^`` powers)."""
    inner = sp.expand((lab + stage) / MU)
    lead = "mu"
    if MU in inner.free_symbols:  # mu is not a factor
        inner, lead = sp.expand(lab + stage), ""
    body = sp.sstr(inner).replace("**", "^").replace("*", " ").replace(str(_Z), "(x - v t)")
    if lab + stage == 0:
        text = "0"
    elif inner == 1 and lead:
        text = "mu"
    elif inner.free_symbols & {X, V, _Z}:
        text = f"{lead} |{body}|".strip()
    else:
        text = f"{lead} {body}".strip()
    grows = " (growing with |x| ~ v t)" if X in lab.free_symbols else ""
    return f"|dD/dx'| = {text}{grows}"


@memo(maxsize=16)
def damping_derivative(model: str | Oscillator) -> DampingDerivative:
    """``dD/dx' = -mu dF/dx'`` of a slider model, derived once from its symbolic ``F``.

    Parameters
    ----------
    model
        A built-in slider's name (:data:`kbm.model.builtins.SLIDERS`) or an
        :class:`~kbm.model.oscillator.Oscillator` with ``omega0`` its spring
        (``stage_relative`` the part of ``F`` measured from the stage).

    Returns
    -------
    DampingDerivative
        The derivative by frame, its message text, and the pieces of the envelope of
        :func:`damping_envelope` (module docstring).
    """
    m = get_model(model) if isinstance(model, str) else model
    rel = m.stage_relative
    lab = sp.expand(-MU * sp.diff(m.F - rel, V))
    stage = sp.expand(-MU * sp.diff(rel, V)).subs(X, _Z)
    w = m.omega0
    try:
        rate = sp.Poly(sp.expand(derive(m, 1).A[1]), _A)
        power = tuple(_lambdified(k) for k in rate.all_coeffs())
    except (sp.PolynomialError, KBMError):
        power = ()
    cons = m.conservative_force().replace(lambda e: isinstance(e, (sp.sin, sp.cos)),
                                          lambda e: sp.Integer(1))
    pin = sp.Add(*(sp.Abs(term) for term in sp.Add.make_args(sp.expand(cons))
                   if X not in term.free_symbols))
    held = (MU * rel).subs(X, _Z)
    held_names = tuple(sorted(str(s) for s in held.free_symbols - {V, _Z}))
    f_held = sp.lambdify((_Z, V, *map(sp.Symbol, held_names)), held, modules="numpy")

    def stage_force(vals: Mapping[str, float], z, xdot):
        return f_held(z, xdot, *(vals[n] for n in held_names))
    g = lab + stage
    names = tuple(sorted(str(s) for s in g.free_symbols - {X, V, _Z}))
    args = (X, V, _Z, *map(sp.Symbol, names))
    f, f_np = sp.lambdify(args, g, modules="math"), sp.lambdify(args, g, modules="numpy")

    def rate(vals: Mapping[str, float], x: float, xdot: float, z: float) -> float:
        return abs(float(f(x, xdot, z, *(vals[n] for n in names))))

    def grid(vals: Mapping[str, float], x, xdot, z) -> np.ndarray:
        return f_np(x, xdot, z, *(vals[n] for n in names))
    return DampingDerivative(lab=lab, stage=stage, text=_text(lab, stage), rate=rate,
                             grid=grid, states=tuple(s in g.free_symbols for s in (X, V, _Z)),
                             power=power, omega=_lambdified(w), pinning=_lambdified(pin),
                             stage_force=stage_force)


def scaled_values(model: str | Oscillator, p: Mapping[str, float]) -> dict[str, float]:
    """The model's scaled parameter values from the physical ones (``v`` aside)."""
    m = get_model(model) if isinstance(model, str) else model
    own = {k: v for k, v in p.items() if k != "v"}
    return dict(bind(m, own).floats)


def amplitude(d: DampingDerivative, vals: Mapping[str, float]) -> float:
    """The first-order KBM amplitude ``A`` of the self-excited cycle (0 for none)."""
    if not d.power:
        return 0.0
    coeffs = np.array([c(vals) for c in d.power])
    if not np.any(coeffs):
        return 0.0
    roots = np.roots(coeffs)
    slope = np.polyder(coeffs)
    stable = [r.real for r in roots if abs(r.imag) <= 1e-12 * abs(r) and r.real > 0
              and np.polyval(slope, r.real) < 0]
    return max(stable, default=0.0)


def follows_stage(d: DampingDerivative, vals: Mapping[str, float], v: float, w: float) -> bool:
    """Whether the spring can pull the slider through its stage-attached damping at the stage
    velocity: ``max over lags z < 0 of (w^2 |z| + mu F_stage(z, x' = v))`` above the pinning
    force (else the lag grows with ``v t``)."""
    z = -np.concatenate(([0.0], np.geomspace(1e-6, 1e6, 601)))
    pull = w * w * -z + np.broadcast_to(d.stage_force(vals, z, v), z.shape)
    return bool(np.max(pull) >= d.pinning(vals))


def damping_text(model: str | Oscillator) -> str:
    """``|dD/dx'|`` of ``model`` for the messages, printed from its derivative
    (:func:`damping_derivative`: ``mu`` for the CDC, ``mu |beta x^2 - 1|`` for the SEDF)."""
    return damping_derivative(model).text


def damping_rate(model: str | Oscillator, p: Mapping[str, float]
                 ) -> Callable[[float, object], float]:
    """``|dD/dx'|`` at time ``t`` and state ``y = (x, x', ...)`` (:func:`damping_derivative`)."""
    d, vals, v = damping_derivative(model), scaled_values(model, p), float(p.get("v", 0.0))
    return lambda t, y: d.rate(vals, float(y[0]), float(y[1]), float(y[0]) - v * float(t))
