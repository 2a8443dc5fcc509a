"""The compiled flow of ``N`` coupled oscillators, with its variational equations.

The state is ``y = (x_1..x_N, xdot_1..xdot_N)`` and the vector field
``(xdot, -omega**2 x + mu F(x, xdot))`` comes from the one symbolic definition of
:class:`kbm.model.coupled.CoupledOscillators`.  The extended system appends the monodromy
``Phi' = J Phi`` (``2N x 2N``, column by column) and the divergence integral
``int tr J dt`` (Liouville's formula: ``det Phi(T) = exp(int tr J dt)``), and is
compiled with the DOP853 stepper of :mod:`numerics.flow.jit` (scipy's ``solve_ivp``
is the fallback, and the benchmark's baseline).  Systems above
:data:`MAX_VARIATIONAL_DOF` degrees of freedom are compiled without the variational
equations (a chain of 64 sliders would need 16384 of them).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Callable

import numpy as np
import sympy as sp

from kbm.model.coupled import CoupledOscillators
from kbm.model.coupled_builtins import get_coupled_model
from kbm.errors import ParameterError
from kbm.symbols import mu as mu_symbol
from kbm.symbols import t as t_symbol
from numerics._memo import memo
from numerics.flow.jit import jit_flow

__all__ = ["CoupledFlow", "coupled_flow", "MAX_VARIATIONAL_DOF", "bind_coupled"]

#: bound on the integrator's steps over one period of the extended system (a Newton iterate
#: that wandered into a runaway orbit fails fast instead of integrating for minutes)
MONODROMY_MAX_STEPS = 200_000

#: most degrees of freedom for which the variational equations are compiled
MAX_VARIATIONAL_DOF = 8


def bind_coupled(model: CoupledOscillators | str, params: Mapping[str, object] | None
                 ) -> tuple[CoupledOscillators, dict[str, float]]:
    """The model and every parameter's value (``mu`` included), defaults filled in.

    Raises
    ------
    kbm.errors.ParameterError
        For an unknown name, a value that is not a finite number, or a parameter (or
        ``mu``) without a value.
    """
    if isinstance(model, str):
        model = get_coupled_model(model)
    given = model.resolve(params)  # the family's bound form (kbm.parameters.bound)
    fixed = model.with_frequencies(given)  # a frequency named by a parameter: its value
    if fixed is not model:
        given = {k: v for k, v in given.items() if k not in model.parameters
                 or k in fixed.parameters}
        model = fixed
    names = set(model.parameters) | {"mu"}
    values = {}
    for name in sorted(names):
        if name not in given:
            raise ParameterError(f"give a value to {name} (-p {name}=VALUE"
                                 f"{model.physical_hint(name)}); the parameters of "
                                 f"{model.name!r} are {', '.join(sorted(names))}")
        v = sp.sympify(given[name])
        if not (v.is_real and v.is_finite):
            raise ParameterError(f"{name} must be a finite real number, got "
                                 f"{dict(params or {}).get(name)}")
        values[name] = float(v)
    return model, values


@dataclass(frozen=True)
class CoupledFlow:
    """A compiled coupled system at given parameter values.

    Attributes
    ----------
    model
        The system.
    values
        Every parameter's value, ``mu`` included.
    dof
        ``N``.
    variational
        Whether the extended system (monodromy and divergence) is compiled.
    """

    model: CoupledOscillators
    values: Mapping[str, float]
    dof: int
    variational: bool
    _flow: Callable
    _p: np.ndarray
    _rhs: Callable

    def rhs(self, y: np.ndarray, t: float = 0.0) -> np.ndarray:
        """The vector field at the state ``y`` (2N values) and time ``t`` (which only a
        forced system's field depends on)."""
        return np.asarray(self._rhs(t, *y, *self._p), dtype=float)

    def at(self, **values: float) -> "CoupledFlow":
        """The same compiled system at other values of some of its parameters (the values
        are arguments of one compilation: nothing is bound or compiled again).

        Raises
        ------
        kbm.errors.ParameterError
            For a name that is not one of :attr:`values` (a physical name such as
            ``Delta`` is bound by :func:`coupled_flow`).
        """
        from dataclasses import replace

        unknown = sorted(set(values) - set(self.values))
        if unknown:
            raise ParameterError(f"{', '.join(unknown)}: not among the values of "
                                 f"{self.model.name!r} ({', '.join(self.values)})")
        new = {**dict(self.values), **{k: float(v) for k, v in values.items()}}
        names = sorted(self.values)
        return replace(self, values=new, _p=np.array([new[n] for n in names], dtype=float))

    @property
    def nu(self) -> float | None:
        """The forcing frequency ``nu0 + mu sigma`` of a forced system (else ``None``)."""
        m = self.model
        if not m.forced:
            return None
        sig = self.values.get(m.nu_detuning, 0.0) if m.nu_detuning else 0.0
        return float(m.nu0) + self.values["mu"] * sig

    def states(self, y0, t_end: float, n_out: int, rtol: float = 1e-10,
               atol: float = 1e-12, max_steps: int = 10**7) -> np.ndarray:
        """The state at ``n_out + 1`` equally spaced times on ``[0, t_end]``.

        Raises
        ------
        numerics.errors.IntegrationError
            If the integrator fails (the reason and the time are in the message).
        """
        from numerics.errors import IntegrationError

        y0 = np.asarray(y0, dtype=float)
        res = self._flow(y0, t_end, self._p, rtol, atol, n_out, max_steps)
        if res.status:
            ok = np.isfinite(res.y[:, 0])
            reached = t_end * (int(ok.sum()) - 1) / n_out
            raise IntegrationError(f"the integration of {self.model.name} failed before "
                                   f"t = {t_end:g} (last output at t = {reached:.6g}): "
                                   f"{res.message}")
        return res.y

    def monodromy(self, y0, T: float, rtol: float = 1e-11, atol: float = 1e-12
                  ) -> tuple[np.ndarray, np.ndarray, float]:
        """``(y(T), Phi(T), int_0^T tr J dt)`` from one integration of the extended system."""
        n2 = 2 * self.dof
        if not self.variational:
            raise ParameterError(f"the monodromy of {self.dof} degrees of freedom is not "
                                 f"compiled (limit {MAX_VARIATIONAL_DOF})")
        ext = np.concatenate([np.asarray(y0, dtype=float), np.eye(n2).ravel(order="F"), [0.0]])
        yT = self.states(ext, T, 1, rtol, atol, max_steps=MONODROMY_MAX_STEPS)[-1]
        return yT[:n2], yT[n2:n2 + n2 * n2].reshape((n2, n2), order="F"), float(yT[-1])


def coupled_flow(model: CoupledOscillators | str, params: Mapping[str, object] | None = None
                 ) -> CoupledFlow:
    """Compile ``model`` (once per model; the parameters are values of one compilation).

    Raises
    ------
    kbm.errors.ParameterError
        As :func:`bind_coupled`.
    """
    model, values = bind_coupled(model, params)
    fn, rhs, names, variational = _compiled(model)
    p = np.array([values[n] for n in names], dtype=float)
    return CoupledFlow(model, values, model.dof, variational, fn, p, rhs)


@memo(maxsize=32)
def _compiled(model: CoupledOscillators):
    """The compiled flow, a numpy right-hand side and the parameter order (memoised per
    model: time only)."""
    n = model.dof
    state = list(model.state)
    f = [*state[n:], *model.accelerations()]
    names = sorted({*model.parameters, "mu"})
    psyms = [mu_symbol if nm == "mu" else sp.Symbol(nm) for nm in names]
    if model.forced:  # theta = nu t, nu = nu0 + mu sigma
        sig = sp.Symbol(model.nu_detuning) if model.nu_detuning else 0
        nu = model.nu0 + mu_symbol * sig  # also the frequency written in F (a stage velocity)
        f = [e.subs({sp.Symbol("theta"): nu * t_symbol, sp.Symbol("nu"): nu},
                    simultaneous=True) for e in f]
    variational = n <= MAX_VARIATIONAL_DOF
    exprs, ys = list(f), list(state)
    if variational:
        J = sp.Matrix(f).jacobian(state)
        n2 = 2 * n
        phi = sp.Matrix(n2, n2, lambda i, j: sp.Symbol(f"phi_{i}_{j}"))
        dphi = J * phi
        exprs += [dphi[i, j] for j in range(n2) for i in range(n2)]
        ys += [phi[i, j] for j in range(n2) for i in range(n2)]
        exprs.append(J.trace())
        ys.append(sp.Symbol("div_"))
    fn = jit_flow(exprs, t_symbol, ys, psyms, n_state=2 * n)
    if fn is None:  # pragma: no cover - numba is a declared dependency
        fn = _scipy_flow(exprs, ys, psyms, 2 * n)
    rhs = sp.lambdify([t_symbol, *state, *psyms], f, "numpy")
    return fn, rhs, tuple(names), variational


def _scipy_flow(exprs, ys, psyms, n_state):  # pragma: no cover - without numba
    from scipy.integrate import solve_ivp

    from numerics.flow.jit import FlowResult

    full = sp.lambdify([t_symbol, ys, psyms], exprs, "numpy")
    part = sp.lambdify([t_symbol, ys[:n_state], psyms], exprs[:n_state], "numpy")

    def flow(y0, t_end, p, rtol, atol, n_out=1, max_steps=10**6):
        fun = full if len(y0) > n_state else part
        ts = np.linspace(0.0, t_end, n_out + 1)
        sol = solve_ivp(lambda t, y: fun(t, y, p), (0.0, t_end), y0, method="DOP853",
                        t_eval=ts, rtol=rtol, atol=atol)
        out = np.full((n_out + 1, len(y0)), np.nan)
        out[:sol.y.shape[1]] = sol.y.T
        return FlowResult(out, 0 if sol.success else 2, int(sol.nfev))

    return flow
