"""Compiled first-passage and pulled-slider kernels of :mod:`numerics.noise`, appended as
source after :mod:`numerics.noise._kernels` (whose ``_first`` and ``_noise_factor`` they
call, and whose ``_step`` and ``_increment`` their loops call) to a printed model.

``first_passages`` gives the escape times of :mod:`numerics.escape` and ``slip_stats`` the
friction runs of :mod:`numerics.thermal.friction`; both run trajectories ``EVENT_LANES``
to a loop (independent chains of dependent operations fill the core; the loops are printed
for the model by :mod:`numerics.noise.lanes`, the numbers are those of one trajectory at a
time) with three-point increments (why not four-point ones: ``docs/noise.rst``, measured
by ``benchmarks/bench_noise.py`` part 3).
"""

import math

import numpy as np
from numba import njit


@njit(cache=True)
def _passage_take(p, y0, t0, states, r):
    """A lane of :func:`first_passages` at trajectory ``r``'s start: ``(r, generator, x, v,
    carried force)``; ``r >= m``: no trajectory left, ``(-1, ...)`` at the last one's start
    (a lane that runs on, unread)."""
    m = y0.shape[0]
    live = r < m
    r = min(r, m - 1)
    x, v = y0[r, 0], y0[r, 1]
    return (r if live else -1), states[r].copy(), x, v, _first(t0, x, v, p)  # noqa: F821


@njit(cache=True)
def _passage_end(r, k, x, h, n_max, xl, xr, times, hit):
    """Whether trajectory ``r`` (``-1``: none) has ended after ``k`` steps at ``x``: left
    (``x <= xl`` or ``x >= xr`` or non-finite; its time ``k h``) or censored (``k = n_max``,
    time ``n_max h``); written to ``times``, ``hit``."""
    if r < 0:
        return False
    if x <= xl or x >= xr or not math.isfinite(x):
        times[r], hit[r] = k * h, True
        return True
    if k >= n_max:
        times[r], hit[r] = n_max * h, False
        return True
    return False


@njit(cache=True)
def first_passages(p, sigma, y0, t0, h, n_max, xl, xr, states):
    """Per trajectory: the first time ``x <= xl`` or ``x >= xr`` (the step's end; ``n_max h``
    when it never happens) and whether it happened.  Trajectories run ``EVENT_LANES`` to a
    loop (``_passages_lanes``, printed for the model by
    :func:`numerics.noise.lanes.lanes_source`), a lane taking the next trajectory when its
    own ends: the same numbers as one at a time."""
    m = y0.shape[0]
    times = np.full(m, n_max * h)
    hit = np.zeros(m, dtype=np.bool_)
    amp = sigma * _noise_factor(p, h) * math.sqrt(3.0 * h)  # noqa: F821
    if m > 0 and n_max > 0:
        _passages_lanes(p, y0, t0, h, n_max, xl, xr, states, amp, times, hit)  # noqa: F821
    return times, hit


@njit(cache=True)
def _slip_init(x, lam):
    """The running record of :func:`slip_stats` for one trajectory at ``x``, a tuple (a
    lane's record stays in registers): the well (``floor(x/lam + 1/2)``, a float: the same
    number as the integer for ``|x| < 2^63 lam``), the time of the last crossing, the
    largest spring force since, then the sums (force, slips, slip force and its square,
    backward jumps, stage position at the slip and its square)."""
    return (np.floor(x / lam + 0.5), -1e300, -1e300, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


@njit(cache=True)
def _slip_record(acc, t, x, v, p, lam, min_gap, v_stage):
    """The record ``acc`` (:func:`_slip_init`) with one step's end ``(t, x, v)`` (garbage,
    never NaN-trapping, when ``x`` is not finite: the caller then drops the record)."""
    well, last, top, force, slips, fs, fs2, back, ls, ls2 = acc
    f = spring(t, x, v, p)  # noqa: F821
    force += f
    if f > top:
        top = f
    w = np.floor(x / lam + 0.5)  # a float: no integer of a non-finite x
    if w > well:
        if t - last > min_gap:
            slips += 1.0
            fs += top
            fs2 += top * top
            rel = v_stage * t - well * lam
            ls += rel
            ls2 += rel * rel
        last = t
        top = f
    elif w < well:
        if t - last > min_gap:
            back += 1.0
        last = t
        top = f
    return w, last, top, force, slips, fs, fs2, back, ls, ls2


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
def slip_stats(p, sigma, y0, t0, h, n_burn, n_run, states, lam, min_gap, v_stage):
    """Per trajectory of a pulled slider, over ``n_run`` steps after ``n_burn``: the mean
    spring force; the slips (a forward crossing of a barrier top ``x = (n + 1/2) lam``
    more than ``min_gap`` after the previous crossing: a new stick-slip event, not the
    next well of the same slip) with the sum and the sum of squares of the largest spring
    force since the previous slip (the slip force) and of the stage position at the slip
    relative to the well left, ``v t - n lam``; the backward jumps (a backward crossing more
    than ``min_gap`` after the previous crossing: not the ringing of a slip).  Columns:
    ``mean force, slips, sum F_slip, sum F_slip^2, backward, sum L_slip, sum L_slip^2``; NaN
    rows for a trajectory whose ``x + x'`` is not finite at the end of the burn-in or at
    any step of the run.  Trajectories run ``EVENT_LANES`` to a loop (``_slips_lanes``,
    printed for the model by :func:`numerics.noise.lanes.lanes_source`; the last loop of a
    block repeats its last trajectory; when a state turns non-finite, each trajectory of
    the loop alone, in every lane): the same numbers as one at a time."""
    m = y0.shape[0]
    out = np.zeros((m, 7))
    amp = sigma * _noise_factor(p, h) * math.sqrt(3.0 * h)  # noqa: F821
    for i in range(0, m, EVENT_LANES):  # noqa: F821 - set by the printed model above
        last = min(i + EVENT_LANES, m) - 1  # noqa: F821
        if _slips_lanes(p, amp, y0, t0, h, n_burn, n_run, states, lam, min_gap,  # noqa: F821
                        v_stage, out, i, last):
            continue
        for r in range(i, last + 1):  # a state turned non-finite: each alone
            if not _slips_lanes(p, amp, y0, t0, h, n_burn, n_run, states, lam,  # noqa: F821
                                min_gap, v_stage, out, r, r):
                out[r, :] = math.nan
    return out
