"""Limit cycles of ``x'' + omega0^2 x = mu F(x, x')`` by shooting, with Floquet multipliers.

The periodic orbit is a fixed point of the Poincare return map on the section
``x' = 0, x > 0`` (crossed with ``x'`` decreasing, i.e. at a maximum of ``x``).
Newton's method on the return map ``P(x0)`` uses ``P'(x0) = Phi_11(T)`` from the
variational equations (``x'(T) = 0`` on the section, so the change of the return
time drops out).  On the converged orbit one more integration gives the
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
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import odeint, solve_ivp

from kbm.errors import KBMError, NonAutonomousError
from kbm.models import Oscillator

from ._compile import CompiledModel, compile_model
from .errors import ConvergenceError, IntegrationError, NoCycleError

__all__ = ["Dissipation", "LimitCycle", "limit_cycle", "STIFF_THRESHOLD"]

#: above this value of (largest Jacobian eigenvalue) x (period) the implicit Radau method is used
STIFF_THRESHOLD = 300.0

#: the same bound for the compiled explicit DOP853 (its steps are cheap, and on stiff van der
#: Pol cycles it is more accurate than LSODA; see ``benchmarks/bench_cycle.py``)
JIT_STIFF_THRESHOLD = 1e5


@dataclass(frozen=True)
class Dissipation:
    """Energy gain and loss over one cycle (paper eqs. 10-11): ``total = factor*plus - minus``.

    For the SEDF (and van der Pol, ``beta = 1``) ``gamma_plus = mu int x^2 x'^2 dt``,
    ``gamma_minus = mu int x'^2 dt`` and ``total = beta gamma_plus - gamma_minus``.
    """

    total: float
    gamma_plus: float
    gamma_minus: float
    plus_factor: float = 1.0


@dataclass(frozen=True)
class LimitCycle:
    """A periodic orbit of the full equation, with its checks.

    Attributes
    ----------
    success, message
        Whether Newton converged to a periodic orbit, and how (or why not).
    period, frequency
        ``T`` and ``2 pi/T``.
    amplitude_max
        Maximum of ``x`` on the orbit (the section point).
    amplitude_first_harmonic
        ``|(2/T) int x e^{-i w t} dt|``: what KBM's amplitude ``a`` predicts.
    harmonics
        Complex Fourier coefficients ``c_m`` of ``x(t) = sum_m c_m e^{i m w t}``,
        ``m = 0..len-1`` (time origin at the section point).
    t, x, xdot
        Samples of one period.
    floquet_multipliers
        Eigenvalues of the monodromy matrix, the trivial one (closest to 1) first.
    stable
        ``|non-trivial multiplier| < 1``.
    liouville
        ``(det Phi(T), exp(int div f dt))``: equal by Liouville's formula.
    dissipation
        :class:`Dissipation` over one period.
    energy_residual
        ``E(0) - E(T) - Gamma``: zero up to integration error.
    iterations, residual, history
        Newton iterations, final ``|P(x0) - x0|``, and the residual of each iteration.
    method
        The integrator used (``"DOP853"`` or ``"Radau"``).
    params
        The parameter values used (floats).
    digits
        ``None`` for double precision; the number of digits for :func:`limit_cycle`
        with ``digits=`` (then ``period_mp``, ``amplitude_max_mp``,
        ``amplitude_first_harmonic_mp`` hold mpmath numbers).
    """

    success: bool
    message: str
    model: str
    params: Mapping[str, float]
    period: float
    frequency: float
    amplitude_max: float
    amplitude_first_harmonic: float
    harmonics: np.ndarray
    t: np.ndarray
    x: np.ndarray
    xdot: np.ndarray
    floquet_multipliers: tuple[complex, complex]
    stable: bool
    liouville: tuple[float, float]
    dissipation: Dissipation
    energy_residual: float
    iterations: int
    residual: float
    history: tuple[float, ...]
    method: str
    digits: int | None = None
    mp: Mapping[str, object] = field(default_factory=dict)

    def to_json(self) -> dict:
        """The keys of ``kbm cycle --json`` (numbers as strings when ``digits`` is set)."""
        def num(name, value):
            if self.digits is not None and name in self.mp:
                import mpmath
                return mpmath.nstr(self.mp[name], self.digits, strip_zeros=False)
            return float(value)

        return {
            "model": self.model,
            "params": {k: float(v) for k, v in sorted(self.params.items())},
            "success": self.success,
            "message": self.message,
            "period": num("period", self.period),
            "frequency": num("frequency", self.frequency),
            "amplitude_max": num("amplitude_max", self.amplitude_max),
            "amplitude_first_harmonic": num("amplitude_first_harmonic",
                                            self.amplitude_first_harmonic),
            "floquet_multipliers": [float(m.real) if abs(m.imag) < 1e-300 else
                                    [float(m.real), float(m.imag)]
                                    for m in self.floquet_multipliers],
            "stable": self.stable,
            "dissipation": {"total": self.dissipation.total,
                            "gamma_plus": self.dissipation.gamma_plus,
                            "gamma_minus": self.dissipation.gamma_minus},
            "energy_residual": self.energy_residual,
            "iterations": self.iterations,
            "residual": self.residual,
            "method": self.method,
            "digits": self.digits,
        }


# ----------------------------------------------------------------------------- helpers
def _maximum_event(t, y):
    return y[1]


_maximum_event.direction = -1  # x' goes from + to -: a maximum of x


def _choose_method(cm: CompiledModel, x0: float, period: float, method: str) -> str:
    if method != "auto":
        return method
    return "Radau" if _stiffness(cm, x0) * period > STIFF_THRESHOLD else "DOP853"


def _solve(cm, y0, t_end, method, rtol, atol, ext, dense=False, events=None, max_step=np.inf):
    fun = cm.rhs_ext if ext else cm.rhs
    kwargs = {}
    if method in ("Radau", "BDF", "LSODA") and not ext:
        kwargs["jac"] = cm.jac
    with np.errstate(all="ignore"):
        sol = solve_ivp(fun, (0.0, t_end), y0, method=method, rtol=rtol, atol=atol,
                        dense_output=dense, events=events, max_step=max_step, **kwargs)
    if sol.status < 0:
        raise IntegrationError(f"{method} failed at t = {sol.t[-1]:.6g}: {sol.message}")
    if not np.all(np.isfinite(sol.y[:, -1])):
        raise IntegrationError(f"the state became non-finite at t = {sol.t[-1]:.6g}")
    return sol


def _transient(cm: CompiledModel, x_start: float, method: str, rtol: float,
               max_time: float, x_max: float) -> tuple[float, float, list[float]]:
    """Integrate until successive maxima of x settle; returns (x_max, period estimate, maxima)."""
    ev = _maximum_event
    y = [x_start, 0.0]
    maxima: list[float] = []
    times: list[float] = []
    t0 = 0.0
    chunk = 40 * 2 * math.pi / cm.omega0
    big = x_max
    while t0 < max_time:
        def blowup(t, yy):
            return big - abs(yy[0]) - abs(yy[1])
        blowup.terminal = True
        sol = _solve(cm, y, chunk, method, rtol, rtol * 1e-2, ext=False, events=[ev, blowup])
        if sol.t_events[1].size:
            raise NoCycleError(
                f"no limit cycle: the amplitude grows without bound (|x| + |x'| > {big:.3g} at "
                f"t = {t0 + sol.t_events[1][0]:.6g}; last maxima of x: "
                f"{', '.join(f'{m:.4g}' for m in maxima[-3:]) or 'none'})")
        for te, ye in zip(sol.t_events[0], sol.y_events[0]):
            if ye[0] > 0:
                maxima.append(float(ye[0]))
                times.append(t0 + float(te))
        y = sol.y[:, -1]
        t0 += chunk
        if len(maxima) >= 6:
            m = np.array(maxima[-6:])
            if m[-1] < 1e-8 * max(maxima[0], 1e-300):
                break
            rel = np.max(np.abs(np.diff(m))) / m[-1]
            if rel < 1e-7:
                break
        if maxima and maxima[-1] < 1e-9 * max(abs(x_start), 1e-300):
            break
    return _settled(maxima, times, x_start, t0, max_time, y)


def _transient_compiled(cm: CompiledModel, x_start: float, rtol: float, max_time: float,
                        x_max: float) -> tuple[float, float, list[float]]:
    """:func:`_transient` through the compiled flow: the state is sampled 128 times per
    linear period; each maximum of ``x`` is bracketed between samples, located by cubic
    Hermite interpolation of ``x'`` (slopes ``x''`` from the model) and refined by
    Newton's method on ``x'(t) = 0`` with the flow itself."""
    from ._compile import template_flow

    fl = template_flow(cm.template)
    T_lin = 2 * math.pi / cm.omega0
    per = 128
    chunk_periods = 20
    h = T_lin / per
    y = np.array([x_start, 0.0])
    maxima: list[float] = []
    times: list[float] = []
    t0 = 0.0
    # slow relaxation oscillations (period >> 2 pi/omega0) get up to 20 max_time to show
    # six maxima
    while t0 < max_time or (len(maxima) < 8 and t0 < 20 * max_time):
        res = fl(y, chunk_periods * T_lin, cm.pvec, rtol, rtol * 1e-2, chunk_periods * per,
                 2 * 10**5)
        ys = res.y
        size = np.abs(ys[:, 0]) + np.abs(ys[:, 1])
        over = np.nonzero(~(size <= x_max))[0]
        n_ok = int(over[0]) if over.size else len(ys)
        xs, vs = ys[:n_ok, 0], ys[:n_ok, 1]
        for i in np.nonzero((vs[:-1] > 0) & (vs[1:] <= 0))[0]:
            t_c, x_c = _hermite_maximum(cm, xs[i], vs[i], xs[i + 1], vs[i + 1], h)
            if x_c > 0:
                t_r, x_r = _refine_maximum(cm, fl, ys[i], t_c, h, rtol)
                if np.isfinite(x_r):
                    t_c, x_c = t_r, x_r
                maxima.append(x_c)
                times.append(t0 + i * h + t_c)
        if over.size:
            i = int(over[0])
            growing = (len(maxima) >= 3 and maxima[-1] > maxima[-2] > maxima[-3]
                       and size[i - 1] > 0.1 * x_max)
            if res.status == 1 and growing:
                raise NoCycleError(
                    f"no limit cycle: the amplitude grows without bound (|x| + |x'| reached "
                    f"{size[i - 1]:.3g} by t = {t0 + (i - 1) * h:.6g}, where the step limit of "
                    f"the compiled integrator stopped it; last maxima of x: "
                    f"{', '.join(f'{m:.4g}' for m in maxima[-3:])})")
            if res.status == 1 and np.all(np.isfinite(ys[i - 1])) and size[i - 1] < x_max:
                raise IntegrationError(
                    f"{JIT_METHOD}: the step limit (2e5 per {chunk_periods} linear periods) "
                    f"was reached by t = {t0 + (i - 1) * h:.6g} with |x| + |x'| = "
                    f"{size[i - 1]:.3g}; the transient is too stiff for an explicit method "
                    "(use method='LSODA')")
            raise NoCycleError(
                f"no limit cycle: the amplitude grows without bound (|x| + |x'| > {x_max:.3g} "
                f"at t = {t0 + i * h:.6g}; last maxima of x: "
                f"{', '.join(f'{m:.4g}' for m in maxima[-3:]) or 'none'})")
        y = ys[-1].copy()
        t0 += chunk_periods * T_lin
        if len(maxima) >= 6:
            m = np.array(maxima[-6:])
            if m[-1] < 1e-8 * max(maxima[0], 1e-300):
                break
            if np.max(np.abs(np.diff(m))) / m[-1] < 1e-7:
                break
        if maxima and maxima[-1] < 1e-9 * max(abs(x_start), 1e-300):
            break
        if not maxima and np.hypot(*y) < 1e-9 * max(abs(x_start), 1e-300):
            break
    return _settled(maxima, times, x_start, t0, max_time, y)


def _hermite_maximum(cm, x0, v0, x1, v1, h) -> tuple[float, float]:
    """The zero of ``x'`` in ``[0, h]`` and ``x`` there, by cubic Hermite interpolation."""
    a0, a1 = cm.acc(0.0, x0, v0), cm.acc(0.0, x1, v1)
    # x'(s) on s in [0, 1] (time s h): Hermite cubic with values v0, v1 and slopes h a0, h a1
    c = np.array([2 * v0 - 2 * v1 + h * a0 + h * a1, -3 * v0 + 3 * v1 - 2 * h * a0 - h * a1,
                  h * a0, v0])
    roots = [r.real for r in np.roots(c) if abs(r.imag) < 1e-12 and -1e-9 <= r.real <= 1 + 1e-9]
    s = min(roots) if roots else v0 / (v0 - v1)
    s = min(max(s, 0.0), 1.0)
    # x(s): integrate the cubic for x' and correct with the end value (quartic)
    xs = x0 + h * (c[0] * s**4 / 4 + c[1] * s**3 / 3 + c[2] * s**2 / 2 + c[3] * s)
    x_end = x0 + h * (c[0] / 4 + c[1] / 3 + c[2] / 2 + c[3])
    return s * h, float(xs + s * (x1 - x_end))


def _refine_maximum(cm, fl, y_i, s, h, rtol) -> tuple[float, float]:
    """The zero of ``x'`` in ``(0, h]`` after the sample ``y_i`` (where ``x' > 0``, and
    ``x' <= 0`` at ``h``): safeguarded Newton's method (bisection when a step leaves the
    bracket) with the compiled flow, ``x''`` as the derivative, from the interpolated ``s``.
    Returns ``(s, x(s))``, or ``(nan, nan)`` if the flow fails."""
    lo, hi = 0.0, h
    s = s if 0.0 < s <= h else 0.5 * h
    x_c = float("nan")
    for _ in range(80):
        res = fl(y_i[:2], s, cm.pvec, rtol, rtol * 1e-2, 1, 10**4)
        if res.status:
            return float("nan"), float("nan")
        x_c, v_c = res.y[-1]
        if v_c > 0:
            lo = s
        else:
            hi = s
        a_c = cm.acc(0.0, x_c, v_c)
        new = s - v_c / a_c if a_c != 0 else 0.5 * (lo + hi)
        if not lo < new < hi:
            new = 0.5 * (lo + hi)
        if abs(new - s) <= 1e-15 * max(1.0, h) or hi - lo <= 1e-15 * max(1.0, h):
            break
        s = new
    return s, float(x_c)


def _settled(maxima, times, x_start, t0, max_time, y):
    """The verdict of a transient: decay to rest, too few maxima, or (x_max, period)."""
    if not maxima or maxima[-1] < 1e-8 * max(abs(x_start), maxima[0]):
        last = maxima[-1] if maxima else float(np.hypot(*y[:2]))
        raise NoCycleError(
            f"no limit cycle: the motion decays to rest (max x fell from "
            f"{maxima[0] if maxima else abs(x_start):.4g} to {last:.3g} by t = {t0:.6g})")
    if len(times) < 3:
        raise NoCycleError(f"no limit cycle found by t = {max_time:.6g}: fewer than three "
                           f"maxima of x ({len(times)})")
    # one period may contain several local maxima: pick the return to the largest
    return _period_from_maxima(maxima, times)


def _period_from_maxima(maxima, times):
    m = np.array(maxima)
    tt = np.array(times)
    last_big = int(np.argmax(m[len(m) // 2:]) + len(m) // 2)
    xb = m[last_big]
    prev = [i for i in range(last_big) if abs(m[i] - xb) < 1e-3 * abs(xb) + 1e-12]
    if not prev:
        period = tt[-1] - tt[-2]
    else:
        period = tt[last_big] - tt[prev[-1]]
    return float(xb), float(period), list(maxima)


#: name of the compiled integrator in results and messages
JIT_METHOD = "DOP853 (compiled)"


#: bound on the compiled integrator's steps over one period inside Newton's method
NEWTON_MAX_STEPS = 5 * 10**4


def _flow(cm: CompiledModel, y0, t_end: float, n_out: int, method: str, rtol: float,
          atol: float, max_steps: int = 10**6, steps: list | None = None) -> np.ndarray:
    """States of the extended system at ``t_k = k t_end/n_out``, shape ``(n_out + 1, 9)``.

    ``steps``, if given, receives the compiled integrator's step count.
    """
    t_end = float(t_end)
    if method == JIT_METHOD:
        from ._compile import template_flow

        res = template_flow(cm.template)(y0, t_end, cm.pvec, rtol, atol, n_out, max_steps)
        if steps is not None:
            steps.append(res.steps)
        if res.status:
            raise IntegrationError(f"{method} failed before t = {t_end:.6g} after {res.steps} "
                                   f"steps: {res.message}")
        ys = res.y
    elif method == "LSODA":
        times = np.linspace(0.0, t_end, n_out + 1)
        with np.errstate(all="ignore"):
            ys, info = odeint(cm.rhs_ext, y0, times, tfirst=True, rtol=rtol, atol=atol,
                              full_output=True, mxstep=500000)
        if info["message"] != "Integration successful.":
            raise IntegrationError(f"LSODA failed before t = {t_end:.6g}: {info['message']}")
    else:
        times = np.linspace(0.0, t_end, n_out + 1)
        sol = _solve(cm, y0, t_end, method, rtol, atol, ext=True, dense=True)
        ys = sol.sol(times).T
        ys[-1] = sol.y[:, -1]
    if not np.all(np.isfinite(ys[-1])):
        raise IntegrationError(f"the state became non-finite before t = {t_end:.6g}")
    return ys


def _shooting_method(cm: CompiledModel, x0: float, period: float, method: str) -> str:
    """``"auto"``: the compiled DOP853 when available and the cycle is not stiff, else LSODA."""
    from ._compile import template_flow

    if method == JIT_METHOD and template_flow(cm.template) is None:
        raise IntegrationError(f"the compiled integrator is not available for {cm.name!r} "
                               "(numba not installed, KBM_NO_JIT set, or a function of the "
                               "model without a math-module form); use method='auto' or "
                               "'LSODA'")
    if method != "auto":
        return method
    if template_flow(cm.template) is None:
        return "LSODA"
    return "LSODA" if _stiffness(cm, x0) * period > JIT_STIFF_THRESHOLD else JIT_METHOD


def _compiled_transient(cm: CompiledModel, x_start: float, T_lin: float, method: str) -> bool:
    """Whether the transient from ``x_start`` runs through the compiled flow."""
    from ._compile import template_flow

    if method not in ("auto", JIT_METHOD) or template_flow(cm.template) is None:
        return False
    return method == JIT_METHOD or _stiffness(cm, abs(x_start)) * T_lin < JIT_STIFF_THRESHOLD


def _stiffness(cm: CompiledModel, x0: float) -> float:
    """The largest Jacobian eigenvalue modulus at three points of a circle of radius x0."""
    return max(cm.stiffness(x0, 0.0), cm.stiffness(0.0, cm.omega0 * x0),
               cm.stiffness(0.5 * x0, 0.5 * cm.omega0 * x0))


def _newton(cm, x0, T, method, rtol, atol, max_iter, floor):
    """Newton's method on ``(x(T) - x0, x'(T)) = 0`` for the unknowns ``(x0, T)``."""
    history: list[float] = []
    it = 0
    budget = NEWTON_MAX_STEPS
    while True:
        it += 1
        steps: list[int] = []
        yT = _flow(cm, [x0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0], T, 1, method,
                   rtol, atol, max_steps=budget, steps=steps)[-1]
        if it == 1 and steps:
            # later iterates near the cycle need about as many steps as the first: many
            # more means Newton has wandered into a stiff region
            budget = min(NEWTON_MAX_STEPS, max(5000, 50 * steps[0]))
        r = np.array([yT[0] - x0, yT[1]])
        history.append(float(np.max(np.abs(r))))
        acc = cm.acc(T, yT[0], yT[1])
        J = np.array([[yT[2] - 1.0, yT[1]], [yT[3], acc]])
        try:
            dx, dT = np.linalg.solve(J, -r)
        except np.linalg.LinAlgError:
            raise ConvergenceError(f"singular Newton matrix at x0 = {x0:.10g}, T = {T:.10g} "
                                   "(non-hyperbolic cycle or x' = 0 is not a transversal "
                                   "section there)") from None
        # damp steps that would leave the section, reverse time, or change x0 or T by
        # more than half (a far start then walks instead of jumping into stiff regions)
        lam = min(1.0, 0.5 * max(1.0, abs(x0)) / max(abs(dx), 1e-300),
                  0.5 * T / max(abs(dT), 1e-300))
        while (x0 + lam * dx <= 0 or T + lam * dT <= 0) and lam > 1e-3:
            lam /= 2
        x0, T = x0 + lam * dx, T + lam * dT
        if max(abs(dx) / max(1.0, abs(x0)), abs(dT) / T) < floor or history[-1] < floor:
            return x0, T, it, history
        if len(history) >= 5 and all(b > a for a, b in zip(history[-5:], history[-4:])):
            raise ConvergenceError(
                f"Newton on the return map diverges: the residual |(x(T) - x0, x'(T))| grew "
                f"four times in a row ({', '.join(f'{h:.2e}' for h in history[-5:])}); "
                f"last x0 = {x0:.10g}, T = {T:.10g}")
        if it >= max_iter or not (np.isfinite(x0) and np.isfinite(T)):
            raise ConvergenceError(
                f"Newton on the return map did not converge in {it} iterations; residuals "
                f"|(x(T) - x0, x'(T))|: {', '.join(f'{h:.2e}' for h in history[-6:])}; "
                f"last x0 = {x0:.10g}, T = {T:.10g}")


def _check_nontrivial(cm, converged, meth, rtol, atol, scale) -> None:
    """Reject a 'cycle' that is an equilibrium or whose trivial multiplier is not 1."""
    x0, T, it, history = converged
    if x0 < 1e-6 * max(1.0, abs(scale)):
        raise ConvergenceError(f"Newton converged to the equilibrium (x0 = {x0:.3g}), not to a "
                               "cycle")
    ys = _flow(cm, [x0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0], T, 64, meth, rtol, atol)
    spread = float(np.ptp(ys[:, 0]))
    if spread < 1e-6 * max(1.0, abs(x0)):
        raise NoCycleError(f"no limit cycle: the motion settles to rest at x = {x0:.6g} (an "
                           f"equilibrium of the potential; x varies by {spread:.2e} over "
                           f"T = {T:.4g}); start elsewhere (x_start) to look for a cycle")
    yT = ys[-1]
    mults = np.linalg.eigvals(np.array([[yT[2], yT[4]], [yT[3], yT[5]]]))
    if np.min(np.abs(mults - 1.0)) > 1e-5:
        raise ConvergenceError(f"the orbit found (x0 = {x0:.6g}, T = {T:.6g}) has no Floquet "
                               f"multiplier 1 ({mults[0]:.6g}, {mults[1]:.6g}): not a cycle")


def _kbm_guess(model, params) -> tuple[float, float] | None:
    """The stable first-order KBM cycle with the largest amplitude, as (amplitude, period)."""
    try:
        from kbm.models import get_model

        m = get_model(model) if isinstance(model, str) else model
        vals = m.resolve(dict(params or {}))
        rates = _first_order(m)
        need = {p: vals[p] for p in rates.params if p in vals}
        if len(need) != len(rates.params) or "mu" not in vals:
            return None
        cycles = [c for c in rates.cycles({"mu": vals["mu"], **need}) if c.stable]
    except KBMError:
        return None
    if not cycles:
        return None
    c = max(cycles, key=lambda c: c.amplitude)
    return c.amplitude, c.period


#: memo of first-order KBM averaged equations used as initial guesses (bounded; time only)
_FIRST_ORDER: dict = {}


def _first_order(m):
    import sympy as sp

    from kbm import averaged_rates, derive

    key = (m.name, sp.srepr(m.F), sp.srepr(m.omega0))
    if key not in _FIRST_ORDER:
        if len(_FIRST_ORDER) >= 32:
            _FIRST_ORDER.pop(next(iter(_FIRST_ORDER)))
        _FIRST_ORDER[key] = averaged_rates(derive(m, 1))
    return _FIRST_ORDER[key]


def limit_cycle(model: Oscillator | str, params: Mapping[str, object] | None = None, *,
                guess: tuple[float, float] | None = None, digits: int | None = None,
                rtol: float = 1e-12, atol: float | None = None, method: str = "auto",
                max_iter: int = 25, x_start: float = 1.0, max_time: float | None = None,
                x_max: float | None = None, template=None,
                n_samples: int = 1024, n_harmonics: int = 16) -> LimitCycle:
    """The limit cycle of an autonomous model, by shooting on ``x' = 0, x > 0``.

    Parameters
    ----------
    model
        An :class:`~kbm.models.Oscillator` or a built-in name.
    params
        Parameter values (physical names such as ``Delta``, ``lam`` or the
        scaled ones), including ``mu``.
    guess
        ``(amplitude, period)`` to start Newton from.  Without it, the stable
        first-order KBM cycle is tried first (largest amplitude), and if Newton
        does not converge from there, transients from ``x = a_KBM`` (the
        first-order amplitude, when there is one) and from ``x = x_start``,
        ``x' = 0`` are integrated until the maxima of ``x`` settle.
    digits
        If given (up to ~50), also compute period and amplitudes with an
        mpmath Taylor-series integrator to this many digits
        (:func:`numerics.highprec.limit_cycle_mp`).
    rtol, atol
        Integrator tolerances (default ``atol = rtol``).
    method
        ``"auto"``: DOP853 compiled with numba (:mod:`numerics._jit`) when the
        model compiles and the cycle is not too stiff (largest Jacobian
        eigenvalue times the period below :data:`JIT_STIFF_THRESHOLD`), else
        LSODA (ODEPACK), which switches between Adams (non-stiff) and BDF
        (stiff) by itself.  Or name one: ``"DOP853 (compiled)"``, ``"LSODA"``,
        or any :func:`scipy.integrate.solve_ivp` method (``"DOP853"``,
        ``"Radau"``, ...).  The transient, when needed, runs through the
        compiled flow under the same rule; otherwise through scipy's DOP853,
        or Radau when the stiffness exceeds :data:`STIFF_THRESHOLD`.
    max_iter
        Bound on Newton iterations.
    template
        A :class:`numerics._compile.ModelTemplate` of the model (skips lambdifying;
        used by :func:`numerics.sweep`).
    x_start, max_time, x_max
        Start of the transient, its time limit, and the size ``|x| + |x'|`` above
        which the motion counts as growing without bound (default
        ``1000 max(1, |x_start|)``; raise it for cycles larger than that).

    Returns
    -------
    LimitCycle
        With ``success = False`` and a message when Newton stalls above the
        integration accuracy but the orbit is still closed to ``1e-6``.

    Raises
    ------
    kbm.errors.NonAutonomousError
        For a driven model (``v != 0``).
    numerics.errors.NoCycleError
        If the transient grows without bound or decays to rest.
    numerics.errors.ConvergenceError
        If Newton's method fails (residual history in the message).

    Examples
    --------
    >>> c = limit_cycle("vdp", {"mu": 1})
    >>> round(c.period, 8), round(c.amplitude_max, 8)
    (6.66328686, 2.00861986)
    """
    cm = compile_model(model, params, template=template)
    if not cm.autonomous:
        raise NonAutonomousError(f"limit cycles need an autonomous model; {cm.name!r} has an "
                                 "explicit time dependence (stage velocity v != 0); use "
                                 "`kbm slide` for the driven slider")
    atol = rtol if atol is None else atol
    T_lin = 2 * math.pi / cm.omega0
    if max_time is None:
        mu = abs(cm.values.get("mu", 1.0)) or 1.0
        max_time = min(max(200 * T_lin, 60.0 / mu), 2e5)
    floor = 1e3 * max(rtol, atol)
    source = "guess"
    start = guess
    if start is None:
        start = _kbm_guess(model, params)
        source = "KBM first-order averaged cycle"
    converged = None
    if start is not None:
        x0, period = float(start[0]), float(start[1])
        if not (np.isfinite(x0) and np.isfinite(period) and period > 0 and x0 > 0):
            raise ConvergenceError(f"bad initial guess (amplitude, period) = {start}")
        meth = _shooting_method(cm, x0, period, method)
        try:
            converged = _newton(cm, x0, period, meth, rtol, atol, max_iter, floor)
            _check_nontrivial(cm, converged, meth, rtol, atol, x0)
        except (ConvergenceError, IntegrationError, NoCycleError):
            if guess is not None:
                raise
            converged = None
    if converged is None:
        # transients: from the KBM amplitude when there is one (a cycle may coexist with
        # stable equilibria that a start at x_start falls into), then from x_start
        starts = [float(x_start)]
        if guess is None and start is not None and abs(float(start[0]) - x_start) > 1e-3:
            starts.insert(0, float(start[0]))
        failures: list[tuple[float, Exception]] = []
        big = x_max if x_max is not None else 1e3 * max(1.0, abs(x_start))
        for xs in starts:
            try:
                if _compiled_transient(cm, xs, T_lin, method):
                    x0, period, _ = _transient_compiled(cm, xs, max(rtol, 1e-10), max_time,
                                                        big)
                else:
                    tmeth = _choose_method(cm, abs(xs), T_lin,
                                           "auto" if method in ("auto", "LSODA", JIT_METHOD)
                                           else method)
                    x0, period, _ = _transient(cm, xs, tmeth, max(rtol, 1e-10), max_time, big)
                meth = _shooting_method(cm, x0, period, method)
                found = _newton(cm, x0, period, meth, rtol, atol, max_iter, floor)
                _check_nontrivial(cm, found, meth, rtol, atol, x0)
            except (ConvergenceError, IntegrationError, NoCycleError) as exc:
                failures.append((xs, exc))
            else:
                converged, source = found, f"transient from x = {xs:.6g}"
                break
        if converged is None:
            xs, exc = failures[-1]
            if len(failures) == 1:
                raise exc
            raise type(exc)("; ".join(f"from x = {s:.6g} (x' = 0): {e}" for s, e in failures)) \
                from exc
    x0, T, it, history = converged
    # final pass on the converged orbit: samples, monodromy, dissipation
    tt = np.linspace(0.0, T, n_samples + 1)
    ys = _flow(cm, [x0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0], T, n_samples, meth, rtol,
               atol)
    yT = ys[-1]
    residual = float(max(abs(yT[0] - x0), abs(yT[1])))
    xs, vs = ys[:-1, 0], ys[:-1, 1]
    tt = tt[:-1]
    if not source.startswith("transient") and x0 < np.max(xs) - 1e-6 * max(1.0, abs(x0)):
        # the guess led to a point that is not the maximum of x: restart at the maximum
        i = int(np.argmax(xs))
        converged = _newton(cm, float(xs[i]), T, meth, rtol, atol, max_iter, floor)
        x0, T, it2, h2 = converged
        it, history = it + it2, history + h2
        tt = np.linspace(0.0, T, n_samples + 1)
        ys = _flow(cm, [x0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0], T, n_samples, meth, rtol,
                   atol)
        yT = ys[-1]
        residual = float(max(abs(yT[0] - x0), abs(yT[1])))
        xs, vs, tt = ys[:-1, 0], ys[:-1, 1], tt[:-1]
    Phi = np.array([[yT[2], yT[4]], [yT[3], yT[5]]])
    mults = np.linalg.eigvals(Phi)
    order = np.argsort(np.abs(mults - 1.0))
    trivial, other = complex(mults[order[0]]), complex(mults[order[1]])
    det = float(np.linalg.det(Phi))
    liou = float(math.exp(yT[6]))
    gp, gm = float(yT[7]), float(yT[8])
    total = cm.plus_factor * gp - gm
    e0 = float(cm.energy(x0, 0.0))
    e1 = float(cm.energy(yT[0], yT[1]))
    coeffs = np.fft.rfft(xs) / n_samples
    harmonics = coeffs[:n_harmonics].copy()
    first = 2 * abs(coeffs[1])
    mp: dict = {}
    if digits is not None:
        from .highprec import limit_cycle_mp

        mp = limit_cycle_mp(cm.acceleration_expr, int(digits), x0, T)
    success = residual < 1e3 * floor
    msg = (f"converged in {it} Newton iterations from the {source} ({meth}, rtol {rtol:g}); "
           f"|(x(T) - x0, x'(T))| = {residual:.2e}; trivial multiplier {trivial.real:.12f}")
    if not success:
        msg = (f"Newton stalled: |(x(T) - x0, x'(T))| = {residual:.2e} after {it} iterations "
               f"(floor {floor:.1e})")
    return LimitCycle(
        success=bool(success), message=msg, model=cm.name, params=dict(cm.values),
        period=float(T), frequency=2 * math.pi / float(T), amplitude_max=float(x0),
        amplitude_first_harmonic=float(first), harmonics=harmonics, t=tt, x=xs, xdot=vs,
        floquet_multipliers=(trivial, other), stable=bool(abs(other) < 1.0),
        liouville=(det, liou),
        dissipation=Dissipation(total=float(total), gamma_plus=gp, gamma_minus=gm,
                                plus_factor=cm.plus_factor),
        energy_residual=float(e0 - e1 - total), iterations=it, residual=float(residual),
        history=tuple(history), method=meth, digits=None if digits is None else int(digits),
        mp=mp)
