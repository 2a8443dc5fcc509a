"""The driven sliders, reference path: SEDF (eq. 3) and CDC (eq. 12) pulled at velocity v.

This is the scipy (``solve_ivp``) path with dense output that the paper's experiments
(:mod:`numerics.paper.claims`, Figs. 4-6) and the event analysis
(:mod:`numerics.sliding.stickslip`) use; the friction laws run the compiled path of
:mod:`numerics.sliding.driven`, checked against this one.

``x'' + D(x, x') + Delta sin(k x) + Omega^2 (x - v t) = 0`` with the damping force
``D = mu (beta x^2 - 1) x'`` (SEDF) or ``D = mu x'`` (CDC), ``k = 2 pi/lambda``.
The equations are those of the compiled path,
:func:`numerics.sliding.driven.slider_equations` (the model of :func:`kbm.get_model`,
lambdified once per slider with ``v`` a parameter).  Along the trajectory extra states
are integrated (not sampled): ``Gamma_+ = mu int x^2 x'^2``, ``Gamma_- = mu int x'^2``
(paper eq. 11; for the CDC ``Gamma = mu int x'^2``), and the work of the spring on
the slider ``W = int Omega^2 (v t - x) x' dt``.  Energy audit:
``W = Delta(x'^2/2) + Delta(-(Delta/k) cos k x) + Gamma``, with its residual.

The friction force the paper plots is the spring force ``F = Omega^2 (v t - x)``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp

from kbm.errors import ParameterError
from kbm.model.builtins import SLIDERS, get_model
from kbm.output.paper import FIXED

from numerics.errors import IntegrationError
from numerics.sliding.driven import physical_values, slider_equations
from numerics.sliding.stiffness import STABILITY_INTERVAL, StepGuard, stiff_steps, stiff_t_end
from numerics.sliding.damping import damping_rate, damping_text

__all__ = ["SlideResult", "slide", "MAX_PERIODS"]

#: bound on the length of a run, in natural periods ``2 pi/Omega`` (for the CDC a run of this
#: length takes about half a minute and keeps its dense output in memory; the SEDF's damping
#: grows like ``(v t)^2`` and its cost is bounded by :data:`MAX_STIFF_STEPS`)
MAX_PERIODS = 5_000
#: bound on the integration steps a run's largest step (a quarter of its shortest time scale)
#: allows at the least: ``kbm slide sedf -p v=1e9 --t-end 15`` (the stage crosses a well every
#: 1e-9) ran without end; a run of MAX_PERIODS periods at the paper's values takes 1e5
MAX_STEPS = 2_000_000
#: bound on the steps the stiffness of the damping needs (:mod:`numerics.sliding.stiffness`,
#: DOP853 takes about 0.3 ms a step: ``kbm slide sedf -p Delta=3 -p beta=1 -p mu=1e6 -p
#: v=0.1 --t-end 15`` and ``t_end = 31000`` at ``v = 0.01`` ran for minutes); the
#: integration itself stops after ``max(4 x the estimate, 2e5)`` steps, at most GUARD_STEPS
MAX_STIFF_STEPS = 250_000
#: bound on the steps of the integration itself (about three minutes)
GUARD_STEPS = 600_000


@dataclass(frozen=True, eq=False)
class SlideResult:
    """A driven simulation: time series, the dissipation states and the energy audit.

    Attributes
    ----------
    model, params
        ``"sedf"`` or ``"cdc"`` and the physical parameters used.
    t, x, xdot, force
        Samples (``force = Omega^2 (v t - x)``, the friction force of the paper).
    gamma_plus, gamma_minus, gamma, work
        Running integrals at the samples (``gamma = beta gamma_plus - gamma_minus``
        for the SEDF, ``mu int x'^2`` for the CDC; ``work`` of the spring).
    energy_residual
        ``W - Delta KE - Delta U_periodic - Gamma`` at the end (integration error).
    sol
        The dense solution (callable ``sol(t)`` for the 7 states ``x, x_dot, t, G_+, G_-,
        W, J`` of :func:`numerics.sliding.driven.slider_equations`).
    """

    model: str
    params: Mapping[str, float]
    t: np.ndarray
    x: np.ndarray
    xdot: np.ndarray
    force: np.ndarray
    gamma_plus: np.ndarray
    gamma_minus: np.ndarray
    gamma: np.ndarray
    work: np.ndarray
    energy_residual: float
    method: str
    rtol: float
    sol: object = field(repr=False, compare=False)
    gain_factor: float = 1.0

    def gamma_at(self, t: float) -> float:
        """The dissipation ``Gamma(t) = factor*Gamma_+ - Gamma_-`` (paper eq. 11) at time ``t``."""
        y = self.sol.sol(t)
        return float(self.gain_factor * y[3] - y[4])

    def window(self, t0: float, t1: float) -> np.ndarray:
        """Boolean mask of the samples in ``[t0, t1]``."""
        return (self.t >= t0) & (self.t <= t1)


def _validate(params: Mapping[str, float], t_end: float) -> dict[str, float]:
    p = physical_values({**FIXED, **params}, standing=True)
    if not (math.isfinite(t_end) and t_end > 0):
        raise ParameterError(f"t_end must be a positive number, got {t_end}")
    periods = t_end * p.get("Omega", 1.0) / (2 * math.pi)
    if periods > MAX_PERIODS:
        raise ParameterError(f"t_end = {t_end:g} is {periods:.3g} natural periods 2 pi/Omega; "
                             f"the limit is {MAX_PERIODS} (t_end <= "
                             f"{MAX_PERIODS * 2 * math.pi / p.get('Omega', 1.0):.4g}): "
                             "split a longer run")
    return p


def slide(model: str, params: Mapping[str, float], t_end: float, *, x0: float = 0.0,
          v0: float = 0.0, rtol: float = 1e-10, atol: float = 1e-12, method: str = "DOP853",
          n_samples: int | None = None, max_step: float | None = None) -> SlideResult:
    """Simulate the slider pulled at velocity ``v`` from ``x = x0, x' = v0`` to ``t_end``.

    Parameters
    ----------
    model
        ``"sedf"`` (paper eq. 3), ``"cdc"`` (paper eq. 12) or ``"sedf_comoving"``
        (:mod:`kbm.model.builtins`: the self-excitation attached to the stage).
    params
        Physical parameters ``mu, beta, Delta, lam, Omega, v`` (``mu = 0.1``,
        ``Omega = 1``, ``lam = 1`` by default, as in the paper).
    t_end
        Final time.
    method, rtol, atol
        :func:`scipy.integrate.solve_ivp` method and tolerances.
    n_samples
        Output samples (default: 20 per natural period ``2 pi/Omega``, at least 2000).
    max_step
        Largest step (default: a quarter of the shortest time scale).

    Raises
    ------
    kbm.errors.ParameterError
        For ``lam <= 0``, ``Omega <= 0``, ``v < 0``, ``t_end <= 0``, NaN, etc., or a
        run longer than :data:`MAX_PERIODS` natural periods, or one whose damping is too
        stiff for an explicit method (:mod:`numerics.sliding.stiffness`: more than
        :data:`MAX_STIFF_STEPS` steps).
    numerics.errors.IntegrationError
        If the integrator fails or takes more steps than the estimate allows (4 times it,
        at least 2e5, at most :data:`GUARD_STEPS`).

    Examples
    --------
    >>> r = slide("cdc", {"Delta": 3.0, "v": 0.1}, t_end=50.0)
    >>> abs(r.energy_residual) < 1e-7
    True
    """
    if model not in SLIDERS:
        raise ParameterError(f"slide needs a slider model ({', '.join(SLIDERS)}), "
                             f"got {model!r}")
    p = _validate(params, t_end)
    if not 1e-14 <= rtol <= 1e-3:
        raise ParameterError(f"rtol must be between 1e-14 and 1e-3, got {rtol}")
    if not (math.isfinite(atol) and atol > 0):
        raise ParameterError(f"atol must be a positive number, got {atol}")
    if "beta" not in get_model(model).parameters:
        p.pop("beta", None)
    p.setdefault("v", 0.0)
    # the equations of the compiled path (numerics.sliding.driven), through solve_ivp
    tp, pvec = slider_equations(model, p)
    f, beta = tp.f_rhs, float(tp.f_factor(*pvec))

    def rhs(t, yy):
        return f(t, yy, *pvec)

    Om, v = p["Omega"], p["v"]
    k = 2 * math.pi / p["lam"]
    scale = min(2 * math.pi / Om, p["lam"] / max(abs(v), 1e-12),
                2 * math.pi / math.sqrt(Om**2 + p["Delta"] * k))
    ms = max_step if max_step is not None else scale / 4
    if t_end / ms > MAX_STEPS:
        why = ("the stage crosses a well every lam/v" if scale == p["lam"] / max(abs(v), 1e-12)
               else "the shortest period of the slider is")
        raise ParameterError(f"t_end = {t_end:g} needs at least {t_end / ms:.3g} steps ({why} "
                             f"= {scale:.3g}, at most a quarter of it per step); the limit is "
                             f"{MAX_STEPS:.0e}: lower v or t_end")
    stiff = stiff_steps(model, p, t_end, method)
    if stiff > MAX_STIFF_STEPS:
        raise ParameterError(
            f"t_end = {t_end:g} needs about {stiff:.3g} steps of {method}: the damping's "
            f"{damping_text(model)} (mu = {p['mu']:g}) and an explicit step is stable only "
            f"below about {STABILITY_INTERVAL[method]:g}/|dD/dx'|; "
            f"the limit is {MAX_STIFF_STEPS:.3g}: lower mu or t_end (t_end <= "
            f"{stiff_t_end(model, p, method, MAX_STIFF_STEPS, t_end):.4g})")
    guard = StepGuard(rhs, min(GUARD_STEPS, max(4 * (stiff + t_end / ms), 200_000)),
                      method)
    n = n_samples or max(2000, int(20 * t_end * Om / (2 * math.pi)))
    with np.errstate(all="ignore"):
        sol = guard.run(lambda fun: solve_ivp(
            fun, (0.0, t_end), [x0, v0, 0.0, 0.0, 0.0, 0.0, 0.0], method=method, rtol=rtol,
            atol=atol, dense_output=True, max_step=ms), t_end, damping_rate(model, p))
    if sol.status != 0 or not np.all(np.isfinite(sol.y[:, -1])):
        raise IntegrationError(f"{method} failed at t = {sol.t[-1]:.6g}: {sol.message}; the "
                               "motion may have diverged (try a smaller t_end)")
    tt = np.linspace(0.0, t_end, n)
    ys = sol.sol(tt)
    xs, vs = ys[0], ys[1]
    Gp, Gm, W = ys[3], ys[4], ys[5]
    G = beta * Gp - Gm
    yend = sol.y[:, -1]
    G_end = beta * yend[3] - yend[4]
    # the substrate's potential as the template derives it (-int F_c dx: Delta/k (1 - cos k x))
    resid = yend[5] - (yend[1]**2 / 2 - v0**2 / 2) - (tp.f_potential(yend[0], *pvec)
                                                      - tp.f_potential(x0, *pvec)) - G_end
    return SlideResult(model=model, params=p, t=tt, x=xs, xdot=vs, force=Om**2 * (v * tt - xs),
                       gamma_plus=Gp, gamma_minus=Gm, gamma=G, work=W,
                       energy_residual=float(resid), method=method, rtol=rtol, sol=sol,
                       gain_factor=beta)
