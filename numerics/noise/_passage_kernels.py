"""Compiled first-passage and pulled-slider kernels of :mod:`numerics.noise`, appended as
source after :mod:`numerics.noise._kernels` (whose ``_step``, ``_first``, ``_increment``,
``_pair_start``, ``_advance2`` and ``_noise_factor`` they call) to a printed model.

``first_passages`` gives the escape times of :mod:`numerics.escape` and ``slip_stats`` the
friction runs of :mod:`numerics.thermal.friction`; both run trajectories two to a loop (two
independent chains of dependent operations fill the core; the numbers are those of one
trajectory at a time) with three-point increments (why not four-point ones:
``docs/noise.rst``, measured by ``benchmarks/bench_noise.py`` part 3).
"""

import math

import numpy as np
from numba import njit


@njit(cache=True)
def _passage(p, x, v, f, t0, k0, h, n_max, xl, xr, s, amp):
    """Steps ``k0 .. n_max - 1`` of one trajectory (state ``(x, v)``, carried force ``f``)
    until ``x <= xl`` or ``x >= xr`` (or non-finite): ``(time, hit)``, the time the step's
    end, ``n_max h`` when it never happens."""
    for k in range(k0, n_max):
        x, v, f = _step(t0 + k * h, x, v, f, h, _increment(s, amp), p)  # noqa: F821
        if x <= xl or x >= xr or not math.isfinite(x):
            return (k + 1) * h, True
    return n_max * h, False


@njit(cache=True)
def first_passages(p, sigma, y0, t0, h, n_max, xl, xr, states):
    """Per trajectory: the first time ``x <= xl`` or ``x >= xr`` (the step's end; ``n_max h``
    when it never happens) and whether it happened.  Trajectories run two to a loop (see
    :func:`_advance2`) until one of them leaves, the other then alone (:func:`_passage`):
    the same numbers as one at a time."""
    m = y0.shape[0]
    times = np.empty(m)
    hit = np.zeros(m, dtype=np.bool_)
    amp = sigma * _noise_factor(p, h) * math.sqrt(3.0 * h)  # noqa: F821
    for i in range(0, m - 1, 2):
        sa, xa, va, fa, sb, xb, vb, fb = _pair_start(p, y0, t0, states, i, i + 1)  # noqa: F821
        done = n_max
        out_a = False
        out_b = False
        for k in range(n_max):
            t = t0 + k * h
            xa, va, fa = _step(t, xa, va, fa, h, _increment(sa, amp), p)  # noqa: F821
            xb, vb, fb = _step(t, xb, vb, fb, h, _increment(sb, amp), p)  # noqa: F821
            out_a = xa <= xl or xa >= xr or not math.isfinite(xa)
            out_b = xb <= xl or xb >= xr or not math.isfinite(xb)
            if out_a or out_b:
                done = k + 1
                break
        if out_a:
            times[i], hit[i] = done * h, True
        else:
            times[i], hit[i] = _passage(p, xa, va, fa, t0, done, h, n_max, xl, xr, sa, amp)
        if out_b:
            times[i + 1], hit[i + 1] = done * h, True
        else:
            times[i + 1], hit[i + 1] = _passage(p, xb, vb, fb, t0, done, h, n_max, xl, xr, sb,
                                                amp)
    if m % 2:
        s = states[m - 1].copy()
        x, v = y0[m - 1, 0], y0[m - 1, 1]
        f = _first(t0, x, v, p)  # noqa: F821
        times[m - 1], hit[m - 1] = _passage(p, x, v, f, t0, 0, h, n_max, xl, xr, s, amp)
    return times, hit


@njit(cache=True)
def _slip_init(x, lam):
    """The running record of :func:`slip_stats` for one trajectory at ``x``: the well, the
    time of the last crossing, the largest spring force since, then the sums (force,
    slips, slip force and its square, backward jumps, stage position at the slip and its
    square)."""
    acc = np.zeros(10)
    acc[0] = math.floor(x / lam + 0.5)
    acc[1] = -1e300
    acc[2] = -1e300
    return acc


@njit(cache=True)
def _slip_record(acc, t, x, v, p, lam, min_gap, v_stage):
    """One step's end ``(t, x, v)`` into the record ``acc`` (:func:`_slip_init`)."""
    f = spring(t, x, v, p)  # noqa: F821
    acc[3] += f
    if f > acc[2]:
        acc[2] = f
    w = math.floor(x / lam + 0.5)
    if w > acc[0]:
        if t - acc[1] > min_gap:
            acc[4] += 1.0
            acc[5] += acc[2]
            acc[6] += acc[2] * acc[2]
            rel = v_stage * t - acc[0] * lam
            acc[8] += rel
            acc[9] += rel * rel
        acc[1] = t
        acc[2] = f
    elif w < acc[0]:
        if t - acc[1] > min_gap:
            acc[7] += 1.0
        acc[1] = t
        acc[2] = f
    acc[0] = w


@njit(cache=True)
def _slip_row(out, i, acc, n_run):
    """Row ``i`` of :func:`slip_stats` from the record."""
    out[i, 0] = acc[3] / n_run
    out[i, 1] = acc[4]
    out[i, 2] = acc[5]
    out[i, 3] = acc[6]
    out[i, 4] = acc[7]
    out[i, 5] = acc[8]
    out[i, 6] = acc[9]


@njit(cache=True)
def _slip_two(p, amp, y0, t0, h, n_burn, n_run, states, lam, min_gap, v_stage, out, ia, ib):
    """Rows ``ia`` and ``ib`` of :func:`slip_stats`, the two trajectories in one loop (see
    :func:`_advance2`), each exactly as it runs alone (``ib == ia``: trajectory ``ia``
    beside its twin); False (nothing written) when a state turns non-finite: the caller
    then runs each beside its twin."""
    sa = states[ia].copy()
    sb = states[ib].copy()
    xa, va, xb, vb = _advance2(  # noqa: F821
        p, y0[ia, 0], y0[ia, 1], sa, y0[ib, 0], y0[ib, 1], sb, t0, h, n_burn, amp)
    if not (math.isfinite(xa) and math.isfinite(xb)):
        return False
    t1 = t0 + n_burn * h
    fa = _first(t1, xa, va, p)  # noqa: F821
    fb = _first(t1, xb, vb, p)  # noqa: F821
    acc_a = _slip_init(xa, lam)
    acc_b = _slip_init(xb, lam)
    for k in range(n_run):
        t = t1 + (k + 1) * h
        xa, va, fa = _step(t - h, xa, va, fa, h, _increment(sa, amp), p)  # noqa: F821
        xb, vb, fb = _step(t - h, xb, vb, fb, h, _increment(sb, amp), p)  # noqa: F821
        if not (math.isfinite(xa + va) and math.isfinite(xb + vb)):
            return False
        _slip_record(acc_a, t, xa, va, p, lam, min_gap, v_stage)
        _slip_record(acc_b, t, xb, vb, p, lam, min_gap, v_stage)
    _slip_row(out, ia, acc_a, n_run)
    _slip_row(out, ib, acc_b, n_run)
    return True


@njit(cache=True)
def slip_stats(p, sigma, y0, t0, h, n_burn, n_run, states, lam, min_gap, v_stage):
    """Per trajectory of a pulled slider, over ``n_run`` steps after ``n_burn``: the mean
    spring force; the slips (a forward crossing of a barrier top ``x = (n + 1/2) lam``
    more than ``min_gap`` after the previous crossing: a new stick-slip event, not the
    next well of the same slip) with the sum and the sum of squares of the largest spring
    force since the previous slip (the slip force) and of the stage position at the slip
    relative to the well left, ``v t - n lam``; the backward jumps (a backward crossing more
    than ``min_gap`` after the previous crossing: not the ringing of a slip).  Columns:
    ``mean force, slips, sum F_slip, sum F_slip^2, backward, sum L_slip, sum L_slip^2``; NaN
    rows for a diverged trajectory.  Trajectories run two to a loop (:func:`_slip_two`), the
    last of an odd number and each of a pair with a diverged one beside its twin: the same
    numbers either way."""
    m = y0.shape[0]
    out = np.zeros((m, 7))
    amp = sigma * _noise_factor(p, h) * math.sqrt(3.0 * h)  # noqa: F821
    for i in range(0, m, 2):
        j = min(i + 1, m - 1)
        if _slip_two(p, amp, y0, t0, h, n_burn, n_run, states, lam, min_gap, v_stage, out, i,
                     j):
            continue
        for r in range(i, j + 1):
            if j == i or not _slip_two(p, amp, y0, t0, h, n_burn, n_run, states, lam, min_gap,
                                       v_stage, out, r, r):
                out[r, :] = math.nan
    return out
