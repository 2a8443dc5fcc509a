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
    largest spring force since; the open run of crossings (:func:`_slip_record`): the well
    it left (NaN: none open), the largest spring force before it and the stage position at
    its start relative to that well; then the sums (force, slips, slip force and its square,
    backward jumps, stage position at the slip and its square)."""
    return (np.floor(x / lam + 0.5), -1e300, -1e300, math.nan, 0.0, 0.0,
            0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


@njit(cache=True)
def _slip_close(acc):
    """The record with its open run of crossings closed in the well it has reached: a slip
    (the force and the stage position at the run's start) when that well lies ahead of the
    one the run left, a backward jump when behind, nothing when it is the same well (an
    oscillation in the well or a recrossing of the barrier top: no well crossed)."""
    well, last, top, start, f0, rel, force, slips, fs, fs2, back, ls, ls2 = acc
    if well > start:  # False for start = NaN (no run open)
        slips += 1.0
        fs += f0
        fs2 += f0 * f0
        ls += rel
        ls2 += rel * rel
    elif well < start:
        back += 1.0
    return (well, last, top, math.nan, f0, rel, force, slips, fs, fs2, back, ls, ls2)


@njit(cache=True)
def _slip_record(acc, t, x, v, p, lam, min_gap, v_stage):
    """The record ``acc`` (:func:`_slip_init`) with one step's end ``(t, x, v)`` (garbage,
    never NaN-trapping, when ``x`` is not finite: the caller then drops the record).

    Crossings of barrier tops ``x = (n + 1/2) lam`` less than ``min_gap`` apart form one
    run (a slip over several wells, its ringing, an oscillation across a barrier top); a
    crossing more than ``min_gap`` after the previous one closes the open run in the well
    the slider has stayed in since (:func:`_slip_close`) and opens the next, which keeps the
    well left, the largest spring force since the previous crossing and ``v t - n lam``."""
    well, last, top, start, f0, rel, force, slips, fs, fs2, back, ls, ls2 = acc
    f = spring(t, x, v, p)  # noqa: F821
    force += f
    if f > top:
        top = f
    w = np.floor(x / lam + 0.5)  # a float: no integer of a non-finite x
    if w != well:
        if t - last > min_gap:
            (well, last, top, start, f0, rel, force, slips, fs, fs2, back, ls,
             ls2) = _slip_close((well, last, top, start, f0, rel, force, slips, fs, fs2,
                                 back, ls, ls2))
            start, f0, rel = well, top, v_stage * t - well * lam
        last = t
        top = f
    return w, last, top, start, f0, rel, force, slips, fs, fs2, back, ls, ls2


@njit(cache=True)
def _slip_row(out, i, acc, n_run):
    """Row ``i`` of :func:`slip_stats` from the record, its open run closed in the well
    reached at the end (:func:`_slip_close`)."""
    acc = _slip_close(acc)
    out[i, 0] = acc[6] / n_run
    out[i, 1] = acc[7]
    out[i, 2] = acc[8]
    out[i, 3] = acc[9]
    out[i, 4] = acc[10]
    out[i, 5] = acc[11]
    out[i, 6] = acc[12]


@njit(cache=True)
def slip_stats(p, sigma, y0, t0, h, n_burn, n_run, states, lam, min_gap, v_stage):
    """Per trajectory of a pulled slider, over ``n_run`` steps after ``n_burn``: the mean
    spring force; the slips (a run of barrier-top crossings ``x = (n + 1/2) lam``, each
    less than ``min_gap`` after the previous one, that starts more than ``min_gap`` after
    the previous crossing and ends in a well ahead of the one it left: a stick-slip event,
    its wells and its ringing together) with the sum and the sum of squares of the largest
    spring force before the run (the slip force) and of the stage position at its start
    relative to the well left, ``v t - n lam``; the backward jumps (such a run that ends in
    a well behind the one it left).  A run that ends in the well it left (an oscillation
    in the well, a recrossing of the barrier top) is neither.  Columns:
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
