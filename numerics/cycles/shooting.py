"""Limit cycles of ``x'' + omega0^2 x = mu F(x, x')`` by shooting, with Floquet multipliers.

The periodic orbit is a fixed point of the Poincare return map on the section
``x' = 0, x > 0`` (crossed with ``x'`` decreasing, i.e. at a maximum of ``x``).
Newton's method on the return map ``P(x0)`` (the case ``N = 1`` of
:func:`numerics.shooting.orbit.shoot`, :mod:`numerics.cycles.newton`) uses
``P'(x0) = Phi_11(T)`` from the variational equations (``x'(T) = 0`` on the section,
so the change of the return time drops out).  On the converged orbit one more integration gives the
monodromy matrix ``Phi(T)`` (its eigenvalues are the Floquet multipliers; one is
1 for an autonomous system), ``int div f dt`` (Liouville: ``det Phi(T) =
exp(int div f)``), the dissipation ``Gamma`` (paper eqs. 10-11) as extra states,
and the energy balance ``E(0) - E(T) - Gamma`` as an accuracy check.

References
----------
M. D'Acunto, "Friction force for self-excited systems", eqs. (3), (10)-(12).
T. S. Parker and L. O. Chua, *Practical Numerical Algorithms for Chaotic Systems*,
Springer (1989), ch. 5 (shooting for periodic orbits).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from kbm.errors import NonAutonomousError

from numerics.cycles.finalpass import final_pass
from numerics.cycles.guess import energy_cycles, kbm_guess
from numerics.cycles.newton import check_nontrivial, newton
from numerics.cycles.result import LimitCycle
from numerics.cycles.transient import transient
from numerics.errors import ConvergenceError, IntegrationError, NoCycleError
from numerics.flow import Method, ModelTemplate, choose_method, compile_model, solve

if TYPE_CHECKING:  # the symbolic model is built on use (a model card: issue 39)
    from kbm.parameters.bound import BoundModel
    from kbm.model.builtins import Oscillator

__all__ = ["limit_cycle"]


def limit_cycle(model: Oscillator | str | BoundModel, params: Mapping[str, object] | None = None,
                *, guess: tuple[float, float] | None = None, digits: int | None = None,
                rtol: float = 1e-12, atol: float | None = None, method: Method | str = "auto",
                max_iter: int = 25, x_start: float = 1.0, max_time: float | None = None,
                x_max: float | None = None, template: ModelTemplate | None = None,
                n_samples: int = 1024, n_harmonics: int = 16) -> LimitCycle:
    """The limit cycle of an autonomous model, by shooting on ``x' = 0, x > 0``.

    Parameters
    ----------
    model
        An :class:`~kbm.model.builtins.Oscillator`, a built-in name, or a
        :class:`~kbm.parameters.bound.BoundModel` (then ``params`` is ``None``).
    params
        Parameter values (physical names such as ``Delta``, ``lam`` or the
        scaled ones), including ``mu``.
    guess
        ``(x_max, period)`` to start Newton from (``x_max`` the maximum of ``x`` on
        the cycle, negative for a cycle in a side well at ``x < 0``); if Newton does
        not converge from it, once more from the point where the orbit from
        ``(x_max, 0)`` first returns to ``x' = 0``.  Without it the starts are
        (:mod:`numerics.cycles.guess`): the stable first-order KBM cycle of largest
        amplitude; then the stable cycles of the energy-balance averaging about the
        conservative orbit (:func:`numerics.energy.predict_cycles`, right where
        the potential is strong); when neither predicts a stable cycle, their
        unstable cycles (Newton converges to unstable cycles as well: van der Pol
        with ``mu < 0``); then transients from the predicted amplitudes and
        from ``x = x_start``, ``x' = 0``, integrated until the maxima of ``x`` settle.
    digits
        If given (up to ~50), also compute period and amplitudes with an
        mpmath Taylor-series integrator to this many digits
        (:func:`numerics.cycles.highprec.limit_cycle_mp`).
    rtol, atol
        Integrator tolerances (default ``atol = rtol``).
    method
        A :class:`numerics.flow.Method` or its name.  ``"auto"``: DOP853
        compiled with numba (:mod:`numerics.flow.jit`) when the model compiles
        and the cycle is not too stiff (largest Jacobian eigenvalue times the
        period below :data:`numerics.flow.JIT_STIFF_THRESHOLD`), else LSODA
        (ODEPACK), which switches between Adams (non-stiff) and BDF (stiff) by
        itself.  Or name one: ``"compiled"``, ``"LSODA"``, or any
        :func:`scipy.integrate.solve_ivp` method (``"DOP853"``, ``"Radau"``,
        ...).  The transient, when needed, runs through the compiled flow under
        the same rule; otherwise through scipy's DOP853, or Radau when the
        stiffness exceeds :data:`numerics.flow.STIFF_THRESHOLD`
        (:func:`numerics.flow.choose_method`).
    max_iter
        Bound on Newton iterations.
    template
        A :class:`numerics.flow.compiled.ModelTemplate` of the model (skips lambdifying;
        used by :func:`numerics.cycles.sweep`).
    x_start, max_time, x_max
        Start of the transient, its time limit, and the size ``|x| + |x'|`` above
        which the motion counts as growing without bound (default
        ``1000 max(1, |x_start|)``; raise it for cycles larger than that).
    n_samples, n_harmonics
        Samples of one period (``t``, ``x``, ``xdot``), and the number of Fourier
        coefficients, which are integrated along the orbit, not taken from the samples
        (:mod:`numerics.cycles.harmonics`).

    Returns
    -------
    LimitCycle
        With ``success = False`` and a message when Newton stalls above the
        integration accuracy but the orbit is still closed to ``1e-6``.  Its
        ``accuracy`` holds the estimated relative errors; a weakly attracting cycle
        whose double-precision accuracy is worse than ``1e-10`` is recomputed with the
        Taylor integrator, and the message says so (:mod:`numerics.cycles.finalpass`).

    See Also
    --------
    numerics.cycles.every_cycle.limit_cycles : every cycle (stable and unstable) the
        predictions point to.

    Raises
    ------
    kbm.errors.NonAutonomousError
        For a driven model (``v != 0``).
    numerics.errors.NoCycleError
        If the transient grows without bound or decays to rest, for ``mu = 0`` (a
        conservative oscillator: no isolated cycle), or when the orbit found is not
        isolated (non-trivial multiplier 1).
    numerics.errors.ConvergenceError
        If Newton's method fails (residual history in the message).

    Examples
    --------
    >>> c = limit_cycle("vdp", {"mu": 1})
    >>> round(c.period, 8), round(c.amplitude_max, 8)
    (6.66328686, 2.00861986)
    """
    bound, cm = _bound_and_compiled(model, params, template)
    _check_not_conservative(bound, cm)
    st = _settings(cm, method, rtol, atol, max_iter, max_time, x_max, x_start)
    converged, meth, source = _find_orbit(cm, bound, guess, float(x_start), st)
    return final_pass(cm, converged, meth, source, st, digits, n_samples, n_harmonics)


@dataclass(frozen=True)
class _Settings:
    method: Method
    rtol: float
    atol: float
    max_iter: int
    max_time: float
    x_max: float
    floor: float
    T_lin: float


def _bound_and_compiled(model, params, template):
    """``(bound, compiled)``: from the model card of a built-in name when one is stored
    (no sympy, :mod:`numerics.flow.card`), else bound and compiled (and the card stored)."""
    from numerics.flow.card import card_key, card_model, model_of, write_card

    if template is None:
        found = card_model(model, params)
        if found is not None:
            return found
    from kbm.parameters.bound import bind

    key, model = card_key(model, params), model_of(model)

    from numerics.cycles.guess import rates_key

    bound = bind(model, params)
    cm = compile_model(bound, template=template)
    if template is None:
        write_card(key, bound, cm, rates_key=rates_key(bound.model))
    return bound, cm


def _check_not_conservative(bound: BoundModel, cm) -> None:
    """``mu = 0`` in ``x'' + omega0^2 x = mu F``: a linear oscillator, no isolated cycle."""
    if cm.values.get("mu", 1.0) != 0:
        return
    has_mu = getattr(bound, "has_mu", None)  # a model card's
    if has_mu is None:
        import sympy as sp

        has_mu = bound.model.acceleration().has(sp.Symbol("mu"))
    if has_mu:
        raise NoCycleError("mu = 0 leaves x'' + omega0^2 x = 0, a conservative oscillator: "
                           "every orbit is periodic, so there is no isolated limit cycle; "
                           "give mu != 0 (mu < 0 gives the cycle with reversed stability)")


def _settings(cm, method, rtol, atol, max_iter, max_time, x_max, x_start) -> _Settings:
    if not cm.autonomous:
        raise NonAutonomousError(f"limit cycles need an autonomous model; {cm.name!r} has an "
                                 "explicit time dependence (stage velocity v != 0); use "
                                 "numerics.slide for the driven slider")
    atol = rtol if atol is None else atol
    T_lin = 2 * math.pi / cm.omega0
    if max_time is None:
        mu = abs(cm.values.get("mu", 1.0)) or 1.0
        max_time = min(max(200 * T_lin, 60.0 / mu), 2e5)
    big = x_max if x_max is not None else 1e3 * max(1.0, abs(x_start))
    return _Settings(Method.parse(method), rtol, atol, max_iter, max_time, big,
                     1e3 * max(rtol, atol), T_lin)


def _check_guess(start) -> tuple[float, float]:
    x0, period = float(start[0]), float(start[1])
    if not (np.isfinite(x0) and np.isfinite(period) and period > 0 and x0 != 0):
        raise ConvergenceError(f"bad initial guess (x_max, period) = {tuple(start)}: need a "
                               "finite x_max != 0 and a period > 0")
    return x0, period


def _shoot(cm, x0: float, period: float, st: _Settings):
    """Newton from ``(x0, period)``, then the non-triviality check; ``(converged, method)``."""
    meth = choose_method(cm, st.method, "shooting", abs(x0), period)
    converged = newton(cm, x0, period, meth, st.rtol, st.atol, st.max_iter, st.floor)
    check_nontrivial(cm, converged, meth, st.rtol, st.atol, x0)
    return converged, meth


def _return_point(cm, x0: float, period: float, st: _Settings) -> tuple[float, float]:
    """Where the orbit from ``(x0, 0)`` first returns to ``x' = 0`` going down, and when.

    A start whose period is off (near a separatrix the period depends strongly on
    the amplitude) is replaced by a point of the return map with its own return time.
    """
    def section(t, y):
        return y[1]
    section.direction = -1  # x' from + to -: a maximum of x
    scipy_ok = st.method not in (Method.AUTO, Method.COMPILED, Method.LSODA)
    meth = choose_method(cm, st.method if scipy_ok else Method.AUTO, "integrate", abs(x0),
                         period, v0=0.0)
    sol = solve(cm, [x0, 0.0], 3.0 * period, meth, max(st.rtol, 1e-10),
                max(st.rtol, 1e-10) * 1e-2, events=[section], dense=False)
    times = [float(t) for t in sol.t_events[0] if t > 0.05 * period]
    if not times:
        raise NoCycleError(f"the orbit from x = {x0:.6g} (x' = 0) does not return to x' = 0 "
                           f"within {3 * period:.4g}")
    i = [float(t) for t in sol.t_events[0]].index(times[0])
    return float(sol.y_events[0][i][0]), times[0]


def _starts(bound: BoundModel, guess, x_start: float):
    """The starting guesses in order: ``(label, (x_max, period) or None, transient x)``."""
    if guess is not None:
        yield "guess", _check_guess(guess), None
        return
    kg = kbm_guess(bound)
    if kg is not None:
        yield "KBM first-order averaged cycle", kg, None
    ec = energy_cycles(bound)  # one prediction for the stable and the unstable starts
    eg = [(x, T) for x, T, stable in ec if stable]
    for x, T in eg:
        yield "energy-balance cycle", (x, T), None
    if kg is None and not eg:
        # no stable cycle predicted (e.g. van der Pol with mu < 0): Newton does not care
        # about stability, so start it from the unstable ones
        ku = kbm_guess(bound, stable=False)
        if ku is not None:
            yield "unstable KBM first-order averaged cycle", ku, None
        for x, T, _ in ec:
            yield "unstable energy-balance cycle", (x, T), None
    seen = []
    for x in [*(x for x, _ in eg), *([kg[0]] if kg else []), x_start]:
        if all(abs(x - y) > 1e-3 for y in seen):
            seen.append(x)
            yield f"transient from x = {x:.6g}", None, x


def _find_orbit(cm, bound: BoundModel, guess, x_start: float, st: _Settings):
    """Converge on a periodic orbit from the first start that works."""
    failures: list[tuple[str, Exception]] = []
    for label, start, xs in _starts(bound, guess, x_start):
        try:
            if start is not None:
                x0, period = start
                try:
                    converged, meth = _shoot(cm, x0, period, st)
                except (ConvergenceError, IntegrationError, NoCycleError):
                    x1, T1 = _return_point(cm, x0, period, st)
                    converged, meth = _shoot(cm, x1, T1, st)
                    label += " (after one return)"
            else:
                tmeth = choose_method(cm, st.method, "transient", abs(xs), st.T_lin)
                x0, period, _ = transient(cm, xs, tmeth, max(st.rtol, 1e-10), st.max_time,
                                          st.x_max)
                converged, meth = _shoot(cm, x0, period, st)
        except (ConvergenceError, IntegrationError, NoCycleError) as exc:
            failures.append((label, exc))
            continue
        return converged, meth, label
    label, exc = failures[-1]
    if len(failures) == 1:
        raise exc
    transients = [(lb, e) for lb, e in failures if lb.startswith("transient")] or failures
    raise type(exc)("; ".join(f"{lb}: {e}" for lb, e in transients)) from exc
