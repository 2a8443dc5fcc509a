"""Thermally activated slips of the Prandtl-Tomlinson slider (the CDC, paper eq. 12) by
rate theory: the creep law of the slip force.

The stage at ``L`` holds the slider in a well of ``U(x, L) = Omega^2 (x - L)^2/2 -
(Delta/k) cos(k x)`` (paper eq. 4, derived from the symbolic CDC once:
:func:`numerics.sliding.potential.eq4`).  Pulled slowly (``dL/dt = v``), the forward barrier
``E_b(L)`` shrinks and vanishes at the saddle node ``L_0``, where the athermal slider
slips at the static force ``F_c = Omega^2 (L_0 - x_0)``
(:func:`numerics.sliding.potential.saddle_node`).  With noise the slider leaves earlier,
at the escape rate ``r(L)``; the probability to be still stuck at ``L`` is
``S(L) = exp(-int r(L')/v dL')`` and the mean slip force is
``<F> = int F(L) (-dS/dL) dL + F_c S(L_0)`` (Sang, Dube and Grant, PRL 87 (2001) 174301;
Dudko, Filippov, Klafter and Urbakh, Chem. Phys. Lett. 352 (2002) 499).

The rate is the underdamped one of :mod:`numerics.escape.rate`, Kramers' energy-diffusion
rate with the Mel'nikov-Meshkov depopulation factor, ``r = A(delta) (omega_w/2 pi)
exp(-E_b/kT)``, ``delta = mu I(E_b)/kT``, with the barrier, the well frequency and the
separatrix action computed from the potential at each ``L``.  Near the saddle node
``E_b ~ (F_c - F)^{3/2}``, whence the creep law ``F_c - <F> ~ T^{2/3}
|ln(v/v_c)|^{2/3}``; :func:`fit_creep` measures both exponents.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import quad
from scipy.optimize import brentq, curve_fit

from kbm.errors import ParameterError

from ..sliding.potential import eq4, saddle_node
from .turnover import melnikov_meshkov_factor

__all__ = ["SlipForce", "slip_force", "CreepFit", "fit_creep", "barrier_at", "law_points"]


def barrier_at(L: float, *, Delta: float, lam: float = 1.0, Omega: float = 1.0):
    """``(x_w, x_s, E_b, omega_w, I(E_b))`` of the well at the stage position ``L``
    (``0 <= L < L_0``, the well that holds the slider from ``x = 0``)."""
    k = 2 * math.pi / lam
    sn = saddle_node(Delta=Delta, lam=lam, Omega=Omega)
    xc = sn.x0
    f = eq4()

    def g(z):
        return f.dU(z, L, Delta, k, Omega)

    def U(z):
        return f.U(z, L, Delta, k, Omega)

    xw = brentq(g, -xc, xc, xtol=1e-15)
    xs = brentq(g, xc, lam - xc, xtol=1e-15)
    Eb = U(xs) - U(xw)
    ww = math.sqrt(f.d2U(xw, L, Delta, k, Omega))
    # the other turning point of the separatrix loop: scan left from the well until U
    # exceeds the forward saddle's value (the backward barrier is higher for L >= 0)
    Us, step, lo = U(xs), lam / 512, xw
    while True:
        nxt = lo - step
        if U(nxt) >= Us:
            xt = brentq(lambda z: U(z) - Us, nxt, lo, xtol=1e-15)
            break
        if g(nxt) >= 0:   # passed the backward saddle (level with the forward one at L = 0)
            xt = brentq(g, nxt, lo, xtol=1e-15)
            break
        lo = nxt
    I = 2 * quad(lambda z: math.sqrt(max(2 * (U(xs) - U(z)), 0.0)), xt, xs, limit=200)[0]
    return xw, xs, Eb, ww, I


def law_points(fit: str, columns: dict, positive: tuple = (), errors: tuple = ()) -> list:
    """The columns of a friction law's points as float arrays, checked for a fit.

    Each column must be a 1-D sequence of finite numbers, all of one length, the columns
    named in ``positive`` (those fitted in logarithms: ``v``, ``kT``) above zero, and those
    named in ``errors`` (standard errors) not below zero.

    Raises
    ------
    kbm.errors.ParameterError
        Naming ``fit``, the column and the first offending point.
    """
    try:
        arrays = [np.asarray(z, float) for z in columns.values()]
    except (TypeError, ValueError) as exc:
        raise ParameterError(f"{fit}: {', '.join(columns)} must be sequences of numbers "
                             f"({exc})") from None
    lengths = [a.shape[0] if a.ndim == 1 else None for a in arrays]
    if None in lengths or len(set(lengths)) != 1:
        got = ", ".join(f"{n} {a.shape}" for n, a in zip(columns, arrays))
        raise ParameterError(f"{fit}: {', '.join(columns)} must be 1-D sequences of the same "
                             f"length (one entry per point), got shapes {got}")
    for name, a in zip(columns, arrays):
        bad = np.flatnonzero(~np.isfinite(a))
        if bad.size:
            raise ParameterError(f"{fit}: {name} must be finite, got {a[bad[0]]} at point "
                                 f"{bad[0]} (drop the failed points)")
        if name in positive and np.any(a <= 0):
            i = int(np.flatnonzero(a <= 0)[0])
            raise ParameterError(f"{fit}: {name} must be > 0 (it is fitted in logarithms), got "
                                 f"{a[i]:g} at point {i}")
        if name in errors and np.any(a < 0):
            i = int(np.flatnonzero(a < 0)[0])
            raise ParameterError(f"{fit}: the standard errors {name} must be >= 0, got "
                                 f"{a[i]:g} at point {i}")
    return arrays


@functools.lru_cache(maxsize=16)
def _ramp(Delta: float, lam: float, Omega: float, n: int):
    """The well along the ramp ``0 <= L < L_0`` on a grid graded towards the saddle node
    (where the barrier closes like ``(L_0 - L)^{3/2}``)."""
    sn = saddle_node(Delta=Delta, lam=lam, Omega=Omega)
    s = np.linspace(0, 1, n)
    L = sn.L0 * (1 - (1 - s)**3)[:-1]
    rows = np.array([barrier_at(float(Li), Delta=Delta, lam=lam, Omega=Omega) for Li in L])
    F = eq4("numpy").spring_force(rows[:, 0], L, Delta, 2 * math.pi / lam, Omega)
    return L, F, rows[:, 2], rows[:, 3], rows[:, 4], float(sn.L0), float(sn.static_force)


_DELTAS = np.logspace(-6, 4, 301)


@functools.lru_cache(maxsize=1)
def _mm_table():
    return np.log([melnikov_meshkov_factor(float(d)) for d in _DELTAS])


def _mm(delta):
    """Mel'nikov-Meshkov ``A(delta)`` interpolated in log-log (exact limits outside)."""
    d = np.clip(np.asarray(delta, float), _DELTAS[0], _DELTAS[-1])
    return np.exp(np.interp(np.log(d), np.log(_DELTAS), _mm_table()))


@dataclass(frozen=True)
class SlipForce:
    """Mean and spread of the thermally activated slip force at ``(v, kT)``.

    Attributes
    ----------
    mean, std : float
        ``<F>`` and the standard deviation of the slip force.
    static : float
        The athermal slip force ``F_c``.
    v, kT : float
    advance : float
        ``L_0 - <L_slip>``: how much earlier than the athermal slider the stage position
        at the slip is (the barrier closes like ``(L_0 - L)^{3/2}``, so this quantity
        follows the creep law ``~ (T ln(v_c/v))^{2/3}`` for any ``eta``; the spring force
        ``Omega^2 (L - x_w)`` has a square-root cusp at the saddle node and peaks at
        ``Delta`` at ``x_w = lam/4`` before it, so ``F_c - <F>`` follows it only for
        ``eta = Delta k/Omega^2 >> 1`` well inside the window).
    """

    mean: float
    std: float
    static: float
    v: float
    kT: float
    advance: float


def slip_force(v: float, kT: float, *, mu: float, Delta: float, lam: float = 1.0,
               Omega: float = 1.0, n: int = 4000) -> SlipForce:
    """The mean slip force of the CDC pulled at ``v`` with ``kT = D/mu``.

    Raises
    ------
    kbm.errors.ParameterError
        ``v``, ``kT`` or ``mu`` not positive, or no stick-slip (``Delta k <= Omega^2``).
    """
    for name, val in (("v", v), ("kT", kT), ("mu", mu)):
        if not (math.isfinite(val) and val > 0):
            raise ParameterError(f"{name} must be a positive number, got {val}")
    L, F, Eb, ww, I, L0, Fc = _ramp(float(Delta), float(lam), float(Omega), int(n))
    r = _mm(mu * I / kT) * ww / (2 * math.pi) * np.exp(-Eb / kT)
    # survival by the trapezoid rule in L
    cum = np.concatenate([[0.0], np.cumsum(0.5 * (r[1:] + r[:-1]) * np.diff(L))]) / v
    S = np.exp(-cum)
    Fx = np.append(F, Fc)
    Sx = np.append(S, 0.0)
    dP = -np.diff(Sx)                      # probability of slipping in each interval
    Fm = 0.5 * (Fx[1:] + Fx[:-1])
    mean = float(np.sum(dP * Fm))
    var = float(np.sum(dP * (Fm - mean)**2))
    Lx = np.append(L, L0)
    Ls = float(np.sum(dP * 0.5 * (Lx[1:] + Lx[:-1])))
    return SlipForce(mean, math.sqrt(max(var, 0.0)), float(Fc), float(v), float(kT),
                     float(L0 - Ls))


@dataclass(frozen=True)
class CreepFit:
    """The creep law ``F_c - <F> = C(T) |ln(v/v_c(T))|^b``, ``C(T) = c T^a``.

    Attributes
    ----------
    a, a_err : float
        The temperature exponent (Sang et al.: 2/3) from ``ln C`` against ``ln T``, with
        ``C(T)`` refitted at the common ``b``; ``a_err`` includes the error ``b`` passes
        on to every ``C(T)`` (:func:`fit_creep`).
    b, b_err : float
        The velocity exponent (2/3): the mean of the per-temperature fits and its
        standard error (their spread over sqrt(n)).
    b_each : tuple of float
        ``b`` at each temperature.
    c : float
    v_c : tuple of float
        ``v_c(T)`` at each temperature.
    rms : float
        Largest root-mean-square residual of ``ln(F_c - <F>)`` over the temperatures.
    points : int
    """

    a: float
    a_err: float
    b: float
    b_err: float
    b_each: tuple
    c: float
    v_c: tuple
    rms: float
    points: int


def _creep_model(lv, lnC, b, lnvc):
    """``ln(F_c - F) = ln C + b ln|ln v - ln v_c|`` (Sang et al.)."""
    return lnC + b * np.log(np.abs(lv - lnvc))


def _temperature_law(v, kT, F, Fc: float, temps, b: float) -> tuple[float, float, float]:
    """``(a, ln c, a's standard error from the line's residuals)``: ``ln C(T)`` refitted at
    the common ``b`` (``C`` and ``v_c`` trade off against each other when ``b`` is free),
    then the straight line ``ln C = ln c + a ln T`` (its error NaN with two temperatures)."""
    lnC = []
    for T in temps:
        m = kT == T
        lv, y = np.log(v[m]), np.log(Fc - F[m])
        p, _ = curve_fit(lambda z, c0, lvc: _creep_model(z, c0, b, lvc), lv, y,
                         p0=(0.0, float(np.max(lv)) + 2), maxfev=20000)
        lnC.append(p[0])
    if len(temps) > 2:
        (a, lnc), cov = np.polyfit(np.log(temps), lnC, 1, cov=True)
        return float(a), float(lnc), float(math.sqrt(cov[0, 0]))
    a, lnc = np.polyfit(np.log(temps), lnC, 1)
    return float(a), float(lnc), math.nan


def fit_creep(v, kT, F, Fc: float) -> CreepFit:
    """Fit the creep law of Sang et al. (PRL 87, 174301) to slip forces ``F(v_i, kT_i)``.

    At each temperature ``ln(F_c - F) = ln C + b ln|ln v - ln v_c|`` is fitted by least
    squares (three parameters, at least four velocities); then ``C`` is refitted at the
    mean ``b`` and ``ln C = ln c + a ln T`` fitted by a straight line.  Every fit is
    unweighted (the points' standard errors are not taken): ``b_err`` is the spread of the
    per-temperature ``b`` over ``sqrt(n)``; ``a_err`` adds in quadrature the straight line's
    standard error from its residuals (NaN with two temperatures) and ``|da/db| b_err``, the
    error every ``ln C`` takes from the common ``b`` (without it, on seeded data of the law,
    ``(a - 2/3)/a_err`` had a spread of 3 instead of 1).
    Give only points in the creep window (``F_c - F`` small against ``F_c`` but above the
    athermal regime ``v > v_c``).

    Raises
    ------
    kbm.errors.ParameterError
        Fewer than two temperatures or four velocities at one of them; columns of different
        lengths, not finite, ``v`` or ``kT`` not positive; a force not below ``Fc``.
    """
    v, kT, F = law_points("fit_creep", {"v": v, "kT": kT, "F": F}, positive=("v", "kT"))
    if not math.isfinite(Fc):
        raise ParameterError(f"fit_creep: the static force Fc must be a finite number, got {Fc}")
    if not np.all(F < Fc):
        i = int(np.argmax(F))
        raise ParameterError(f"fit_creep: every slip force F must be below the static force "
                             f"Fc = {Fc:g} (the law is fitted in ln(Fc - F)), got F = {F[i]:g} "
                             f"at point {i}: give only points in the creep window")
    temps = np.unique(kT)
    if len(temps) < 2:
        raise ParameterError("fit_creep needs slip forces at two temperatures at least")

    model = _creep_model
    lnC, bs, vcs, rms = [], [], [], []
    for T in temps:
        m = kT == T
        if np.count_nonzero(m) < 4:
            raise ParameterError(f"fit_creep needs four velocities at least at kT = {T}")
        lv, y = np.log(v[m]), np.log(Fc - F[m])
        p, _ = curve_fit(model, lv, y, p0=(0.0, 2 / 3, float(np.max(lv)) + 2), maxfev=20000)
        lnC.append(p[0])
        bs.append(p[1])
        vcs.append(math.exp(p[2]))
        rms.append(float(np.sqrt(np.mean((y - model(lv, *p))**2))))
    b = float(np.mean(bs))
    b_err = float(np.std(bs, ddof=1) / math.sqrt(len(bs)))  # two temperatures at least
    a, lnc, a_line = _temperature_law(v, kT, F, Fc, temps, b)
    # every ln C(T) is refitted at the one estimated b, so b's error shifts them together
    # and is no residual of the line: propagated (delta method, da/db by central difference)
    db = max(b_err, 1e-6 * abs(b), 1e-12)
    dadb = (_temperature_law(v, kT, F, Fc, temps, b + db)[0]
            - _temperature_law(v, kT, F, Fc, temps, b - db)[0]) / (2 * db)
    a_err = math.sqrt(a_line**2 + (dadb * b_err)**2)
    return CreepFit(float(a), float(a_err), b, b_err, tuple(map(float, bs)),
                    float(math.exp(lnc)), tuple(vcs), float(max(rms)), int(len(F)))
