"""Limit cycles by successive approximation of the energy along the cycle.

On a cycle of ``x'' = -g(x) + mu h(x, x')`` the energy ``E = v**2/2 + G(x)``
obeys ``dE/dx = mu h(x, v)`` on each branch.  The cycle is parametrised by
``x = c - r cos s``, ``0 <= s < 2 pi`` (``s`` in ``(0, pi)`` the upper branch from
``x- = c - r`` to ``x+ = c + r``, ``(pi, 2 pi)`` the lower one), and its energy is
written ``E(s) = eps + phi(s)`` with ``phi(0) = 0``, so ``eps = G(x-)``.  Then

``v(s) = sign(sin s) sqrt(2 (eps + phi(s) - G(x(s))))``, ``dt = ds/w``,
``w = |v|/(r |sin s|)``,

and on the true cycle ``phi' = mu h(x, v) r sin s``.  Since ``phi'`` vanishes at
``s = 0, pi``, ``eps + phi - G(x(s))`` vanishes to second order at both turning
points whenever ``G(x-) = eps`` and ``G(x+) = eps + phi(pi)``: ``w`` is a smooth
positive periodic function and every orbit integral has a smooth periodic
integrand (the trapezoid rule converges spectrally, ``phi`` is integrated as a
Fourier series).  The iteration alternates

* the closure (a generalised energy balance): with ``phi`` fixed, the level
  ``eps`` (hence ``x-``, ``x+``) making the energy gain ``R = oint h v dt``
  over the closed curve vanish; for ``phi = 0`` this is ``Gamma(eps) = 0``;
* the integration ``phi_new(s) = mu int_0^s h(x, v) r sin s' ds'`` along it.

The square root is never expanded in ``mu``: near a separatrix, where the
period ``T(E)`` has a logarithmic singularity, the curve keeps the exact
dependence of the time on the energy's swing.  ``n`` integrations make the
energy along the cycle correct to ``O(mu**(n+1))``; the fixed point is the true
cycle.  The non-trivial Floquet multiplier is Liouville's
``exp(mu oint h_v(x, v) dt)`` on the computed curve (``exp(mu dGamma/dE)`` for
``phi = 0``).  When ``E(s)`` falls to ``G(x(s))`` inside the path (the curve
cannot pass a saddle) the iteration stops and says so.

Design notes.  The level is solved for, not iterated: with ``v`` taken from the
previous iterate the energy gain does not depend on the new turning points (``v``
vanishes there), so a plain Picard step leaves the level undetermined; the
closure restores the energy balance's dependence ``dGamma/dE``.  ``phi`` is
carried from one iterate to the next as a function of ``s``, i.e. of the
relative position ``(x - c)/r`` on each branch.  For ``h`` odd in ``x'`` the
scheme keeps the symmetry ``(t, x', mu) -> (-t, -x', -mu)``, so the period
(even in ``mu``) gains two orders every other integration.

References
----------
S. Coppola and R. H. Rand, Acta Mechanica 81 (1990) (the energy balance the
iteration starts from).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from .portrait import Annulus

__all__ = ["PositionCycle", "position_cycle", "PositionError"]


class PositionError(RuntimeError):
    """An iterate of the position scheme does not define a closed curve."""


@dataclass(frozen=True, eq=False)
class PositionCycle:
    """A cycle ``E(s) = eps + phi(s)`` of the position scheme after ``integrations`` steps.

    Attributes
    ----------
    energy : float
        ``eps = G(x-)``, the energy at the left turning point.
    mean_energy : float
        The time average of ``E`` over the cycle.
    x_min, x_max : float
        The turning points.
    period : float
    floquet_multiplier : float
        ``exp(mu oint h_v dt)`` on the curve.
    harmonics : numpy.ndarray
        Complex ``c_m``, ``m = 0..15``, of ``x(t)``, time 0 at ``x_max``.
    integrations : int
    nodes : int
        Trapezoid nodes in ``s``.
    error : float
        Relative change of the period on halving the nodes.
    energy_swing : float
        ``max E(s) - min E(s)``.
    saddle_gap : float
        ``min (E - G(x)) / max (E - G(x))`` away from the turning points: how
        close the curve comes to stopping at a saddle.
    levels : tuple of tuple
        ``(eps, slope)`` per iterate: the level closing it and the slope of the energy
        gain there (or None); the warm start (``guesses``) of a neighbouring ``mu``.
    """

    energy: float
    mean_energy: float
    x_min: float
    x_max: float
    period: float
    floquet_multiplier: float
    harmonics: np.ndarray
    integrations: int
    nodes: int
    error: float
    energy_swing: float
    saddle_gap: float
    levels: tuple = ()


class _Curve:
    """The closed curve of level ``eps`` for a fixed ``phi`` on ``n`` midpoint nodes."""

    def __init__(self, annulus, fun, mu, phi_c, eps):
        n = 2 * (len(phi_c) - 1)
        self.s = (np.arange(n) + 0.5) * 2 * np.pi / n
        _, _, G, h = fun
        phi, phi_pi = _phi_values(phi_c, self.s)
        lo_out, lo_in, hi_in, hi_out = annulus.bounds
        xm = annulus._solve1(eps, lo_out, lo_in, increasing=False)
        xp = annulus._solve1(eps + phi_pi, hi_in, hi_out, increasing=True)
        if not (abs(G(np.array([xm]))[0] - eps) <= 1e-9 * (1 + abs(eps))
                and abs(G(np.array([xp]))[0] - eps - phi_pi) <= 1e-9 * (1 + abs(eps))):
            raise PositionError(f"no turning point at energies {eps:.6g}, {eps + phi_pi:.6g} "
                                f"in annulus {annulus.label!r}")
        self.c, self.r = 0.5 * (xp + xm), 0.5 * (xp - xm)
        self.x = self.c - self.r * np.cos(self.s)
        sn = np.sin(self.s)
        D = eps + phi - G(self.x)
        inner = np.abs(sn) > 0.3
        self.gap = float(np.min(D[inner]) / np.max(D)) if np.any(inner) else 1.0
        bad = (inner & (D <= 0)) | (D < -1e-9 * np.max(D))   # rounding only near x-, x+
        if np.any(bad):
            j = int(np.argmin(np.where(bad, D, np.inf)))
            raise PositionError(
                f"the energy E(s) = {eps + phi[j]:.6g} falls below G(x) at x = {self.x[j]:.6g}: "
                "the approximate cycle cannot pass the saddle there")
        D = np.maximum(D, np.finfo(float).tiny)
        self.v = np.sign(sn) * np.sqrt(2 * D)
        self.w = np.abs(self.v) / (self.r * np.abs(sn))
        self.ds = 2 * np.pi / n
        self.eps, self.phi, self.mu, self.h = eps, phi, mu, h
        self.hs = h(self.x, self.v) * self.r * sn       # dE/ds / mu

    def gain(self) -> float:
        """``oint h v dt``: the energy gain per turn over ``mu``."""
        return float(np.sum(self.hs) * self.ds)

    def integrate(self) -> np.ndarray:
        """Fourier coefficients (rfft convention, cosine-sine at nodes) of the new ``phi``."""
        return _integral_coeffs(self.mu * self.hs, self.s)

    @property
    def period(self) -> float:
        return float(np.sum(1 / self.w) * self.ds)


def _integral_coeffs(f, s):
    """Coefficients ``b_k`` with ``int_0^s f = sum_k Re(b_k (e^{iks} - 1))`` (mean dropped)."""
    n = len(f)
    k = np.arange(n // 2 + 1)
    ck = np.fft.rfft(f) / n * np.exp(-1j * k * s[0])
    ck[1:] *= 2.0
    if n % 2 == 0:
        ck[-1] = 0.0
    b = np.zeros_like(ck)
    b[1:] = ck[1:] / (1j * k[1:])
    return b


def _phi_values(b, s):
    """``phi`` at the nodes ``s`` and at ``pi`` from its coefficients (resampled to ``len(s)``)."""
    n = len(s)
    m = n // 2 + 1
    bb = np.zeros(m, complex)
    kk = min(m - 1, len(b))           # the Nyquist mode stays zero
    bb[:kk] = b[:kk]
    k = np.arange(m)
    X = 0.5 * bb * np.exp(1j * k * s[0])
    vals = np.fft.irfft(X, n) * n - np.real(np.sum(bb))
    at_pi = float(np.real(np.sum(bb * ((-1.0) ** k - 1))))
    return vals, at_pi


def _level(annulus, fun, mu, phi_c, eps0, scale, slope=None):
    """The level ``eps`` closing the curve for ``phi`` (the root of the gain nearest ``eps0``,
    skipping levels whose curve stops at a saddle) and the gain's slope there (or None)."""
    def R(e):
        try:
            return _Curve(annulus, fun, mu, phi_c, e).gain(), ""
        except PositionError as err:
            return np.nan, str(err)

    r0, why = R(eps0)
    if r0 == 0:
        return eps0, slope
    if np.isfinite(r0):
        found = _secant(R, eps0, r0, scale, slope)
        if found is not None:
            return found
    prev = dict.fromkeys((-1, 1), (eps0, r0) if np.isfinite(r0) else None)
    step = 1e-3 * scale
    while step <= 10 * scale:
        for side in (-1, 1):
            e = eps0 + side * step
            r, err = R(e)
            if not np.isfinite(r):
                why = why or err
                continue
            p = prev[side]
            if p is not None and np.sign(r) != np.sign(p[1]):
                lo, hi = sorted((p[0], e))
                return brentq(lambda z: R(z)[0], lo, hi, xtol=1e-15 * max(1.0, abs(eps0)),
                              rtol=1e-15), None
            prev[side] = (e, r)
        step *= 1.6
    raise PositionError(why or f"no level near {eps0:.6g} closes the curve (the energy gain "
                        "keeps one sign)")


def _secant(R, e0, r0, scale, slope=None):
    """``(root, slope)`` of the gain by secants from ``e0`` (first step: Newton with ``slope``
    if given); None if not settled in 12 steps within ``10 scale`` or a curve is open."""
    tiny = 1e-15 * max(1.0, abs(e0))
    if slope is not None and np.isfinite(slope) and slope != 0:
        d = -r0 / slope
        if abs(d) <= tiny:
            return e0, slope
        e1 = e0 + d
    else:
        e1 = e0 + max(1e-7 * scale, 1e3 * tiny)
    r1 = R(e1)[0]
    for _ in range(12):
        if not np.isfinite(r1) or r1 == r0:
            return None
        slope = (r1 - r0) / (e1 - e0)
        e2 = e1 - r1 / slope
        if not abs(e2 - e0) <= 10 * scale:
            return None
        if abs(e2 - e1) <= tiny:
            return e2, slope
        e0, r0, e1 = e1, r1, e2
        r1 = R(e1)[0]
        if r1 == 0:
            return e1, slope
    return None


def _run(annulus, fun, hv, mu, E_star, integrations, n, scale, guesses=None):
    phi_c = np.zeros(n // 2 + 1, complex)
    eps = E_star
    levels = []
    for k in range(integrations + 1):
        start, slope = (guesses[k] if guesses is not None and k < len(guesses)
                        else (eps, None))
        try:
            eps, slope = _level(annulus, fun, mu, phi_c, start, scale, slope)
            levels.append((eps, slope))
        except PositionError as err:
            raise PositionError(f"no closed curve after {k} integration(s): {err}") from None
        cur = _Curve(annulus, fun, mu, phi_c, eps)
        if k < integrations:
            phi_c = cur.integrate()
    mult = float(np.exp(mu * np.sum(hv(cur.x, cur.v) / cur.w) * cur.ds))
    return cur, mult, tuple(levels)


def _harmonics(cur, m_max=16):
    """``c_m`` of ``x(t)`` on the curve, time 0 at ``x_max`` (``s = pi``)."""
    s, ds = cur.s, cur.ds
    inv_w = 1 / cur.w
    T = float(np.sum(inv_w) * ds)
    b = _integral_coeffs(inv_w - T / (2 * np.pi), s)
    osc, osc_pi = _phi_values(b, s)
    t = T * s / (2 * np.pi) + osc - (0.5 * T + osc_pi)
    omega = 2 * np.pi / T
    z = np.exp(-1j * omega * t)         # e^{-i m omega t} = z**m, by repeated products
    f = (cur.x * inv_w).astype(complex)
    out = np.empty(m_max, complex)
    for m in range(m_max):
        out[m] = np.sum(f)
        f *= z
    return out * ds / T


def position_cycle(annulus: Annulus, functions, hv, mu: float, energy: float,
                   integrations: int, *, n_start: int = 128, n_max: int = 1 << 14,
                   tol: float = 1e-11, guesses=None) -> PositionCycle:
    """The cycle of the position scheme after ``integrations`` integrations of ``phi``.

    Parameters
    ----------
    annulus : Annulus
        The period annulus of the energy-balance root.
    functions : tuple
        ``(g, g', G, h)`` from :meth:`kbm.model.conservative.ConservativeSplit.numpy_functions`.
    hv : callable
        ``dh/dv(x, v)``, vectorised.
    mu : float
    energy : float
        The energy-balance root ``E*`` (the start of the level search).
    integrations : int
        ``0`` is the energy balance itself; each one gains an order in ``mu``.
    n_start, n_max : int
        First and largest number of nodes in ``s`` (doubled until the period
        changes by less than ``tol``).
    tol : float
        Relative tolerance of the period.
    guesses : sequence of tuple, optional
        ``(level, slope)`` guesses of the ``integrations + 1`` levels (``levels`` of a
        neighbouring ``mu``'s cycle); by default each level starts from the last.

    Returns
    -------
    PositionCycle

    Raises
    ------
    PositionError
        If an iterate's energy falls below ``G`` inside the path, or no level
        closes the curve.

    Examples
    --------
    Van der Pol (``h = (1 - x**2) x'``) at ``mu = 0.1``; shooting gives
    ``T = 6.287111``, ``max x = 2.000104``:

    >>> from kbm.model.conservative import split_conservative
    >>> from numerics.energy import phase_portrait
    >>> s = split_conservative("vdp", {"mu": 0.1})
    >>> (a,) = phase_portrait(s).annuli
    >>> c = position_cycle(a, s.numpy_functions(), lambda x, v: 1 - x**2, 0.1, 2.0, 2)
    >>> round(c.period, 5), round(c.x_max, 6)
    (6.28708, 2.000104)
    """
    scale = max(abs(energy - annulus.energy_min), 1e-12)
    if annulus.bounded:
        scale = min(scale, annulus.energy_max - energy)
    n, prev, err = n_start, None, np.inf
    while True:
        cur, mult, levels = _run(annulus, functions, hv, mu, energy, integrations, n, scale,
                                 guesses)
        if prev is not None:
            err = abs(cur.period - prev) / cur.period
            if err <= tol or 2 * n > n_max:
                break
        prev, n = cur.period, 2 * n
        guesses = levels            # the next resolution starts from these levels
    E = cur.eps + cur.phi
    xm, xp = cur.c - cur.r, cur.c + cur.r
    mean_E = float(np.sum(E / cur.w) * cur.ds) / cur.period
    return PositionCycle(float(cur.eps), mean_E, float(xm), float(xp), cur.period, mult,
                         _harmonics(cur), int(integrations), n, float(err),
                         float(np.max(E) - np.min(E)), cur.gap, levels)
