"""The compiled Langevin kernels compute each trajectory alone, however they are grouped.

Issue 36: the kernels (stationary runs, final states, first passages, pulled sliders) run
trajectories two or more to a loop (independent chains of dependent operations keep the
core busy; :mod:`numerics.noise.lanes`), and the synchronous pair and the antithetic triple of the two-level estimator share
one loop with the coupling chosen at compile time.  Neither may change a number.  Independent references:

- a trajectory run alone (the kernel called with one row: the trajectory beside its twin, or
  a first passage's single-trajectory path) gives the same bytes as the same trajectory run
  beside another, also when its partner diverges;
- the couplings written out in Python step by step from the scheme's one-step map
  (``_step``) and the generator's normal pairs (``_normal_pair``): the coarse step takes
  ``g_1 + g_2``, the fine run ``g_1`` then ``g_2``, the antithetic twin ``g_2`` then ``g_1``
  (Giles & Szpruch, Ann. Appl. Probab. 24 (2014) 1585).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from kbm.model.builtins import custom_model
from numerics.noise import langevin_system
from numerics.noise.seeds import trajectory_states

QUARTIC = custom_model("-xdot - x**3", name="quartic")


def _system(scheme: str):
    return langevin_system(QUARTIC, {"mu": 1.0}, 1.0, scheme)


def _same(a, b) -> bool:
    return np.asarray(a).tobytes() == np.asarray(b).tobytes()


@pytest.mark.parametrize("scheme", ["baoab", "kp"])
def test_trajectories_in_pairs_equal_trajectories_alone(scheme):
    """final_states and stationary_stats4 on five trajectories (two pairs and one alone)
    against each trajectory run alone: the same bytes; a pair whose second trajectory
    diverges (started at 1e200 with a cubic force) gives the first one's numbers and a NaN
    row."""
    s = _system(scheme)
    k, p = s.kernels, s._p()
    m, h = 5, 0.05
    y0 = np.linspace(-1.0, 1.2, 2 * m).reshape(m, 2)
    y0[3] = [1e200, 0.0]
    st = trajectory_states(11, 0, m)
    together = k.final_states(p, s.sigma, y0, 0.0, h, 400, st)
    sums, hist = k.stationary_stats4(p, s.sigma, y0, 0.0, h, 30, 400, st, s.omega0, 1, -2.0,
                                     2.0, 9)
    assert np.isnan(together[3]).all() and np.isnan(sums[3]).all() and np.isnan(hist[3]).all()
    assert np.isfinite(sums[[0, 1, 2, 4]]).all()
    for i in range(m):
        alone = k.final_states(p, s.sigma, y0[i:i + 1], 0.0, h, 400, st[i:i + 1])
        assert _same(alone[0], together[i])
        s1, h1 = k.stationary_stats4(p, s.sigma, y0[i:i + 1], 0.0, h, 30, 400, st[i:i + 1],
                                     s.omega0, 1, -2.0, 2.0, 9)
        assert _same(s1[0], sums[i]) and _same(h1[0], hist[i])
    assert hist[0].sum() == pytest.approx(1.0, abs=0.2)  # most steps inside [-2, 2)


def _stepped_in_python(s, y0, st, h: float, n: int) -> list:
    """Each trajectory of ``y0`` stepped ``n`` times in Python with the compiled one-step map
    (``_first``, ``_step``) and the generator's three-point increments (``_increment``) from
    a copy of its stream in ``st``: the final ``[x, v]`` of each."""
    k, p = s.kernels, s._p()
    amp = s.sigma * k._noise_factor(p, h) * math.sqrt(3.0 * h)
    out = []
    for i in range(len(y0)):
        gen = st[i].copy()
        x, v = y0[i]
        f = k._first(0.0, x, v, p)
        for j in range(n):
            x, v, f = k._step(j * h, x, v, f, h, k._increment(gen, amp), p)
        out.append([x, v])
    return out


@pytest.mark.parametrize("scheme", ["baoab", "kp"])
def test_final_states_equal_the_scheme_stepped_in_python(scheme):
    """final_states on three trajectories (a pair, and the last beside its twin) against each
    trajectory stepped in Python with the compiled one-step map (``_first``, ``_step``) and
    the generator's three-point increments (``_increment``, Kloeden & Platen eq. 14.2.8):
    the same bytes."""
    s = _system(scheme)
    k, p = s.kernels, s._p()
    m, h, n = 3, 0.05, 120
    y0 = np.linspace(-1.0, 0.8, 2 * m).reshape(m, 2)
    st = trajectory_states(7, 0, m)
    got = k.final_states(p, s.sigma, y0, 0.0, h, n, st)
    for i, want in enumerate(_stepped_in_python(s, y0, st, h, n)):
        assert _same(want, got[i])


@pytest.mark.parametrize("model, scheme, lanes, parts", [
    (QUARTIC, "baoab", 6, True), (QUARTIC, "kp", 6, True), ("cdc", "baoab", 3, True),
    ("cdc", "kp", 2, False), ("vdp", "baoab", 6, False)])
def test_final_states_in_lanes_equal_the_scheme_stepped_in_python(model, scheme, lanes, parts):
    """final_states on ``2 lanes + 3`` trajectories (two loops of ``lanes`` trajectories, a
    pair, the last beside its twin; one trajectory of the second loop started at NaN)
    against each trajectory stepped in Python with the compiled one-step map and the
    generator's three-point increments (Kloeden & Platen eq. 14.2.8): the same bytes, the
    NaN start a NaN row.  The lane count is the printed one: 6 with no library call a step,
    3 with one (BAOAB's force on the CDC, paper eq. 12), 2 with two (Kloeden-Platen).  The
    loop runs each step in its parts (``_open`` of every lane, then ``_last``, then
    ``_close``) where every call of a step is in its last part, else lane by lane
    (Kloeden-Platen's ``sin`` in both accelerations; van der Pol's BAOAB, whose O part
    calls ``exp``: its friction depends on ``x``)."""
    params = ({"mu": 1.0} if model is QUARTIC else {"mu": 0.3} if model == "vdp"
              else {"mu": 0.1, "Delta": 3, "lam": 1, "Omega": 1})
    s = langevin_system(model, params, 1.0 if model is QUARTIC else 0.1, scheme)
    k, p = s.kernels, s._p()
    assert k.LANES == lanes
    assert ("_open(t, x0" in open(k.__file__).read()) == parts
    m, h, n = 2 * lanes + 3, 0.05, 150
    y0 = np.linspace(-1.0, 0.8, 2 * m).reshape(m, 2)
    y0[lanes + 1] = [np.nan, 0.0]
    st = trajectory_states(3, 0, m)
    got = k.final_states(p, s.sigma, y0, 0.0, h, n, st)
    for i, (x, v) in enumerate(_stepped_in_python(s, y0, st, h, n)):
        want = [x, v] if math.isfinite(x + v) else [math.nan, math.nan]
        assert _same(want, got[i]), i
    assert np.isnan(got[lanes + 1]).all() and np.isfinite(np.delete(got, lanes + 1, 0)).all()


@pytest.mark.parametrize("scheme", ["baoab", "kp"])
def test_first_passages_in_pairs_equal_first_passages_alone(scheme):
    """first_passages on nine trajectories (pairs run together until one leaves, the other
    then alone) against each run alone: the same times and flags, with trajectories that
    leave first, second and never (censored at ``n_max h``)."""
    s = _system(scheme)
    k, p = s.kernels, s._p()
    m, h, n_max = 9, 0.05, 600
    y0 = np.zeros((m, 2))
    st = trajectory_states(21, 0, m)
    times, hit = k.first_passages(p, s.sigma, y0, 0.0, h, n_max, -1.3, 1.3, st)
    assert 0 < hit.sum() < m and len(set(times[hit])) == hit.sum()
    assert (times[~hit] == n_max * h).all()
    for i in range(m):
        t1, h1 = k.first_passages(p, s.sigma, y0[i:i + 1], 0.0, h, n_max, -1.3, 1.3,
                                  st[i:i + 1])
        assert _same(t1[0], times[i]) and h1[0] == hit[i]


@pytest.mark.parametrize("scheme", ["baoab", "kp"])
def test_slider_records_in_pairs_equal_records_alone(scheme):
    """slip_stats of the CDC slider pulled at v = 0.5 (paper eq. 12) on five trajectories
    (two pairs and one alone, a pair with a NaN start) against each run alone: the same
    bytes, slips counted, and the NaN start a NaN row that leaves its partner's row as
    alone."""
    s = langevin_system("cdc", {"mu": 1.0, "Delta": 3, "lam": 1, "Omega": 1, "v": 0.5}, 0.05,
                        scheme)
    k, p = s.kernels, s._p()
    m, h = 5, 0.02
    y0 = np.zeros((m, 2))
    y0[2] = [np.nan, 0.0]
    st = trajectory_states(5, 0, m)
    args = (0.0, h, 200, 2000, st, 1.0, 2 * math.pi, 0.5)
    rows = k.slip_stats(p, s.sigma, y0, *args)
    assert np.isnan(rows[2]).all() and np.isfinite(rows[[0, 1, 3, 4]]).all()
    assert (rows[[0, 1, 3, 4], 1] > 0).all()
    for i in range(m):
        alone = k.slip_stats(p, s.sigma, y0[i:i + 1], 0.0, h, 200, 2000, st[i:i + 1], 1.0,
                             2 * math.pi, 0.5)
        assert _same(alone[0], rows[i])


def _coupled_by_hand(s, y0, h, n_burn, n_run, state, twin: bool) -> list:
    """The coupled runs of one trajectory written out with the compiled one-step map."""
    k, p = s.kernels, s._p()
    hf = 0.5 * h
    sf = s.sigma * math.sqrt(hf)
    af, ac = sf * k._noise_factor(p, hf), sf * k._noise_factor(p, h)
    gen = state.copy()
    f0 = k._first(0.0, y0[0], y0[1], p)
    runs = {"c": [y0[0], y0[1], f0], "a": [y0[0], y0[1], f0], "b": [y0[0], y0[1], f0]}
    acc = np.zeros(6)
    for j in range(n_burn + n_run):
        g1, g2 = k._normal_pair(gen)
        t = j * h
        for name, first, second in (("a", g1, g2), ("b", g2, g1)):
            if name == "b" and not twin:
                continue
            x, v, f = runs[name]
            x, v, f = k._step(t, x, v, f, hf, af * first, p)
            runs[name] = list(k._step(t + hf, x, v, f, hf, af * second, p))
        x, v, f = runs["c"]
        runs["c"] = list(k._step(t, x, v, f, h, ac * (g1 + g2), p))
        if j >= n_burn:
            for c, name in enumerate("cab"):
                x, v = runs[name][:2]
                acc[2 * c] += x * x
                acc[2 * c + 1] += x * x + (v / s.omega0) ** 2
    return [a / n_run for a in acc[:6 if twin else 4]]


def test_couplings_equal_the_couplings_written_out():
    """step_pair_stats (synchronous) and step_antithetic_stats (antithetic twin), one loop
    with the coupling chosen at compile time, against the couplings written out in Python
    from the compiled ``_step`` and ``_normal_pair``: the same bytes; the antithetic
    kernel's coarse and first fine columns are the synchronous pair's."""
    s = _system("baoab")
    k, p = s.kernels, s._p()
    y0 = np.array([[0.3, -0.2], [-0.8, 0.5]])
    st = trajectory_states(4, 0, 2)
    h, n_burn, n_run = 0.2, 5, 40
    pair = k.step_pair_stats(p, s.sigma, y0, 0.0, h, n_burn, n_run, st, s.omega0)
    anti = k.step_antithetic_stats(p, s.sigma, y0, 0.0, h, n_burn, n_run, st, s.omega0)
    assert pair.shape == (2, 4) and anti.shape == (2, 6)
    assert _same(anti[:, :4], pair)
    for i in range(2):
        assert _same(pair[i], _coupled_by_hand(s, y0[i], h, n_burn, n_run, st[i], False))
        assert _same(anti[i], _coupled_by_hand(s, y0[i], h, n_burn, n_run, st[i], True))
    assert not _same(anti[:, 4:], anti[:, 2:4])  # the twin is another path
