"""The lanes of the event kernels (issue 36): ``first_passages`` (escape times) and
``slip_stats`` (a pulled slider's records) run ``EVENT_LANES`` trajectories to a loop
(:mod:`numerics.noise.lanes`), a passage lane taking the next trajectory when its own
leaves.  The reference is the scheme stepped in Python, one trajectory at a time, with the
compiled one-step map (``_first``, ``_step``) and the generator's three-point increments
(``_increment``; Kloeden & Platen eq. 14.2.8) from a copy of the trajectory's stream, and
the events written out from their definitions: the first step's end with ``x <= x_l``, ``x
>= x_r`` or ``x`` non-finite (``n_max h`` and no hit when none), and the slips and backward
jumps as runs of crossings of the barrier tops ``x = (n + 1/2) lam`` (each less than
``min_gap`` after the previous one) that end ahead of or behind the well they left.  The kernels must give the same bytes.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from kbm.model.builtins import custom_model
from numerics.noise import langevin_system
from numerics.noise.seeds import trajectory_states

#: a double well ``x'' = -x'/2 + x - x^3`` (``x'' = -x + mu F``, mu = 1): no library call
#: a step (three event lanes); driven by ``cos(t)/4``: one call (two), and the time of each
#: step matters
WELLS = custom_model("-xdot/2 + 2*x - x**3", name="double_well")
DRIVEN = custom_model("-xdot/2 + 2*x - x**3 + cos(t)/4", name="driven_double_well")
CDC = {"mu": 0.5, "Delta": 3, "lam": 1, "Omega": 1}


def _same(a, b) -> bool:
    return np.asarray(a, float).tobytes() == np.asarray(b, float).tobytes()


def _amp(s, h: float) -> float:
    return s.sigma * s.kernels._noise_factor(s._p(), h) * math.sqrt(3.0 * h)


def _path(s, x: float, v: float, gen, h: float, t_first: float, time):
    """The trajectory from ``(x, v)`` stepped in Python with the compiled one-step map
    (carried force ``_first`` at ``t_first``, step ``j`` at ``time(j)``, its increments
    drawn from the generator ``gen``, updated): ``(x, v)`` after each step."""
    k, p = s.kernels, s._p()
    amp = _amp(s, h)
    f = k._first(t_first, x, v, p)
    for j in itertools.count():
        x, v, f = k._step(time(j), x, v, f, h, k._increment(gen, amp), p)
        yield x, v


def _passage_in_python(s, y0, state, h: float, n_max: int, xl: float, xr: float):
    """One trajectory stepped in Python until it leaves ``(xl, xr)``: ``(time, hit)``."""
    path = _path(s, *y0, state.copy(), h, 0.0, lambda j: j * h)
    for j, (x, _) in zip(range(n_max), path):
        if x <= xl or x >= xr or not math.isfinite(x):
            return (j + 1) * h, True
    return n_max * h, False


@pytest.mark.parametrize("model, scheme, lanes", [
    (WELLS, "kp", 3), (WELLS, "baoab", 3), (DRIVEN, "kp", 2), (DRIVEN, "baoab", 2),
    ("cdc", "kp", 2), ("cdc", "baoab", 2)])
def test_first_passages_in_lanes_equal_the_scheme_stepped_in_python(model, scheme, lanes):
    """first_passages on ``3 lanes + 2`` trajectories (a start at NaN and one beyond the
    right line, the rest at a well's bottom; escapes early and late and censored ones, so
    that lanes take new trajectories at different steps and run on empty at the end)
    against each trajectory stepped in Python: the same times and flags.  The double wells
    from the left bottom ``x = -1`` to the barrier top ``x = 0`` (or ``x = -2.5``), the CDC
    (paper eq. 12) from ``x = 0`` to ``|x| = 0.45``."""
    wells = model != "cdc"
    D = {WELLS: 0.1, DRIVEN: 0.05}.get(model, 0.2)
    s = langevin_system(model, {"mu": 1.0} if wells else CDC, D, scheme)
    k, p = s.kernels, s._p()
    assert k.EVENT_LANES == lanes
    m, h, n_max = 3 * lanes + 2, 0.05, 500
    xl, xr = (-2.5, 0.0) if wells else (-0.45, 0.45)
    y0 = np.zeros((m, 2))
    y0[:, 0] = -1.0 if wells else 0.0
    y0[1], y0[lanes + 1] = [np.nan, 0.0], [xr + 0.15, 0.0]
    st = trajectory_states(5, 0, m)
    times, hit = k.first_passages(p, s.sigma, y0, 0.0, h, n_max, xl, xr, st)
    want = [_passage_in_python(s, y0[i], st[i], h, n_max, xl, xr) for i in range(m)]
    assert _same(times, [w[0] for w in want]) and list(hit) == [w[1] for w in want]
    assert hit[1] and times[1] == h and hit[lanes + 1] and times[lanes + 1] == h
    assert 5 <= hit.sum() < m and len(set(times[hit])) >= 4  # several passage steps


def _slips_in_python(s, y0, state, h, n_burn, n_run, lam, min_gap, v_stage) -> list:
    """One slider trajectory stepped in Python: burn-in, then the records of
    :func:`slip_stats` from their definitions (NaN row when ``x + x'`` is not finite)."""
    gen, (x, v) = state.copy(), y0
    for _, (x, v) in zip(range(n_burn), _path(s, x, v, gen, h, 0.0, lambda j: j * h)):
        pass
    if not math.isfinite(x + v):
        return [math.nan] * 7
    t1 = n_burn * h
    well, last, top = float(math.floor(x / lam + 0.5)), -1e300, -1e300
    force = 0.0
    runs = []  # (well left, force before, v t - n lam at the start, well reached)
    run = _path(s, x, v, gen, h, t1, lambda j: (t1 + (j + 1) * h) - h)
    for j, (x, v) in zip(range(n_run), run):
        t = t1 + (j + 1) * h
        if not math.isfinite(x + v):
            return [math.nan] * 7
        spring = s.kernels.spring(t, x, v, s._p())
        force += spring
        top = max(top, spring)
        w = math.floor(x / lam + 0.5)
        if w != well:
            if t - last > min_gap:  # a stay of min_gap in `well`: it ends the open run
                if runs:
                    runs[-1][3] = well
                runs.append([well, top, v_stage * t - well * lam, None])
            last, top = t, spring
        well = float(w)
    if runs:
        runs[-1][3] = well
    # a run ending ahead of the well it left is a slip, behind a backward jump, else neither
    ahead = [(f0, rel) for left, f0, rel, end in runs if end > left]
    slips, back = float(len(ahead)), float(sum(end < left for left, _, _, end in runs))
    fs = fs2 = ls = ls2 = 0.0
    for f0, rel in ahead:  # summed in time order, as the kernel does
        fs, fs2, ls, ls2 = fs + f0, fs2 + f0 * f0, ls + rel, ls2 + rel * rel
    return [force / n_run, slips, fs, fs2, back, ls, ls2]


@pytest.mark.parametrize("model, scheme, lanes", [
    (WELLS, "kp", 3), (WELLS, "baoab", 3), ("cdc", "kp", 2), ("cdc", "baoab", 2)])
def test_slip_records_in_lanes_equal_the_scheme_stepped_in_python(model, scheme, lanes):
    """slip_stats on ``2 lanes + 1`` trajectories (two loops and a remainder that repeats
    its last trajectory; one trajectory of the second loop diverging, so that loop's
    trajectories run again each alone) against each trajectory stepped in Python with the
    records written out from their definitions: the same bytes, events in every row."""
    params = {"mu": 1.0} if model is WELLS else dict(CDC, v=0.5)
    s = langevin_system(model, params, 0.1 if model is WELLS else 0.05, scheme)
    k, p = s.kernels, s._p()
    assert k.EVENT_LANES == lanes
    m, h = 2 * lanes + 1, 0.02
    y0 = np.zeros((m, 2))
    y0[lanes + 1] = [1e200, 0.0] if model is WELLS else [np.nan, 0.0]
    lam, gap, v_stage = (1.0, 0.5, 0.0) if model is WELLS else (1.0, 2 * math.pi, 0.5)
    st = trajectory_states(9, 0, m)
    rows = k.slip_stats(p, s.sigma, y0, 0.0, h, 100, 1500, st, lam, gap, v_stage)
    for i in range(m):
        want = _slips_in_python(s, y0[i], st[i], h, 100, 1500, lam, gap, v_stage)
        assert _same(rows[i], want), i
    assert np.isnan(rows[lanes + 1]).all()
    kept = np.delete(rows, lanes + 1, 0)
    assert (kept[:, 1] + kept[:, 4] > 0).all() and kept[:, 1].sum() > 0
