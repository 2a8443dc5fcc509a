"""Compiled Gaussian-increment kernels of :mod:`numerics.noise`: the pair of steps on one
Brownian path and the increments of the other kernels, appended as source after
:mod:`numerics.noise._kernels` (whose ``_step``, ``_first``, ``_uniform`` and
``_noise_factor`` they call) to a printed model.

The Richardson extrapolation (:mod:`numerics.noise.extrapolate`) and the measured default
step (:func:`numerics.noise.langevin.measured_step`) run the scheme at ``h`` and ``h/2`` on one
Brownian path (``step_pair_stats``), each coarse Gaussian increment the sum of the two fine
ones, so that the runs stay close and their difference has a small variance;
``step_antithetic_stats`` adds the fine run with each coarse step's two increments swapped
(the antithetic correction): both couplings are one loop (``_coupled_stats``) with the
coupling chosen at compile time.  ``_normal_pair`` and the four-point Gauss-Hermite
increment ``_increment4`` also drive the ensemble kernels of
:mod:`numerics.noise._lane_kernels` (``step_gauss_stats``, ``stationary_stats4``).
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
