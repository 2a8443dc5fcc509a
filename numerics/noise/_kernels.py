"""Compiled Langevin kernels of :mod:`numerics.noise`, as source appended to a printed model.

This file is read as text and appended to the module that
:func:`numerics.noise.langevin.langevin_system` prints for a model; that module
defines, above this text, ``accel(t_, x_, v_, p)`` (the model's ``x''`` without the
noise), ``spring(t_, x_, v_, p)`` (the spring force ``drive - omega0^2 x``) and
``energy(x_, v_, p)`` (``x'^2/2 + G(x)``, NaN when the potential has no closed
form).  numba compiles all of it.  Appended to the module of ``N`` coupled accelerations
(:func:`numerics.noise.codegen.vector_module`), which defines ``accel_n(t_, y, p, out)``
instead, it serves :func:`vector_paths`, the same scheme for ``N`` degrees of freedom.

The scheme
----------
``x' = v``, ``v' = f(t, x, v) + sigma xi(t)`` with ``sigma = sqrt(2 D)`` and additive
noise is advanced by the explicit order-2.0 weak scheme of Kloeden and Platen,
*Numerical Solution of Stochastic Differential Equations* (Springer 1992),
eq. (15.1.3) (Platen's scheme for additive noise, a stochastic Heun step):

``ybar = y + a(t, y) h + b dW``,  ``y' = y + (a(t, y) + a(t + h, ybar)) h/2 + b dW``

with ``a = (v, f)``, ``b = (0, sigma)`` and ``dW`` the three-point random variable
``P(dW = +-sqrt(3 h)) = 1/6``, ``P(dW = 0) = 2/3`` (its moments equal the Gaussian's
up to the fifth, which is what weak order 2 needs; Kloeden & Platen eq. (14.2.8)).
Two evaluations of ``f`` and one uniform number per step.

Random numbers
--------------
xoshiro256** (Blackman and Vigna, ACM TOMS 47 (2021) 36), one generator per
trajectory, its 256-bit state taken from that trajectory's own
``numpy.random.SeedSequence`` (:mod:`numerics.noise.seeds`): a trajectory's path
depends on the root seed and its index only, never on the chunk it runs in.
"""

import math

import numpy as np
from numba import njit

_U5 = np.uint64(5)
_U9 = np.uint64(9)
_U11 = np.uint64(11)
_U17 = np.uint64(17)
_TO_UNIT = 1.0 / 9007199254740992.0  # 2**-53


@njit(cache=True)
def _rotl(x, k):
    return (x << np.uint64(k)) | (x >> np.uint64(64 - k))


@njit(cache=True)
def _next(s):
    """The next 64-bit output of xoshiro256** (state ``s``, 4 x uint64, updated)."""
    result = _rotl(s[1] * _U5, 7) * _U9
    t = s[1] << _U17
    s[2] ^= s[0]
    s[3] ^= s[1]
    s[1] ^= s[2]
    s[0] ^= s[3]
    s[2] ^= t
    s[3] = _rotl(s[3], 45)
    return result


@njit(cache=True)
def _uniform(s):
    """A uniform number in [0, 1) with 53 random bits."""
    return float(_next(s) >> _U11) * _TO_UNIT


@njit(cache=True)
def _increment(s, root3h):
    """The three-point weak increment: +-sqrt(3 h) with probability 1/6 each, else 0
    (``root3h`` is ``sqrt(3 h)``, or that times the noise amplitude: ``+-root3h`` or 0)."""
    u = _uniform(s)
    if u < 1.0 / 6.0:
        return -root3h
    if u < 1.0 / 3.0:
        return root3h
    return 0.0


@njit(cache=True)
def _ou(gh):
    """The O part's factors ``(e^(-gh), sqrt((1 - e^(-2gh))/(2 gh)))`` by exp alone (an LLVM
    intrinsic), the second by its series where the difference would cancel (error below
    1e-12)."""
    e = math.exp(-gh)
    if abs(gh) > 1e-4:
        return e, math.sqrt((1.0 - e * e) / (2.0 * gh))
    return e, math.sqrt(1.0 - gh * (1.0 - gh * (2.0 / 3.0 - gh / 3.0)))


@njit(cache=True)
def _noise_factor(p, h):
    """What the increments' amplitude is multiplied by before a step ``h``: the O part's
    ``sqrt((1 - e^(-2 gamma h))/(2 gamma h))`` when the friction ``gamma`` is a constant
    (BAOAB; folded into the amplitude once, so that the step is as short as a hand loop's),
    else 1 (the step applies it, or Kloeden-Platen needs none)."""
    if SCHEME == 1 and FRICTION_CONST:  # noqa: F821 - set by the printed model above
        return _ou(friction(0.0, 0.0, p) * h)[1]  # noqa: F821
    return 1.0


@njit(cache=True)
def _open(t, x, v, f, h, sdw, p):
    """A step up to its last evaluation of the model (``sdw = sigma * dW``): ``(x, v, xb,
    vb, a0)``.  BAOAB (Leimkuhler & Matthews 2013; ``v' = force(t, x) - gamma(t, x) v + sigma
    xi``): B, A, O, A, the O part solved exactly at the frozen midpoint position, ``f`` the
    force at the previous step's end (one new force evaluation per step) and ``sdw`` times
    ``_noise_factor(p, h)`` (the O part's noise factor when the friction is constant);
    ``(xb, vb)`` is the state before the last B.  Kloeden-Platen (15.1.3): ``a0 =
    a(t, x, v)`` and the predictor ``(xb, vb)``; ``f`` unused."""
    if SCHEME == 1:  # noqa: F821 - set by the printed model above
        v = v + 0.5 * h * f
        x = x + 0.5 * h * v
        if FRICTION_CONST:  # noqa: F821 - 1 when gamma depends on no state: hoisted from loops
            e = math.exp(-friction(0.0, 0.0, p) * h)  # noqa: F821 - the printed model above
            v = e * v + sdw
        else:
            e, c = _ou(friction(t + 0.5 * h, x, p) * h)  # noqa: F821
            v = e * v + c * sdw
        x = x + 0.5 * h * v
        return x, v, x, v, 0.0
    a0 = accel(t, x, v, p)  # noqa: F821 - defined by the printed model above
    return x, v, x + v * h, v + a0 * h + sdw, a0


@njit(cache=True)
def _last(t, xb, vb, h, p):
    """The step's last evaluation of the model: BAOAB's force at the new position, or
    Kloeden-Platen's ``a(t + h, xb, vb)`` at the predictor."""
    if SCHEME == 1:  # noqa: F821
        return force(t + h, xb, p)  # noqa: F821
    return accel(t + h, xb, vb, p)  # noqa: F821


@njit(cache=True)
def _close(x, v, xb, vb, a0, a1, h, sdw):
    """The step's end from :func:`_open`'s ``(x, v, xb, vb, a0)`` and :func:`_last`'s ``a1``:
    ``(x, v, f)`` (BAOAB's last B, ``f = a1`` carried to the next step; Kloeden-Platen's
    corrector, ``f = 0``)."""
    if SCHEME == 1:  # noqa: F821
        return xb, vb + 0.5 * h * a1, a1
    return x + 0.5 * (v + vb) * h, v + 0.5 * (a0 + a1) * h + sdw, 0.0


@njit(cache=True)
def _first(t, x, v, p):
    """The carried force at the start (BAOAB) or 0 (Kloeden-Platen carries nothing)."""
    if SCHEME == 1:  # noqa: F821 - set by the printed model above
        return force(t, x, p)  # noqa: F821
    return 0.0


@njit(cache=True)
def _step(t, x, v, f, h, sdw, p):
    """One step of the model's scheme (``SCHEME``: 0 Kloeden-Platen, 1 BAOAB): ``(x, v, f)``,
    :func:`_open`, :func:`_last` and :func:`_close` in turn (the loops over several
    trajectories run each part for every lane before the next part:
    :mod:`numerics.noise.lanes`)."""
    x, v, xb, vb, a0 = _open(t, x, v, f, h, sdw, p)
    return _close(x, v, xb, vb, a0, _last(t, xb, vb, h, p), h, sdw)


@njit(cache=True)
def _pair_start(p, y0, t0, states, i, j):
    """Trajectories ``i`` and ``j`` at ``t0`` (``j == i``: trajectory ``i`` and its twin):
    ``(sa, xa, va, fa, sb, xb, vb, fb)``, each its generator (a copy of ``states[i]``,
    ``states[j]``), its state and its carried force."""
    sa = states[i].copy()
    sb = states[j].copy()
    xa, va = y0[i, 0], y0[i, 1]
    xb, vb = y0[j, 0], y0[j, 1]
    return sa, xa, va, _first(t0, xa, va, p), sb, xb, vb, _first(t0, xb, vb, p)


@njit(cache=True)
def _advance2(p, xa, va, sa, xb, vb, sb, t0, h, n, amp):
    """``n`` steps of two trajectories from ``(xa, va)`` and ``(xb, vb)`` at ``t0`` in one
    loop, each on its own generator (``sa``, ``sb``): ``(xa, va, xb, vb)``, a state NaN when
    it ends non-finite (a non-finite state stays non-finite: NaN propagates through every
    step, so the loop holds no test).  A step's force is a chain of dependent operations
    (the new ``x`` waits for the kick, the next kick for the force at the new ``x``: a libm
    call), so one trajectory leaves most of the core idle; two independent chains in one
    loop fill it (measured: 1.3-1.6x the steps per second).  Each trajectory's numbers are
    those it has alone: a trajectory alone runs beside its twin (the same state and a copy
    of its generator)."""
    fa = _first(t0, xa, va, p)
    fb = _first(t0, xb, vb, p)
    for k in range(n):
        t = t0 + k * h
        xa, va, fa = _step(t, xa, va, fa, h, _increment(sa, amp), p)
        xb, vb, fb = _step(t, xb, vb, fb, h, _increment(sb, amp), p)
    if not math.isfinite(xa + va):
        xa, va = math.nan, math.nan
    if not math.isfinite(xb + vb):
        xb, vb = math.nan, math.nan
    return xa, va, xb, vb


@njit(cache=True)
def _finite(x, v):
    """``(x, v)``, or NaNs when either is non-finite."""
    if math.isfinite(x + v):
        return x, v
    return math.nan, math.nan


@njit(cache=True)
def final_states(p, sigma, y0, t0, h, n, states):
    """The states after ``n`` steps from ``y0[i]`` (``NaN`` once a state is non-finite);
    trajectories ``LANES`` at a time in one loop (``_advance_lanes``, printed for the model
    by :func:`numerics.noise.lanes.lanes_source`), the rest two at a time
    (:func:`_advance2`), the last of an odd number beside its twin: each trajectory's
    numbers are those it has alone."""
    m = y0.shape[0]
    out = np.empty((m, 2))
    amp = sigma * _noise_factor(p, h) * math.sqrt(3.0 * h)
    whole = m - m % LANES  # noqa: F821 - set by the printed model above
    for i in range(0, whole, LANES):  # noqa: F821
        _advance_lanes(p, y0, t0, h, n, states, i, amp, out)  # noqa: F821
    for i in range(whole, m, 2):
        j = min(i + 1, m - 1)
        sa = states[i].copy()
        sb = states[j].copy()
        xa, va, xb, vb = _advance2(p, y0[i, 0], y0[i, 1], sa, y0[j, 0], y0[j, 1], sb, t0, h,
                                   n, amp)
        out[i, 0], out[i, 1] = xa, va
        out[j, 0], out[j, 1] = xb, vb
    return out


@njit(cache=True)
def _observe(kind, x, v, w0, p):
    if kind == 0:
        return math.sqrt(x * x + (v / w0) ** 2)
    if kind == 1:
        return x
    return energy(x, v, p)  # noqa: F821


@njit(cache=True)
def sample_path(p, sigma, y0, t0, h, n, stride, state):
    """One trajectory's states every ``stride`` steps (``n // stride + 1`` rows)."""
    rows = n // stride + 1
    out = np.full((rows, 2), np.nan)
    s = state.copy()
    x, v = y0[0], y0[1]
    out[0, 0], out[0, 1] = x, v
    amp = sigma * _noise_factor(p, h) * math.sqrt(3.0 * h)
    f = _first(t0, x, v, p)
    for k in range(n):
        x, v, f = _step(t0 + k * h, x, v, f, h, _increment(s, amp), p)
        if not math.isfinite(x + v):
            break
        if (k + 1) % stride == 0:
            out[(k + 1) // stride, 0], out[(k + 1) // stride, 1] = x, v
    return out


@njit(cache=True)
def vector_paths(p, amps, y, t0, h, n, stride, states):
    """Kloeden-Platen (15.1.3) for ``N`` degrees of freedom with independent additive noises
    on the velocities, ``x_i' = v_i``, ``v_i' = a_i(t, x, v) + amps[r] xi_i`` (``a`` is
    ``accel_n`` of the printed model above): the rows of ``y`` (``m x 2N``, updated) driven
    by the generators ``states[r]`` (updated; ``amps[r] = 0``: a noise-free row), their
    states every ``stride`` steps (``m x n // stride x 2N``).  Step ``k`` draws the modes'
    increments in order."""
    m, d = y.shape
    nd = d // 2
    rec = np.empty((m, n // stride, d))
    a0 = np.empty(nd)
    a1 = np.empty(nd)
    yb = np.empty(d)
    dw = np.empty(nd)
    for r in range(m):
        s = states[r]
        yr = y[r]
        root = amps[r] * math.sqrt(3.0 * h)
        for k in range(n):
            t = t0 + k * h
            accel_n(t, yr, p, a0)  # noqa: F821 - defined by the printed model above
            for i in range(nd):
                dw[i] = _increment(s, root)
                yb[i] = yr[i] + h * yr[nd + i]
                yb[nd + i] = yr[nd + i] + h * a0[i] + dw[i]
            accel_n(t + h, yb, p, a1)  # noqa: F821
            for i in range(nd):
                yr[i] = yr[i] + 0.5 * h * (yr[nd + i] + yb[nd + i])
                yr[nd + i] = yr[nd + i] + 0.5 * h * (a0[i] + a1[i]) + dw[i]
            if (k + 1) % stride == 0:
                for i in range(d):
                    rec[r, (k + 1) // stride - 1, i] = yr[i]
    return rec
