"""The driven slider, compiled: long stick-slip runs with their work and dissipation integrals.

A slider model of :mod:`kbm.model.builtins` (``sedf``, ``cdc``, ``sedf_comoving``) pulled by its
stage at velocity ``v`` is, with the time kept as a state ``tau``, the autonomous system

``x' = x_dot``, ``x_dot' = a(x, x_dot, tau)``, ``tau' = 1``,
``G_+' = plus``, ``G_-' = minus``, ``W' = F x_dot``, ``J' = F``,

where ``a`` is the model's acceleration (the model is defined once, in :mod:`kbm`), ``F =
Omega^2 (v tau - x)`` is the spring force (the friction force of the paper),
``plus``/``minus`` are the two parts of the dissipation integrand (paper eq. 11,
``Gamma = beta G_+ - G_-``), ``W`` is the work of the spring on the slider and ``J`` the
impulse of the spring (so the mean friction force over a window is ``Delta J/Delta t``,
an integral, not an average of samples).  Keeping ``tau`` a state lets a run continue
from its last state, block after block.

The equations are printed once per model with ``v`` and the other parameters as
arguments and compiled by numba into the adaptive DOP853 of :mod:`numerics.flow.jit`
(:class:`DrivenSystem`, engine ``"compiled"``); :func:`scipy.integrate.solve_ivp`
(``DOP853``, or ``LSODA``) on the lambdified same expressions is the reference path
(engine ``"scipy"``).  The energy ``E = x_dot^2/2 + V(x) + Omega^2 (x - v tau)^2/2``
(``V`` the periodic potential) obeys ``v Delta J = Gamma + Delta E`` exactly, which
:mod:`numerics.sliding.friction` uses as its built-in check.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Callable

import numpy as np
import sympy as sp

from kbm.errors import ParameterError
from kbm.parameters.bound import bind
from kbm.model.builtins import SLIDERS, Oscillator, get_model
from kbm.symbols import t as T, x as X, xdot as V

from numerics._memo import memo
from numerics.errors import IntegrationError
from numerics.flow.jit import jit_available, jit_flow
from numerics.flow.template import conservative_potential
from numerics.sliding.damping import damping_derivative

__all__ = ["DrivenSystem", "Block", "driven_system", "slider_equations", "physical_values",
           "ENGINES", "N_STATES"]

#: the two integration paths: numba-compiled DOP853, and scipy's solve_ivp (reference)
ENGINES = ("compiled", "scipy")
#: the states (x, x_dot, tau, G_plus, G_minus, W, J)
N_STATES = 7
_V_STAGE = sp.Symbol("v")


@dataclass(frozen=True, eq=False)
class Block:
    """Samples of one stretch of a driven run: ``y[i] = (x, x_dot, tau, G_+, G_-, W, J)`` at
    equally spaced times, the first row the starting state."""

    y: np.ndarray
    steps: int
    status: int = 0
    message: str = ""

    @property
    def last(self) -> np.ndarray:
        """The last finite state (the whole block's last row when the integration succeeded)."""
        good = np.nonzero(np.isfinite(self.y[:, 0]))[0]
        return self.y[good[-1]]


@dataclass(frozen=True)
class _Template:
    """A slider model's extended equations with every parameter (``v`` too) an argument."""

    model: Oscillator
    names: tuple[str, ...]
    exprs: tuple[sp.Expr, ...]
    states: tuple[sp.Symbol, ...]
    f_rhs: Callable
    f_energy: Callable
    f_potential: Callable
    f_factor: Callable
    f_omega: Callable


@memo(maxsize=8)
def _template(name: str) -> _Template:
    model = get_model(name).with_stage_velocity(_V_STAGE)
    names = tuple(sorted(set(model.parameters) | {"mu"}))
    P = [sp.Symbol(n) for n in names]
    y = sp.symbols(f"y0:{N_STATES}")
    es = {X: y[0], V: y[1], T: y[2]}
    spring = (model.drive - model.omega0**2 * X).subs(es)
    plus, minus, factor = model.dissipation_parts()
    exprs = (y[1], model.acceleration().subs(es), sp.Integer(1), plus.subs(es), minus.subs(es),
             spring * y[1], spring)
    periodic = conservative_potential(get_model(name))  # the substrate's, Delta/k (1 - cos k x)
    energy = (V**2 / 2 + periodic + (model.omega0**2 * X - model.drive)**2
              / (2 * model.omega0**2)).subs(es)
    return _Template(
        model=model, names=names, exprs=exprs, states=y,
        f_rhs=sp.lambdify((T, y, *P), list(exprs), modules="math", cse=True),
        f_energy=sp.lambdify((y, *P), energy, modules=["numpy", "scipy"]),
        f_potential=sp.lambdify((X, *P), periodic, modules="math"),
        f_factor=sp.lambdify(P, factor, modules="math"),
        f_omega=sp.lambdify(P, model.omega0, modules="math"))


@memo(maxsize=8)
def _compiled(name: str, enabled: bool):
    if not enabled:
        return None
    tp = _template(name)
    return jit_flow(tp.exprs, T, tp.states, [sp.Symbol(n) for n in tp.names],
                    n_state=N_STATES)


@dataclass(frozen=True, eq=False)
class DrivenSystem:
    """One slider at bound parameter values, ready to integrate block after block.

    Attributes
    ----------
    model
        The slider's name (:data:`kbm.model.builtins.SLIDERS`).
    params
        Every parameter value as a float (physical names: ``mu, Delta, lam, Omega, v``
        and ``beta`` where the model has it).
    engine
        ``"compiled"`` or ``"scipy"``.
    gain_factor
        ``Gamma = gain_factor G_+ - G_-`` (``beta`` for the SEDF, 1 for the CDC).
    """

    model: str
    params: Mapping[str, float]
    engine: str
    pvec: tuple[float, ...]
    gain_factor: float
    omega: float
    rtol: float
    atol: float
    _flow: Callable | None
    _tp: _Template

    @property
    def v(self) -> float:
        return self.params["v"]

    @property
    def lam(self) -> float:
        return self.params["lam"]

    @property
    def has_source(self) -> bool:
        """Whether the model feeds energy in (a self-excitation: ``G_-`` not identically 0)."""
        return self._tp.exprs[4] != 0

    def initial_state(self, x0: float = 0.0, v0: float = 0.0) -> np.ndarray:
        """``(x0, v0)`` at ``tau = 0`` with zero integrals."""
        return np.array([x0, v0, 0.0, 0.0, 0.0, 0.0, 0.0])

    def energy(self, y: np.ndarray) -> np.ndarray:
        """``E = x_dot^2/2 + V(x) + Omega^2 (x - v tau)^2/2`` of states ``y`` (rows)."""
        y = np.atleast_2d(y)
        return np.asarray(self._tp.f_energy(y.T, *self.pvec), dtype=float)

    def damping(self, y: np.ndarray) -> np.ndarray:
        """The local damping rate ``-d x_dot'/d x_dot`` at states ``y`` (rows): the model's one
        derivative :func:`~numerics.sliding.damping.damping_derivative`, its stage-attached
        part at the spring's extension ``x - v tau``."""
        y = np.atleast_2d(y)
        rate = damping_derivative(self.model).grid(dict(zip(self._tp.names, self.pvec)),
                                                   y[:, 0], y[:, 1], y[:, 0] - self.v * y[:, 2])
        return np.broadcast_to(np.asarray(rate, dtype=float), (len(y),))

    def gamma(self, y: np.ndarray) -> np.ndarray:
        """The dissipation ``Gamma = gain_factor G_+ - G_-`` of states ``y`` (rows)."""
        y = np.atleast_2d(y)
        return self.gain_factor * y[:, 3] - y[:, 4]

    def run(self, y0: np.ndarray, duration: float, n_out: int,
            max_steps: int = 50_000_000, partial: bool = False) -> Block:
        """Integrate from the state ``y0`` over ``duration``, sampled at ``n_out + 1`` times.

        With ``partial=True`` a failed integration returns the rows reached (NaN after)
        with its ``status`` and ``message`` instead of raising.

        Raises
        ------
        IntegrationError
            If the integrator fails (with the time reached and the reason).
        """
        y0 = np.asarray(y0, dtype=float)
        if self._flow is not None:
            res = self._flow(y0, duration, self.pvec, self.rtol, self.atol, n_out, max_steps)
            blk = Block(y=res.y, steps=res.steps, status=res.status, message=res.message)
        else:
            blk = self._run_scipy(y0, duration, n_out)
        if blk.status != 0 and not partial:
            raise IntegrationError(self._failure(y0, blk.y, blk.message))
        return blk

    def _run_scipy(self, y0: np.ndarray, duration: float, n_out: int) -> Block:
        from scipy.integrate import solve_ivp

        f, p = self._tp.f_rhs, self.pvec
        ts = np.linspace(0.0, duration, n_out + 1)
        with np.errstate(all="ignore"):
            sol = solve_ivp(lambda t, y: f(t, y, *p), (0.0, duration), y0, method="DOP853",
                            t_eval=ts, rtol=self.rtol, atol=self.atol,
                            max_step=duration / n_out)
        y = np.full((len(ts), len(y0)), np.nan)
        y[:sol.y.shape[1]] = sol.y.T
        ok = sol.status == 0 and sol.y.shape[1] == len(ts)
        return Block(y=y, steps=int(sol.nfev // 12), status=0 if ok else 1,
                     message="" if ok else sol.message)

    def _failure(self, y0, y, why: str) -> str:
        good = np.isfinite(y[:, 0])
        tau = float(y[good][-1, 2]) if good.any() else float(y0[2])
        return (f"the driven {self.model} ({_fmt(self.params)}) failed at t = {tau:.6g}: "
                f"{why}; the motion may diverge (lower Delta or mu, or raise rtol)")


def _fmt(params: Mapping[str, float]) -> str:
    return ", ".join(f"{k}={v:g}" for k, v in params.items())


def driven_system(model: str, params: Mapping[str, object], *, engine: str = "compiled",
                  rtol: float = 1e-9, atol: float = 1e-9) -> DrivenSystem:
    """The slider ``model`` at ``params`` (``v > 0`` among them), ready to integrate.

    Parameters
    ----------
    model
        ``"sedf"`` (paper eq. 3), ``"cdc"`` (eq. 12) or ``"sedf_comoving"``.
    params
        Physical parameters (``mu, Delta, lam, v``, ``beta`` for the self-excited
        sliders, ``Omega`` = 1 by default).
    engine
        ``"compiled"`` (numba DOP853; falls back on scipy without numba) or ``"scipy"``.

    Raises
    ------
    kbm.errors.ParameterError
        For an unknown slider, a missing or non-finite parameter, ``v <= 0``,
        ``lam <= 0``, ``Omega <= 0``, ``mu <= 0`` or ``Delta < 0``.
    """
    if model not in SLIDERS:
        raise ParameterError(f"the friction laws need a slider model ({', '.join(SLIDERS)}), "
                             f"got {model!r}")
    if engine not in ENGINES:
        raise ParameterError(f"engine must be one of {', '.join(ENGINES)}, got {engine!r}")
    for name, val in (("rtol", rtol), ("atol", atol)):
        if not (isinstance(val, (int, float)) and 1e-14 <= val <= 1e-3):
            raise ParameterError(f"{name} must be between 1e-14 and 1e-3, got {val!r}")
    if "v" not in params:
        raise ParameterError("the stage velocity is missing: give params={'v': 0.01} (v > 0)")
    p = physical_values(params)
    p.setdefault("Omega", 1.0)
    tp, pvec = slider_equations(model, p)
    flow = _compiled(model, jit_available()) if engine == "compiled" else None
    return DrivenSystem(model=model, params=p, engine="compiled" if flow else "scipy",
                        pvec=pvec, gain_factor=float(tp.f_factor(*pvec)),
                        omega=float(tp.f_omega(*pvec)), rtol=float(rtol), atol=float(atol),
                        _flow=flow, _tp=tp)


def slider_equations(model: str, params: Mapping[str, float]) -> tuple[_Template, tuple]:
    """The slider's extended equations (states ``x, x_dot, tau, G_+, G_-, W, J``; every
    parameter, ``v`` too, an argument) and the parameter vector at the physical values
    ``params`` (``v = 0`` allowed), shared by :class:`DrivenSystem` and the reference path
    :func:`numerics.sliding.reference.slide`.

    Raises
    ------
    kbm.errors.ParameterError
        For a parameter the slider does not take, or one it needs and is not given.
    """
    tp = _template(model)
    base = get_model(model)
    takes = ["mu", "Delta", "lam", "Omega", "v"] + (["beta"] if "beta" in base.parameters else [])
    unknown = sorted(set(params) - set(takes) - set(base.parameters))
    if unknown:
        raise ParameterError(f"unknown parameter {unknown[0]!r} for the slider {model}; it "
                             f"takes {', '.join(takes)}")
    bound = bind(tp.model, params)
    bound.require(tp.names, what="the driven slider")
    return tp, tuple(float(bound.values[n]) for n in tp.names)


def physical_values(params: Mapping[str, object], *, standing: bool = False
                    ) -> dict[str, float]:
    """A slider's physical parameters as finite floats, checked: ``v > 0`` (``v >= 0`` with
    ``standing``: the stage may rest), ``lam, Omega, mu > 0``, ``Delta >= 0`` where given;
    shared by :func:`driven_system` and :func:`numerics.sliding.reference.slide`.

    Raises
    ------
    kbm.errors.ParameterError
        Naming the parameter, the rule and the value given.
    """
    p = {k: _number(k, v) for k, v in params.items()}
    rules = (("v", standing, "the stage pulls forward; mirror x for the other direction"),
             ("lam", False, "the period of the potential"), ("Omega", False, "the spring"),
             ("mu", False, ""), ("Delta", True, ""))
    for name, zero, why in rules:
        if name in p and not (p[name] >= 0 if zero else p[name] > 0):
            raise ParameterError(f"{name} must be {'>=' if zero else '>'} 0"
                                 f"{f' ({why})' if why else ''}, got {p[name]:g}")
    return p


def _number(name: str, value: object) -> float:
    try:
        val = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"parameter {name} must be a number, got {value!r}") from None
    if not math.isfinite(val):
        raise ParameterError(f"parameter {name} must be finite, got {value!r}")
    return val
