"""Transients: integrate until the maxima of ``x`` settle, for a first ``(x_max, period)``.

One settle-on-maxima algorithm (:func:`_settled_now`, :func:`_settled`) over two
samplers of the trajectory: scipy's integrators with an event at ``x' = 0``
(:func:`_transient_scipy`), and the compiled flow sampled 128 times per linear
period with each maximum bracketed, interpolated and refined by Newton's method
with the flow itself (:func:`_transient_compiled`).  :func:`transient` picks the
sampler for the method chosen by :func:`numerics.flow.choose_method`.
"""

from __future__ import annotations

import math

import numpy as np

from numerics.errors import IntegrationError, NoCycleError
from numerics.flow import CompiledModel, Method, solve, template_flow

__all__ = ["transient"]


def transient(cm: CompiledModel, x_start: float, method: Method, rtol: float, max_time: float,
              x_max: float) -> tuple[float, float, list[float]]:
    """Integrate from ``(x_start, 0)`` until successive maxima of ``x`` settle.

    Parameters
    ----------
    method
        ``Method.COMPILED`` for the compiled sampler, else a scipy method.
    rtol
        Integrator tolerance.
    max_time, x_max
        Time limit, and the size ``|x| + |x'|`` taken as growth without bound.

    Returns
    -------
    tuple
        ``(x_max, period estimate, all maxima)``.

    Raises
    ------
    numerics.errors.NoCycleError
        If the motion grows without bound, decays to rest, or shows fewer than
        three maxima in the time allowed.
    """
    if method is Method.COMPILED:
        return _transient_compiled(cm, x_start, rtol, max_time, x_max)
    return _transient_scipy(cm, x_start, method, rtol, max_time, x_max)


def _settled_now(maxima: list[float], x_start: float) -> bool:
    """Whether the last six maxima agree to 1e-7 (relative), or the motion has died out."""
    if len(maxima) >= 6:
        m = np.array(maxima[-6:])
        if m[-1] < 1e-8 * max(maxima[0], 1e-300):
            return True
        if np.max(np.abs(np.diff(m))) / m[-1] < 1e-7:
            return True
    return bool(maxima) and maxima[-1] < 1e-9 * max(abs(x_start), 1e-300)


def _maximum_event(t, y):
    return y[1]


_maximum_event.direction = -1  # x' goes from + to -: a maximum of x


def _transient_scipy(cm: CompiledModel, x_start: float, method: Method, rtol: float,
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
        sol = solve(cm, y, chunk, method, rtol, rtol * 1e-2, events=[ev, blowup])
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
        if _settled_now(maxima, x_start):
            break
    return _settled(maxima, times, x_start, t0, max_time, y)


def _transient_compiled(cm: CompiledModel, x_start: float, rtol: float, max_time: float,
                        x_max: float) -> tuple[float, float, list[float]]:
    """:func:`_transient_scipy` through the compiled flow: the state is sampled 128 times per
    linear period; each maximum of ``x`` is bracketed between samples, located by cubic
    Hermite interpolation of ``x'`` (slopes ``x''`` from the model) and refined by
    Newton's method on ``x'(t) = 0`` with the flow itself."""
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
                    f"{Method.COMPILED.label}: the step limit (2e5 per {chunk_periods} linear periods) "
                    f"was reached by t = {t0 + (i - 1) * h:.6g} with |x| + |x'| = "
                    f"{size[i - 1]:.3g}; the transient is too stiff for an explicit method "
                    "(use method='LSODA')")
            raise NoCycleError(
                f"no limit cycle: the amplitude grows without bound (|x| + |x'| > {x_max:.3g} "
                f"at t = {t0 + i * h:.6g}; last maxima of x: "
                f"{', '.join(f'{m:.4g}' for m in maxima[-3:]) or 'none'})")
        y = ys[-1].copy()
        t0 += chunk_periods * T_lin
        if _settled_now(maxima, x_start):
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
