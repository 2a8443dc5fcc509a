"""The adaptive DOP853 stepper of :mod:`numerics.flow.jit`, as source appended to a printed rhs.

This file is read as text and appended to the module that :func:`numerics.flow.jit.jit_flow`
prints for a model (which defines ``rhs(t, y, p, out)`` above it); numba compiles
both.  The method is scipy's ``solve_ivp(method="DOP853")``: the same Butcher
tableau (taken from scipy), the same blended 3rd/5th-order error estimate and step
control (Hairer, Norsett and Wanner, *Solving Ordinary Differential Equations I*,
2nd ed., Springer 1993, sec. II.10).
"""

import math

import numpy as np
from numba import njit

from numerics.flow._dop853_tableau import dop853_coefficients

_dc = dop853_coefficients()  # scipy's tableau, without importing scipy.integrate

#: step-size control (Hairer, Norsett & Wanner, sec. II.4; the values of scipy's rk.py)
SAFETY = 0.9
MIN_FACTOR = 0.2
MAX_FACTOR = 10.0
#: the error exponent -1/(q + 1) for the 7th-order embedded estimate
ERROR_EXPONENT = -1.0 / 8.0

_NS = _dc.N_STAGES
_A = np.ascontiguousarray(_dc.A[:_NS, :_NS])
_B = np.ascontiguousarray(_dc.B)
_C = np.ascontiguousarray(_dc.C[:_NS])
_E3 = np.ascontiguousarray(_dc.E3)
_E5 = np.ascontiguousarray(_dc.E5)


@njit(cache=True)
def _norm(v, scale):
    s = 0.0
    for i in range(v.shape[0]):
        s += (v[i] / scale[i]) ** 2
    return math.sqrt(s / v.shape[0])


@njit(cache=True)
def _error(K, y, ynew, h, rtol, atol, n):
    """The blended 3rd/5th-order error norm of a step of length ``h > 0`` over the first
    ``n`` states (< 1: accepted; Hairer, Norsett & Wanner, sec. II.10, as scipy's)."""
    e3 = 0.0
    e5 = 0.0
    for i in range(n):
        sc = atol + max(abs(y[i]), abs(ynew[i])) * rtol
        a3 = 0.0
        a5 = 0.0
        for j in range(_NS + 1):
            a3 += K[j, i] * _E3[j]
            a5 += K[j, i] * _E5[j]
        e3 += (a3 / sc) ** 2
        e5 += (a5 / sc) ** 2
    if e5 == 0.0 and e3 == 0.0:
        return 0.0
    return h * e5 / math.sqrt((e5 + 0.01 * e3) * n)


@njit(cache=True)
def flow(y0, t_end, p, rtol, atol, n_out, max_steps):
    """States at t_k = k t_end / n_out, k = 0..n_out (NaN after a failure); status 0 ok,
    1 step limit, 2 step size underflow, 3 non-finite state; and the number of steps."""
    n = y0.shape[0]
    out = np.full((n_out + 1, n), np.nan)
    out[0, :] = y0
    y = y0.copy()
    K = np.zeros((_NS + 1, n))
    f = np.empty(n)
    rhs(0.0, y, p, f)  # noqa: F821 - printed before this source
    # initial step (Hairer, Norsett & Wanner, sec. II.4; as scipy's select_initial_step)
    scale = np.empty(n)
    for i in range(n):
        scale[i] = atol + abs(y[i]) * rtol
    d0 = _norm(y, scale)
    d1 = _norm(f, scale)
    if d0 < 1e-5 or d1 < 1e-5:
        h0 = 1e-6
    else:
        h0 = 0.01 * d0 / d1
    y1 = y + h0 * f
    f1 = np.empty(n)
    rhs(h0, y1, p, f1)  # noqa: F821
    d2 = _norm(f1 - f, scale) / h0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / 8.0)
    h = min(100 * h0, h1, t_end / n_out)
    t = 0.0
    k = 1
    steps = 0
    ynew = np.empty(n)
    fnew = np.empty(n)
    ys = np.empty(n)
    rejected = False
    while k <= n_out:
        t_next = t_end * k / n_out
        if steps >= max_steps:
            return out, 1, steps
        hmin = 10.0 * abs(np.nextafter(t, np.inf) - t)
        h_try = h
        last = False
        if t + h_try >= t_next - hmin:
            h_try = t_next - t
            last = True
        if h_try < hmin:
            return out, 2, steps
        # stages
        K[0, :] = f
        for s in range(1, _NS):
            for i in range(n):
                acc = 0.0
                for j in range(s):
                    acc += _A[s, j] * K[j, i]
                ys[i] = y[i] + h_try * acc
            rhs(t + _C[s] * h_try, ys, p, K[s])  # noqa: F821
        for i in range(n):
            acc = 0.0
            for j in range(_NS):
                acc += _B[j] * K[j, i]
            ynew[i] = y[i] + h_try * acc
        t_new = t_next if last else t + h_try
        rhs(t_new, ynew, p, fnew)  # noqa: F821
        K[_NS, :] = fnew
        steps += 1
        finite = True
        for i in range(n):
            if not math.isfinite(ynew[i]):
                finite = False
        err = _error(K, y, ynew, abs(h_try), rtol, atol, n)
        if not finite:
            err = math.inf
        if err < 1.0:
            if err == 0.0:
                factor = MAX_FACTOR
            else:
                factor = min(MAX_FACTOR, SAFETY * err ** ERROR_EXPONENT)
            if rejected:
                factor = min(1.0, factor)
            t = t_new
            y[:] = ynew
            f[:] = fnew
            if last:
                out[k, :] = y
                k += 1
                # keep the natural step, not the shortened one
                if h_try < h:
                    factor = 1.0
                    h_try = h
            h = h_try * factor
            rejected = False
        else:
            if not finite and h_try < 1e-12 * max(1.0, t_end):
                return out, 3, steps
            h = h_try * max(MIN_FACTOR, SAFETY * err ** ERROR_EXPONENT) if finite else 0.5 * h_try
            rejected = True
    return out, 0, steps


@njit(cache=True)
def _step2(t, y, h, p, sign, K, ys, ynew, fnew):
    """One DOP853 step of size ``h`` of the state ``(x, x')`` under ``sign`` times the field
    (``sign = -1``: backward in time): the stages in ``K``, the new state in ``ynew`` and
    its field in ``fnew``."""
    rhs(t, y, p, K[0])  # noqa: F821
    K[0, 0] *= sign
    K[0, 1] *= sign
    for s in range(1, _NS):
        for i in range(2):
            acc = 0.0
            for j in range(s):
                acc += _A[s, j] * K[j, i]
            ys[i] = y[i] + h * acc
        rhs(t + sign * _C[s] * h, ys, p, K[s])  # noqa: F821
        K[s, 0] *= sign
        K[s, 1] *= sign
    for i in range(2):
        acc = 0.0
        for j in range(_NS):
            acc += _B[j] * K[j, i]
        ynew[i] = y[i] + h * acc
    rhs(t + sign * h, ynew, p, fnew)  # noqa: F821
    fnew[0] *= sign
    fnew[1] *= sign
    K[_NS, 0] = fnew[0]
    K[_NS, 1] = fnew[1]


@njit(cache=True)
def _to_level(y0, sign, comp, level, t_max, p, rtol, atol, max_steps):
    """Follow ``(x, x')`` from ``y0`` forward (``sign = 1``) or backward (``-1``) in time to
    where ``y[comp] - level`` first changes sign; returns ``(x, x', elapsed time, status)``
    with status 0 at the crossing, 1 if there was none within ``t_max`` or ``max_steps``, 3
    for a non-finite state.  The step control is :func:`flow`'s; the crossing inside the
    last step is found by Newton's method on the step length (``d y[comp]/dh`` is the
    signed field's component ``comp``), each iterate one DOP853 step from the start of
    that step."""
    y = y0[:2].copy()
    K = np.zeros((_NS + 1, 2))
    ys = np.empty(2)
    ynew = np.empty(2)
    fnew = np.empty(2)
    f = np.empty(2)
    rhs(0.0, y, p, f)  # noqa: F821
    h = 1e-3 * min(1.0, t_max)
    t = 0.0
    rejected = False
    for _ in range(max_steps):
        if t >= t_max:
            break
        h_try = min(h, t_max - t)
        _step2(sign * t, y, h_try, p, sign, K, ys, ynew, fnew)
        finite = math.isfinite(ynew[0]) and math.isfinite(ynew[1])
        err = _error(K, y, ynew, h_try, rtol, atol, 2)
        if not finite:
            if h_try < 1e-12:
                return ynew[0], ynew[1], t, 3
            h = 0.5 * h_try
            rejected = True
            continue
        if err >= 1.0:
            h = h_try * max(MIN_FACTOR, SAFETY * err ** ERROR_EXPONENT)
            rejected = True
            continue
        if (ynew[comp] > level) != (y[comp] > level) and y[comp] != level:
            # the crossing lies in this step: Newton on the length of a step from y
            g0 = y[comp] - level
            tau = h_try * g0 / (g0 - (ynew[comp] - level))
            for _k in range(30):
                _step2(sign * t, y, tau, p, sign, K, ys, ynew, fnew)
                d = (ynew[comp] - level) / fnew[comp]
                tau -= d
                if abs(d) <= 1e-15 * max(1.0, tau):
                    break
            _step2(sign * t, y, tau, p, sign, K, ys, ynew, fnew)
            return ynew[0], ynew[1], t + tau, 0
        factor = MAX_FACTOR if err == 0.0 else min(MAX_FACTOR, SAFETY * err ** ERROR_EXPONENT)
        if rejected:
            factor = min(1.0, factor)
        t += h_try
        y[0] = ynew[0]
        y[1] = ynew[1]
        h = h_try * factor
        rejected = False
    return y[0], y[1], t, 1


@njit(cache=True)
def to_turn(y0, sign, t_max, p, rtol, atol, max_steps):
    """Follow ``(x, x')`` from ``y0`` forward (``sign = 1``) or backward (``-1``) in time to
    where ``x'`` first changes sign: :func:`_to_level` of ``x'`` at 0."""
    return _to_level(y0, sign, 1, 0.0, t_max, p, rtol, atol, max_steps)


@njit(cache=True)
def to_section(y0, sign, xsec, t_max, p, rtol, atol, max_steps):
    """Follow ``(x, x')`` from ``y0`` forward (``sign = 1``) or backward (``-1``) in time to
    where it first crosses the section ``x = xsec``: :func:`_to_level` of ``x`` at
    ``xsec`` (the Newton derivative ``d x/dh = sign x'``)."""
    return _to_level(y0, sign, 0, xsec, t_max, p, rtol, atol, max_steps)
