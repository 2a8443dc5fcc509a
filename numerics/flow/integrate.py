"""One door to the integrators: the method enum, one stiffness policy, ``flow`` and ``integrate``.

Every numerical trajectory of :mod:`numerics` goes through this module:

- :class:`Method` names the integrators: the DOP853 compiled with numba from the
  model's expressions (:mod:`numerics.flow.jit`), ODEPACK's LSODA, and the
  methods of :func:`scipy.integrate.solve_ivp`;
- :func:`choose_method` is the one policy that turns ``Method.AUTO`` into a
  method, for the three purposes (direct integration, transients, shooting),
  with the thresholds named here (:data:`STIFF_THRESHOLD`,
  :data:`JIT_STIFF_THRESHOLD`);
- :func:`flow` integrates the extended system (state, variational equations,
  divergence, dissipation; :func:`numerics.flow.compiled.extended_state`) to
  equally spaced times; :func:`solve` is the scipy door with events and dense
  output; :func:`integrate` integrates the state of any model, autonomous or
  driven.

``method="auto"`` in :func:`integrate` uses DOP853 (explicit, 8th order) unless
the problem is stiff — the largest eigenvalue of the Jacobian at the start
times one linear period exceeds :data:`STIFF_THRESHOLD` — and then Radau
(implicit) with the analytic Jacobian.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping, Sequence
from enum import Enum
from typing import TYPE_CHECKING

import numpy as np

from kbm.errors import ParameterError

from numerics.errors import IntegrationError
from numerics.flow.compiled import CompiledModel, compile_model
from numerics.flow.template import template_flow

if TYPE_CHECKING:
    from kbm.parameters.bound import BoundModel
    from kbm.model.builtins import Oscillator

__all__ = ["Method", "choose_method", "flow", "solve", "integrate", "stiffness",
           "STIFF_THRESHOLD", "JIT_STIFF_THRESHOLD", "JIT_METHOD"]

#: above this value of (largest Jacobian eigenvalue) x (time scale) scipy's implicit Radau
#: is used instead of its explicit DOP853
STIFF_THRESHOLD = 300.0

#: the same bound for the compiled explicit DOP853 (its steps are cheap, and on stiff van der
#: Pol cycles it is more accurate than LSODA; see ``benchmarks/bench_cycle.py``); above it
#: the shooting uses LSODA
JIT_STIFF_THRESHOLD = 1e5


class Method(str, Enum):
    """The integrators; ``label`` is the name shown in results and messages."""

    AUTO = "auto"
    COMPILED = "compiled"
    LSODA = "LSODA"
    DOP853 = "DOP853"
    RADAU = "Radau"
    BDF = "BDF"
    RK45 = "RK45"
    RK23 = "RK23"

    @property
    def label(self) -> str:
        """``"DOP853 (compiled)"`` for the compiled integrator, else the value."""
        return "DOP853 (compiled)" if self is Method.COMPILED else self.value

    @property
    def implicit(self) -> bool:
        """Whether the method uses the Jacobian."""
        return self in (Method.RADAU, Method.BDF, Method.LSODA)

    @classmethod
    def parse(cls, value: "Method | str") -> "Method":
        """A :class:`Method` from itself, its value or its label.

        Raises
        ------
        kbm.errors.ParameterError
            For an unknown name (the known ones are listed).
        """
        if isinstance(value, Method):
            return value
        for m in cls:
            if value in (m.value, m.label):
                return m
        raise ParameterError(f"unknown integration method {value!r}; use one of "
                             f"{', '.join(m.value for m in cls)}")


#: display name of the compiled integrator (``Method.COMPILED.label``)
JIT_METHOD = Method.COMPILED.label


def stiffness(cm: CompiledModel, x0: float, v0: float | None = None) -> float:
    """Largest Jacobian eigenvalue modulus: at ``(x0, v0)``, or (``v0=None``) the largest
    at three points of the linear orbit of radius ``x0``."""
    if v0 is not None:
        return cm.stiffness(x0, v0)
    return max(cm.stiffness(x0, 0.0), cm.stiffness(0.0, cm.omega0 * x0),
               cm.stiffness(0.5 * x0, 0.5 * cm.omega0 * x0))


def choose_method(cm: CompiledModel, requested: Method | str, purpose: str, x0: float,
                  time_scale: float, v0: float | None = None) -> Method:
    """The one integrator policy: the method for ``purpose`` given the ``requested`` one.

    Parameters
    ----------
    cm
        The compiled model.
    requested
        A :class:`Method` (or its name); ``AUTO`` lets the policy choose.
    purpose
        ``"integrate"`` (a trajectory of the state), ``"transient"`` (settling on a
        cycle), or ``"shooting"`` (Newton on the return map, extended system).
    x0, time_scale, v0
        Where the stiffness is measured (:func:`stiffness`) and the time scale it
        is multiplied by (a period).

    Returns
    -------
    Method
        - ``"shooting"``: the requested method, or under ``AUTO`` the compiled DOP853
          unless unavailable or stiffness x time scale > :data:`JIT_STIFF_THRESHOLD`
          (then LSODA);
        - ``"transient"``: the compiled DOP853 under ``AUTO``/``COMPILED`` below the
          same bound; otherwise scipy's DOP853, or Radau above
          :data:`STIFF_THRESHOLD` (also when LSODA was requested); another scipy
          method as requested;
        - ``"integrate"``: scipy's DOP853, or Radau above :data:`STIFF_THRESHOLD`.

    Raises
    ------
    numerics.errors.IntegrationError
        If the compiled integrator is requested and not available.
    kbm.errors.ParameterError
        For an unknown method or purpose.
    """
    req = Method.parse(requested)
    if purpose not in ("integrate", "transient", "shooting"):
        raise ParameterError(f"unknown purpose {purpose!r} of an integration")
    compiled = template_flow(cm.template) is not None
    if req is Method.COMPILED and not compiled:
        raise IntegrationError(f"the compiled integrator is not available for {cm.name!r} "
                               "(numba not installed, KBM_NO_JIT set, or a function of the "
                               "model without a math-module form); use method='auto' or "
                               "'LSODA'")
    stiff = stiffness(cm, x0, v0) * time_scale
    if purpose == "shooting":
        if req is not Method.AUTO:
            return req
        return Method.COMPILED if compiled and stiff <= JIT_STIFF_THRESHOLD else Method.LSODA
    if purpose == "transient":
        if req is Method.COMPILED or (req is Method.AUTO and compiled
                                      and stiff < JIT_STIFF_THRESHOLD):
            return Method.COMPILED
        if req not in (Method.AUTO, Method.LSODA):
            return req
    elif req is not Method.AUTO:
        return req
    return Method.RADAU if stiff > STIFF_THRESHOLD else Method.DOP853


def solve(cm: CompiledModel, y0, t_end: float, method: Method | str, rtol: float, atol: float,
          *, extended: bool = False, dense: bool = False, events=None, max_step: float = np.inf,
          t_start: float = 0.0, t_eval=None):
    """:func:`scipy.integrate.solve_ivp` on the model's state (or extended system).

    The analytic Jacobian is passed to implicit methods for the state.

    Raises
    ------
    numerics.errors.IntegrationError
        If the integrator fails or the state becomes non-finite (with the time).
    """
    from scipy.integrate import solve_ivp  # imported on use: the compiled path needs none

    meth = Method.parse(method)
    if meth in (Method.AUTO, Method.COMPILED):
        raise ParameterError(f"solve() runs scipy's integrators, not {meth.label!r}")
    fun = cm.rhs_ext if extended else cm.rhs
    kwargs = {"jac": cm.jac} if meth.implicit and not extended else {}
    try:
        with np.errstate(all="ignore"):
            sol = solve_ivp(fun, (t_start, t_end), y0, method=meth.value, rtol=rtol,
                            atol=atol, dense_output=dense, events=events, max_step=max_step,
                            t_eval=t_eval, **kwargs)
    except (ValueError, OverflowError, ZeroDivisionError, np.linalg.LinAlgError) as exc:
        # a non-finite state inside the method (e.g. the LU factors of Radau)
        raise IntegrationError(f"{meth.value} failed: {exc}") from None
    if sol.status < 0:
        raise IntegrationError(f"{meth.value} failed at t = {sol.t[-1]:.6g}: {sol.message}")
    if not np.all(np.isfinite(sol.y[:, -1])):
        raise IntegrationError(f"the state became non-finite at t = {sol.t[-1]:.6g}")
    return sol


def flow(cm: CompiledModel, y0, t_end: float, n_out: int, method: Method | str, rtol: float,
         atol: float, max_steps: int = 10**6, steps: list | None = None) -> np.ndarray:
    """States of the extended system at ``t_k = k t_end/n_out``, shape ``(n_out + 1, 9)``.

    ``method`` is ``COMPILED``, ``LSODA`` or a scipy method (not ``AUTO``: ask
    :func:`choose_method`).  ``steps``, if given, receives the compiled
    integrator's step count.

    Raises
    ------
    numerics.errors.IntegrationError
        If the integration fails (with the time and the reason).
    """
    t_end = float(t_end)
    meth = Method.parse(method)
    if meth is Method.COMPILED:
        fl = template_flow(cm.template)
        if fl is None:
            choose_method(cm, meth, "shooting", 1.0, 1.0)  # raises the explanation
        res = fl(y0, t_end, cm.pvec, rtol, atol, n_out, max_steps)
        if steps is not None:
            steps.append(res.steps)
        if res.status:
            raise IntegrationError(f"{meth.label} failed before t = {t_end:.6g} after "
                                   f"{res.steps} steps: {res.message}")
        ys = res.y
    elif meth is Method.LSODA:
        from scipy.integrate import odeint

        times = np.linspace(0.0, t_end, n_out + 1)
        try:
            with np.errstate(all="ignore"), warnings.catch_warnings():
                warnings.simplefilter("ignore")  # the failure is reported from info below
                ys, info = odeint(cm.rhs_ext, y0, times, tfirst=True, rtol=rtol, atol=atol,
                                  full_output=True, mxstep=500000)
        except (ValueError, OverflowError) as exc:  # e.g. a non-finite state inside ODEPACK
            raise IntegrationError(f"LSODA failed before t = {t_end:.6g}: {exc}") from None
        if info["message"] != "Integration successful.":
            raise IntegrationError(f"LSODA failed before t = {t_end:.6g}: {info['message']}")
    elif meth is Method.AUTO:
        raise ParameterError("flow() needs a definite method; ask choose_method()")
    else:
        times = np.linspace(0.0, t_end, n_out + 1)
        sol = solve(cm, y0, t_end, meth, rtol, atol, extended=True, dense=True)
        ys = sol.sol(times).T
        ys[-1] = sol.y[:, -1]
    if not np.all(np.isfinite(ys[-1])):
        raise IntegrationError(f"the state became non-finite before t = {t_end:.6g}")
    return ys


def integrate(model: Oscillator | str | BoundModel, params: Mapping[str, object] | None,
              y0: Sequence[float], t_span: tuple[float, float], *, method: Method | str = "auto",
              rtol: float = 1e-10, atol: float = 1e-12, t_eval=None, dense_output: bool = True):
    """Integrate ``x'' = -omega0^2 x + mu F(x, x') + drive(t)`` from ``y0 = (x, x')``.

    Returns
    -------
    scipy.integrate.OdeResult
        With ``method_used`` added (``"DOP853"`` or ``"Radau"`` under ``"auto"``).

    Raises
    ------
    numerics.errors.IntegrationError
        If the integrator fails or the state becomes non-finite (with the time).

    Examples
    --------
    >>> sol = integrate("vdp", {"mu": 100}, [2.0, 0.0], (0.0, 1.0))
    >>> sol.method_used
    'Radau'
    """
    cm = compile_model(model, params)
    x0, v0 = float(y0[0]), float(y0[1])
    meth = choose_method(cm, method, "integrate", x0, 2 * math.pi / cm.omega0, v0=v0)
    try:
        sol = solve(cm, [x0, v0], t_span[1], meth, rtol, atol, dense=dense_output,
                    t_start=t_span[0], t_eval=t_eval)
    except IntegrationError as exc:
        raise IntegrationError(f"{exc}") from None
    sol.method_used = meth.value
    return sol
