"""Compiled ensemble kernels of :mod:`numerics.noise`: every kernel that runs independent
trajectories of the scheme, one loop body for all of them, appended as source after
:mod:`numerics.noise._kernels` and :mod:`numerics.noise._pair_kernels` (whose ``_step``,
``_first``, increments and ``_noise_factor`` it calls) to a printed model.

Two lanes
---------
A step's force is a chain of dependent operations (the new ``x`` waits for the kick, the
next kick for the force at the new ``x``: a libm call), so one trajectory leaves most of the
core idle; two independent chains in one loop fill it (1.5-1.7x the steps per second of one
trajectory a loop, ``benchmarks/bench_noise.py`` part 1).  :func:`_lanes` runs two
trajectories side by side; a lane whose trajectory ends (its steps done, a first passage, a
non-finite state) takes the next one, and idles when none is left.  Each trajectory keeps
its own generator, step count and times, so its numbers are those of it run alone, however
the trajectories are grouped (``tests/test_noise_kernels.py``).

The kernels (``task``)
----------------------
- ``final_states`` (``FINAL``): the states after ``n`` steps, three-point increments;
- ``sample_path`` (``PATH``): one trajectory's states every ``stride`` steps;
- ``stationary_stats`` (``STATS3``, three-point increments) and ``stationary_stats4``
  (``STATS4``, four-point ones): time averages and a histogram after a burn-in;
- ``step_gauss_stats`` (``GAUSS``): time averages with Gaussian increments (the
  two-level estimator's level 0, :mod:`numerics.noise.extrapolate`);
- ``first_passages`` (``PASSAGE``): escape times (:mod:`numerics.escape`);
- ``slip_stats`` (``SLIP``): a pulled slider's slips (:mod:`numerics.thermal.friction`).

First passages and friction runs take three-point increments (why not four-point ones:
``docs/noise.rst``, measured by ``benchmarks/bench_noise.py`` part 3).
"""

import math

import numpy as np
from numba import njit

FINAL, PATH, STATS3, STATS4, GAUSS, PASSAGE, SLIP = 0, 1, 2, 3, 4, 5, 6


@njit(cache=True)
def _draw(task, s, amp, k, spare):
    """Step ``k``'s noise increment and the normal number carried to the next step
    (``GAUSS``: one normal pair per two steps)."""
    if task == STATS4:
        return _increment4(s, amp), spare  # noqa: F821 - defined in _pair_kernels above
    if task == GAUSS:
        if k % 2 == 0:
            g1, g2 = _normal_pair(s)  # noqa: F821
            return amp * g1, g2
        return amp * spare, spare
    return _increment(s, amp), spare  # noqa: F821 - defined in _kernels above


@njit(cache=True)
def _observe(kind, x, v, w0, p):
    if kind == 0:
        return math.sqrt(x * x + (v / w0) ** 2)
    if kind == 1:
        return x
    return energy(x, v, p)  # noqa: F821


@njit(cache=True)
def _slip_record(acc, t, x, v, p, lam, min_gap, v_stage):
    """One step's end ``(t, x, v)`` into the slider record ``acc``: the well, the time of the
    last crossing, the largest spring force since, then the sums (force, slips, slip force
    and its square, backward jumps, stage position at the slip and its square)."""
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
def _record(task, p, k, t, x, v, q, acc, i, out, hist):
    """What a step's end ``(t, x, v)`` adds to trajectory ``i``'s record ``acc`` (``k``
    steps done)."""
    if task == PATH:
        if k % int(q[0]) == 0:
            out[k // int(q[0]), 0], out[k // int(q[0]), 1] = x, v
    elif task == SLIP:
        _slip_record(acc, t, x, v, p, q[0], q[1], q[2])
    elif task == STATS3 or task == STATS4 or task == GAUSS:
        acc[0] += x * x
        acc[1] += x * x + (v / q[0]) ** 2
        if task != GAUSS:
            acc[2] += v * v
            acc[3] += spring(t, x, v, p)  # noqa: F821
            j = int(math.floor((_observe(int(q[3]), x, v, q[0], p) - q[1]) / q[2]))
            if 0 <= j < hist.shape[1]:
                hist[i, j] += 1.0


@njit(cache=True)
def _finish(task, i, x, v, n_run, acc, out, hist):
    """Trajectory ``i``'s row of ``out`` (and ``hist``) from its end ``(x, v)`` and its record
    ``acc`` (NaN when the state is non-finite)."""
    ok = math.isfinite(x + v)
    if task == FINAL:
        out[i, 0], out[i, 1] = (x, v) if ok else (math.nan, math.nan)
    elif task == SLIP:
        out[i, 0] = acc[3] / n_run if ok else math.nan
        for c in range(1, 7):
            out[i, c] = acc[c + 3] if ok else math.nan
    elif task == STATS3 or task == STATS4 or task == GAUSS:
        for c in range(out.shape[1]):
            out[i, c] = acc[c] / n_run if ok else math.nan
        for j in range(hist.shape[1]):
            hist[i, j] = hist[i, j] / n_run if ok else math.nan


@njit(cache=True)
def _start(p, y0, t0, states, s, acc, i):
    """A lane (generator ``s``, record ``acc``) at the start of trajectory ``i``: ``(i, k, x,
    v, f, spare)``; idle (``i = -1``) past the last trajectory."""
    if i >= y0.shape[0]:
        return np.int64(-1), np.int64(0), 0.0, 0.0, 0.0, 0.0
    for c in range(4):
        s[c] = states[i, c]
    for c in range(acc.shape[0]):
        acc[c] = 0.0
    x, v = y0[i, 0], y0[i, 1]
    return i, np.int64(0), x, v, _first(t0, x, v, p), 0.0  # noqa: F821


@njit(cache=True)
def _advance(task, p, amp, t0, h, n_burn, n_run, q, lane, s, acc, out, hist):
    """One step of a lane: ``(lane, done)``, ``done`` once its trajectory has ended (its row
    written).  The times are those of the kernels run one trajectory at a time: steps at
    ``t0 + k h``, the stationary three-point runs' and the slider's run phase from ``t1 =
    t0 + n_burn h`` with the carried force evaluated there again."""
    i, k, x, v, f, spare = lane
    if k == n_burn + n_run:
        if task == PASSAGE:
            out[i, 0], out[i, 1] = n_run * h, 0.0
        else:
            _finish(task, i, x, v, n_run, acc, out, hist)
        return lane, True
    t1 = t0 + n_burn * h
    if k < n_burn or not (task == STATS3 or task == SLIP):
        ts, tr = t0 + k * h, t0 + (k + 1) * h
    else:
        j = k - n_burn
        tr = t1 + (j + 1) * h
        ts = t1 + j * h if task == STATS3 else tr - h
        if j == 0:
            f = _first(t1, x, v, p)  # noqa: F821
            if task == SLIP:
                acc[0] = math.floor(x / q[0] + 0.5)
                acc[1] = -1e300
                acc[2] = -1e300
    dw, spare = _draw(task, s, amp, k, spare)
    x, v, f = _step(ts, x, v, f, h, dw, p)  # noqa: F821
    k += 1
    lane = (i, k, x, v, f, spare)
    if task == PASSAGE:
        if x <= q[0] or x >= q[1] or not math.isfinite(x):
            out[i, 0], out[i, 1] = k * h, 1.0
            return lane, True
    elif task != FINAL and not math.isfinite(x + v):
        _finish(task, i, x, v, n_run, acc, out, hist)
        return lane, True
    elif k > n_burn:
        _record(task, p, k, tr, x, v, q, acc, i, out, hist)
    return lane, False


@njit(cache=True)
def _lanes(task, p, amp, y0, t0, h, n_burn, n_run, states, q, out, hist):
    """The rows of ``out`` (and ``hist``) for the trajectories from ``y0[i]`` on the
    generators ``states[i]``, two lanes at a time: ``n_burn`` steps, then ``n_run`` steps
    recorded.  ``task`` is a constant at every call site, and numba compiles a function for
    each literal value it is called with, so each kernel's loop holds its own branches
    only."""
    sa, sb = np.empty(4, np.uint64), np.empty(4, np.uint64)
    acc_a, acc_b = np.zeros(10), np.zeros(10)
    nxt = np.int64(0)
    a = _start(p, y0, t0, states, sa, acc_a, nxt)
    b = _start(p, y0, t0, states, sb, acc_b, nxt + 1)
    nxt += 2
    while a[0] >= 0 or b[0] >= 0:
        if a[0] >= 0:
            a, done = _advance(task, p, amp, t0, h, n_burn, n_run, q, a, sa, acc_a, out, hist)
            if done:
                a = _start(p, y0, t0, states, sa, acc_a, nxt)
                nxt += 1
        if b[0] >= 0:
            b, done = _advance(task, p, amp, t0, h, n_burn, n_run, q, b, sb, acc_b, out, hist)
            if done:
                b = _start(p, y0, t0, states, sb, acc_b, nxt)
                nxt += 1


@njit(cache=True)
def final_states(p, sigma, y0, t0, h, n, states):
    """The states after ``n`` steps from ``y0[i]`` on the generators ``states[i]`` (``NaN``
    once a state is non-finite; the loop holds no test for it: NaN propagates through every
    step)."""
    out = np.empty((y0.shape[0], 2))
    amp = sigma * _noise_factor(p, h) * math.sqrt(3.0 * h)  # noqa: F821
    _lanes(FINAL, p, amp, y0, t0, h, n, 0, states, (0.0, 0.0, 0.0, 0.0), out, out[:, :0])
    return out


@njit(cache=True)
def sample_path(p, sigma, y0, t0, h, n, stride, state):
    """One trajectory's states every ``stride`` steps (``n // stride + 1`` rows; NaN rows
    after a state turns non-finite)."""
    out = np.full((n // stride + 1, 2), np.nan)
    out[0, 0], out[0, 1] = y0[0], y0[1]
    amp = sigma * _noise_factor(p, h) * math.sqrt(3.0 * h)  # noqa: F821
    _lanes(PATH, p, amp, np.ascontiguousarray(y0).reshape((1, 2)), t0, h, 0, n,
           np.ascontiguousarray(state).reshape((1, 4)),
           (float(stride), 0.0, 0.0, 0.0), out, out[:, :0])
    return out


@njit(cache=True)
def _stats(task, p, amp, y0, t0, h, n_burn, n_run, states, w0, kind, lo, hi, nbins):
    sums = np.zeros((y0.shape[0], 4))
    hist = np.zeros((y0.shape[0], nbins))
    _lanes(task, p, amp, y0, t0, h, n_burn, n_run, states,
           (w0, lo, (hi - lo) / nbins, float(kind)), sums, hist)
    return sums, hist


@njit(cache=True)
def stationary_stats(p, sigma, y0, t0, h, n_burn, n_run, states, w0, kind, lo, hi, nbins):
    """Per trajectory: the time averages of ``x^2``, ``a^2 = x^2 + (x'/w0)^2``, ``x'^2`` and
    the spring force over ``n_run`` steps after ``n_burn``, and the fraction of those
    steps the observable ``kind`` (0: ``a``, 1: ``x``, 2: the energy) spent in each of
    ``nbins`` equal bins of ``[lo, hi)``; three-point increments.  A diverged trajectory
    gives NaN rows."""
    amp = sigma * _noise_factor(p, h) * math.sqrt(3.0 * h)  # noqa: F821
    return _stats(STATS3, p, amp, y0, t0, h, n_burn, n_run, states, w0, kind, lo, hi, nbins)


@njit(cache=True)
def stationary_stats4(p, sigma, y0, t0, h, n_burn, n_run, states, w0, kind, lo, hi, nbins):
    """:func:`stationary_stats` with the four-point increments (``_increment4``): the
    stationary ensembles' kernel, whose ``h^2`` coefficient is the Gaussian pair's that the
    step pilot (``step_pair_stats``) measures."""
    amp = sigma * math.sqrt(h) * _noise_factor(p, h)  # noqa: F821
    return _stats(STATS4, p, amp, y0, t0, h, n_burn, n_run, states, w0, kind, lo, hi, nbins)


@njit(cache=True)
def step_gauss_stats(p, sigma, y0, t0, h, n_burn, n_run, states, w0):
    """Per trajectory: the time averages of ``x^2`` and ``a^2`` over ``n_run`` steps ``h``
    after ``n_burn``, with Gaussian increments (one normal pair per two steps): the level
    0 of the two-level estimator, whose expansion in ``h`` is the pair's (the three-point
    increments of ``stationary_stats`` have another ``h^2`` coefficient).  Columns ``x^2,
    a^2``; NaN rows for a diverged trajectory."""
    out = np.zeros((y0.shape[0], 2))
    amp = sigma * math.sqrt(h) * _noise_factor(p, h)  # noqa: F821
    _lanes(GAUSS, p, amp, y0, t0, h, n_burn, n_run, states, (w0, 0.0, 0.0, 0.0), out,
           out[:, :0])
    return out


@njit(cache=True)
def first_passages(p, sigma, y0, t0, h, n_max, xl, xr, states):
    """Per trajectory: the first time ``x <= xl`` or ``x >= xr`` (the step's end; ``n_max h``
    when it never happens) and whether it happened."""
    out = np.empty((y0.shape[0], 2))
    amp = sigma * _noise_factor(p, h) * math.sqrt(3.0 * h)  # noqa: F821
    _lanes(PASSAGE, p, amp, y0, t0, h, 0, n_max, states, (xl, xr, 0.0, 0.0), out, out[:, :0])
    return out[:, 0].copy(), out[:, 1] != 0.0


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
    rows for a diverged trajectory."""
    out = np.zeros((y0.shape[0], 7))
    amp = sigma * _noise_factor(p, h) * math.sqrt(3.0 * h)  # noqa: F821
    _lanes(SLIP, p, amp, y0, t0, h, n_burn, n_run, states, (lam, min_gap, v_stage, 0.0), out,
           out[:, :0])
    return out
