"""Compiled kernels of :mod:`numerics.noise` for stationary averages, appended as source
after :mod:`numerics.noise._kernels` (whose ``_step``, ``_first``, ``_uniform`` and
``_noise_factor`` they call) to a printed model.

The Richardson extrapolation (:mod:`numerics.noise.extrapolate`) and the measured default
step (:func:`numerics.noise._pilot.measured_step`) run the scheme at ``h`` and ``h/2`` on one
Brownian path (``step_pair_stats``), each coarse Gaussian increment the sum of the two fine
ones, so that the runs stay close and their difference has a small variance;
``step_antithetic_stats`` adds the fine run with each coarse step's two increments swapped
(the antithetic correction): both couplings are one loop (``_coupled_stats``) with the
coupling chosen at compile time.  ``stationary_stats4`` is the stationary ensembles' kernel,
with four-point Gauss-Hermite increments (``_increment4``), ``stationary_stats`` the same
with three-point ones and ``step_gauss_stats`` (the two-level estimator's level 0) with
Gaussian ones: one loop body for the three (``_stats``, the increment law a compile-time
constant), two trajectories to a loop.
"""

import math

import numpy as np
from numba import njit


@njit(cache=True)
def _normal_pair(s):
    """Two independent standard normal numbers (Box-Muller on two uniforms)."""
    r = math.sqrt(-2.0 * math.log(1.0 - _uniform(s)))  # noqa: F821
    phi = 2.0 * math.pi * _uniform(s)  # noqa: F821
    return r * math.cos(phi), r * math.sin(phi)


@njit(cache=True, inline="always")
def _coupled_stats(p, sigma, y0, t0, h, n_burn, n_run, states, w0, twin):
    """The coupled runs at ``h`` and ``h/2`` on one Brownian path: the coarse step takes
    ``g_1 + g_2``, the fine run ``g_1`` then ``g_2`` and, when ``twin``, a second fine run
    ``g_2`` then ``g_1``.  ``twin`` is a constant at both call sites
    (:func:`step_pair_stats`, :func:`step_antithetic_stats`) and this function is inlined
    into them (numba ``inline="always"``), so the choice of coupling is made at compile
    time: one loop, no branch left in either kernel.  Columns ``x^2, a^2`` of the coarse
    run, of the fine one and (``twin``) of the twin; NaN rows for a diverged trajectory."""
    m = y0.shape[0]
    ncol = 6 if twin else 4
    out = np.zeros((m, ncol))
    hf = 0.5 * h
    sf = sigma * math.sqrt(hf)
    af = sf * _noise_factor(p, hf)  # noqa: F821
    ac = sf * _noise_factor(p, h)  # noqa: F821
    for i in range(m):
        s = states[i].copy()
        xc, vc = y0[i, 0], y0[i, 1]
        xa, va = xc, vc
        xb, vb = xc, vc
        fc = _first(t0, xc, vc, p)  # noqa: F821
        fa = fc
        fb = fc
        acc = np.zeros(ncol)
        ok = True
        for k in range(n_burn + n_run):
            g1, g2 = _normal_pair(s)
            t = t0 + k * h
            xa, va, fa = _step(t, xa, va, fa, hf, af * g1, p)  # noqa: F821
            xa, va, fa = _step(t + hf, xa, va, fa, hf, af * g2, p)  # noqa: F821
            if twin:
                xb, vb, fb = _step(t, xb, vb, fb, hf, af * g2, p)  # noqa: F821
                xb, vb, fb = _step(t + hf, xb, vb, fb, hf, af * g1, p)  # noqa: F821
            xc, vc, fc = _step(t, xc, vc, fc, h, ac * (g1 + g2), p)  # noqa: F821
            if not (math.isfinite(xc) and math.isfinite(vc) and math.isfinite(xa)
                    and math.isfinite(va) and math.isfinite(xb) and math.isfinite(vb)):
                ok = False
                break
            if k >= n_burn:
                acc[0] += xc * xc
                acc[1] += xc * xc + (vc / w0) ** 2
                acc[2] += xa * xa
                acc[3] += xa * xa + (va / w0) ** 2
                if twin:
                    acc[4] += xb * xb
                    acc[5] += xb * xb + (vb / w0) ** 2
        for c in range(ncol):
            out[i, c] = acc[c] / n_run if ok else math.nan
    return out


@njit(cache=True)
def step_pair_stats(p, sigma, y0, t0, h, n_burn, n_run, states, w0):
    """Per trajectory: the time averages of ``x^2`` and ``a^2`` after ``n_burn`` steps, over
    ``n_run`` steps ``h`` and, on the same Brownian path, over ``2 n_run`` steps ``h/2``
    (Gaussian increments: the two fine ones ``sqrt(h/2) g_1``, ``sqrt(h/2) g_2`` sum to the
    coarse one, so the two runs stay close and their difference is the step's bias with a
    small variance).  Columns: ``x^2 (h), a^2 (h), x^2 (h/2), a^2 (h/2)``; NaN rows for a
    diverged trajectory.  The synchronous coupling of :func:`_coupled_stats`."""
    return _coupled_stats(p, sigma, y0, t0, h, n_burn, n_run, states, w0, False)


@njit(cache=True)
def step_antithetic_stats(p, sigma, y0, t0, h, n_burn, n_run, states, w0):
    """Per trajectory: the time averages of ``x^2`` and ``a^2`` over ``n_run`` steps ``h``
    after ``n_burn`` at the step ``h`` and at ``h/2`` twice, on one Brownian path and its
    antithetic twin (Giles & Szpruch, Ann. Appl. Probab. 24 (2014) 1585): the coarse step
    takes ``g_1 + g_2``, the first fine run ``g_1`` then ``g_2``, the second ``g_2`` then
    ``g_1``.  Both fine runs are BAOAB at ``h/2`` with Gaussian increments; their mean minus
    the coarse run cancels the part of the difference linear in ``g_1 - g_2``.  Columns
    ``x^2 (h), a^2 (h), x^2 (h/2, first), a^2, x^2 (h/2, twin), a^2``; NaN rows for a
    diverged trajectory.  The antithetic coupling of :func:`_coupled_stats`."""
    return _coupled_stats(p, sigma, y0, t0, h, n_burn, n_run, states, w0, True)


#: the four-point Gauss-Hermite increment (Abramowitz & Stegun 25.4.46): nodes ``+-A4``,
#: ``+-B4`` (times ``sqrt(h)``) with probabilities ``PA4``, ``PB4`` each; its moments are the
#: Gaussian's up to the seventh, so BAOAB's ``h^2`` coefficient is the Gaussian one (the
#: three-point law's sixth moment, 9 in place of 15, gives another)
A4 = math.sqrt(3.0 - math.sqrt(6.0))
B4 = math.sqrt(3.0 + math.sqrt(6.0))
PA4 = (3.0 + math.sqrt(6.0)) / 12.0
PB4 = (3.0 - math.sqrt(6.0)) / 12.0


@njit(cache=True)
def _increment4(s, amp):
    """The four-point increment times ``amp`` (``sigma sqrt(h)``, the noise factor folded
    in) from one 64-bit output: its top 53 bits choose the node's size (``B4`` with
    probability ``2 PB4``), its lowest bit the sign (no branch: the sizes' and signs'
    selects compile to conditional moves)."""
    r = _next(s)  # noqa: F821
    u = float(r >> np.uint64(11)) * (1.0 / 9007199254740992.0)
    size = B4 if u < 2.0 * PB4 else A4
    sign = 1.0 - 2.0 * float(r & np.uint64(1))
    return sign * size * amp


@njit(cache=True)
def _increment_law(law, s, amp, k, spare):
    """Step ``k``'s increment times ``amp`` and the normal number carried to the next step:
    four-point (``law`` 4), three-point (3) or Gaussian (0, one normal pair per two steps);
    ``law`` is a constant at every call site, for which numba compiles the function apart."""
    if law == 4:
        return _increment4(s, amp), spare
    if law == 0:
        if k % 2 == 0:
            g1, g2 = _normal_pair(s)
            return amp * g1, g2
        return amp * spare, spare
    return _increment(s, amp), spare  # noqa: F821


@njit(cache=True)
def _run_start(law, t0, h, n_burn):
    """The run phase's time origin ``(t_b, k_b)`` (step ``k`` at ``t_b + (k - k_b) h``): the
    four-point kernel counts from ``t0``, the three-point one from ``t1 = t0 + n_burn h``,
    its carried force evaluated there again."""
    if law == 3:
        return t0 + n_burn * h, n_burn
    return t0, 0


@njit(cache=True, inline="always")
def _two_steps(law, p, amp, t, h, k, sa, xa, va, fa, ga, sb, xb, vb, fb, gb):
    """Step ``k`` (at ``t``) of both lanes of :func:`_stats_two`, each its increment
    (:func:`_increment_law`, ``g`` the carried normal number) and its step; inlined (numba
    ``inline="always"``) into the two loops."""
    dwa, ga = _increment_law(law, sa, amp, k, ga)
    dwb, gb = _increment_law(law, sb, amp, k, gb)
    xa, va, fa = _step(t, xa, va, fa, h, dwa, p)  # noqa: F821
    xb, vb, fb = _step(t, xb, vb, fb, h, dwb, p)  # noqa: F821
    return xa, va, fa, ga, xb, vb, fb, gb


@njit(cache=True)
def _stats_two(law, p, amp, y0, t0, h, n_burn, n_run, states, w0, kind, lo, width, sums, hist,
               ia, ib):
    """Rows ``ia`` and ``ib`` of :func:`stationary_stats` (``law`` 3) or
    :func:`stationary_stats4` (4), the two trajectories in one loop (two independent chains
    of dependent operations fill the core: see ``_advance2``), each exactly as it runs
    alone (``ib == ia``: trajectory ``ia`` beside its twin).  False (nothing written) when
    a state turns non-finite: the caller then runs each beside its twin."""
    nbins = hist.shape[1]
    sa, xa, va, fa, sb, xb, vb, fb = _pair_start(p, y0, t0, states, ia, ib)  # noqa: F821
    ga, gb = 0.0, 0.0
    for k in range(n_burn):
        xa, va, fa, ga, xb, vb, fb, gb = _two_steps(law, p, amp, t0 + k * h, h, k, sa, xa, va,
                                                    fa, ga, sb, xb, vb, fb, gb)
    if not (math.isfinite(xa + va) and math.isfinite(xb + vb)):
        return False
    tb, kb = _run_start(law, t0, h, n_burn)
    if law == 3:
        fa = _first(tb, xa, va, p)  # noqa: F821
        fb = _first(tb, xb, vb, p)  # noqa: F821
    a_x2, a_a2, a_v2, a_f = 0.0, 0.0, 0.0, 0.0
    b_x2, b_a2, b_v2, b_f = 0.0, 0.0, 0.0, 0.0
    ha = np.zeros(nbins)
    hb = np.zeros(nbins)
    for k in range(n_burn, n_burn + n_run):
        xa, va, fa, ga, xb, vb, fb, gb = _two_steps(law, p, amp, tb + (k - kb) * h, h, k, sa,
                                                    xa, va, fa, ga, sb, xb, vb, fb, gb)
        if not (math.isfinite(xa + va) and math.isfinite(xb + vb)):
            return False
        a_x2 += xa * xa
        a_a2 += xa * xa + (va / w0) ** 2
        b_x2 += xb * xb
        b_a2 += xb * xb + (vb / w0) ** 2
        if law != 0:  # the Gaussian kernel keeps x^2 and a^2 only
            tn = tb + (k - kb + 1) * h
            a_v2 += va * va
            a_f += spring(tn, xa, va, p)  # noqa: F821
            b_v2 += vb * vb
            b_f += spring(tn, xb, vb, p)  # noqa: F821
            j = int(math.floor((_observe(kind, xa, va, w0, p) - lo) / width))  # noqa: F821
            if 0 <= j < nbins:
                ha[j] += 1.0
            j = int(math.floor((_observe(kind, xb, vb, w0, p) - lo) / width))  # noqa: F821
            if 0 <= j < nbins:
                hb[j] += 1.0
    sums[ia, 0], sums[ia, 1] = a_x2 / n_run, a_a2 / n_run
    sums[ia, 2], sums[ia, 3] = a_v2 / n_run, a_f / n_run
    sums[ib, 0], sums[ib, 1] = b_x2 / n_run, b_a2 / n_run
    sums[ib, 2], sums[ib, 3] = b_v2 / n_run, b_f / n_run
    for j in range(nbins):
        hist[ia, j] = ha[j] / n_run
        hist[ib, j] = hb[j] / n_run
    return True


@njit(cache=True)
def _stats(law, p, amp, y0, t0, h, n_burn, n_run, states, w0, kind, lo, hi, nbins):
    """Trajectories two at a time (:func:`_stats_two`), the last of an odd number and each
    of a pair with a diverged one beside its twin: the same numbers either way (NaN rows
    for a diverged trajectory)."""
    m = y0.shape[0]
    sums = np.zeros((m, 4))
    hist = np.zeros((m, nbins))
    width = (hi - lo) / nbins
    for i in range(0, m, 2):
        j = min(i + 1, m - 1)
        if _stats_two(law, p, amp, y0, t0, h, n_burn, n_run, states, w0, kind, lo, width,
                      sums, hist, i, j):
            continue
        for r in range(i, j + 1):
            if j == i or not _stats_two(law, p, amp, y0, t0, h, n_burn, n_run, states, w0,
                                        kind, lo, width, sums, hist, r, r):
                sums[r, :] = math.nan
                hist[r, :] = math.nan
    return sums, hist


@njit(cache=True)
def stationary_stats(p, sigma, y0, t0, h, n_burn, n_run, states, w0, kind, lo, hi, nbins):
    """Per trajectory: the time averages of ``x^2``, ``a^2 = x^2 + (x'/w0)^2``, ``x'^2`` and
    the spring force over ``n_run`` steps after ``n_burn``, and the fraction of those
    steps the observable ``kind`` (0: ``a``, 1: ``x``, 2: the energy) spent in each of
    ``nbins`` equal bins of ``[lo, hi)``; three-point increments (:func:`_increment`).  A
    diverged trajectory gives NaN rows.  Trajectories two at a time (:func:`_stats`)."""
    amp = sigma * _noise_factor(p, h) * math.sqrt(3.0 * h)  # noqa: F821
    return _stats(3, p, amp, y0, t0, h, n_burn, n_run, states, w0, kind, lo, hi, nbins)


@njit(cache=True)
def stationary_stats4(p, sigma, y0, t0, h, n_burn, n_run, states, w0, kind, lo, hi, nbins):
    """``stationary_stats`` with the four-point increments (:func:`_increment4`): the
    stationary ensembles' kernel, whose ``h^2`` coefficient is the Gaussian pair's that the
    step pilot (``step_pair_stats``) measures."""
    amp = sigma * math.sqrt(h) * _noise_factor(p, h)  # noqa: F821
    return _stats(4, p, amp, y0, t0, h, n_burn, n_run, states, w0, kind, lo, hi, nbins)


@njit(cache=True)
def step_gauss_stats(p, sigma, y0, t0, h, n_burn, n_run, states, w0):
    """Per trajectory: the time averages of ``x^2`` and ``a^2`` over ``n_run`` steps ``h``
    after ``n_burn``, with Gaussian increments (one normal pair per two steps): the level
    0 of the two-level estimator, whose expansion in ``h`` is the pair's (the three-point
    increments of ``stationary_stats`` have another ``h^2`` coefficient).  Columns ``x^2,
    a^2``; NaN rows for a diverged trajectory.  The loop of :func:`_stats`."""
    amp = sigma * math.sqrt(h) * _noise_factor(p, h)  # noqa: F821
    sums, _ = _stats(0, p, amp, y0, t0, h, n_burn, n_run, states, w0, 1, 0.0, 1.0, 1)
    return sums[:, :2].copy()
