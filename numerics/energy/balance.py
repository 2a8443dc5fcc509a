"""First-order strongly nonlinear averaging: the energy balance ``Gamma(E) = 0``.

On the conservative orbit of energy ``E`` of ``x'' + g(x) = 0`` the energy of
``x'' = -g(x) + mu h(x, x')`` changes by ``mu Gamma(E)`` per period, with

``Gamma(E) = oint h(x, x') x' dt = int_{x-}^{x+} [h(x, v+) - h(x, -v+)] dx``

(the paper's eq. (10) read as a cycle condition).  Averaging gives
``dE/dt = mu Gamma(E)/T(E)``; its roots ``E*`` are the limit cycles to first
order, stable when ``mu dGamma/dE(E*) < 0``, with the non-trivial Floquet
multiplier ``exp(mu dGamma/dE(E*))`` (the averaged equation linearised over one
period).  The slope is itself a smooth orbit integral,

``dGamma/dE = int_{x-}^{x+} [h_v(x, v+) + h_v(x, -v+)] / v+ dx``.

For linear ``g = omega0**2 x`` this is exactly classical KBM at order one
(``E = omega0**2 a**2/2``, ``Gamma/T = omega0**2 a A_1(a)``).

References
----------
S. Coppola and R. H. Rand, Acta Mechanica 81 (1990); N. N. Bogoliubov and
Y. A. Mitropolsky, *Asymptotic Methods*, chapter on nearly conservative systems.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


from .portrait import Annulus, Portrait

__all__ = ["BalanceCycle", "balance_cycles", "gamma_function", "harmonics"]


@dataclass(frozen=True, eq=False)
class BalanceCycle:
    """A root ``E*`` of ``Gamma`` and the cycle it predicts (first order).

    Attributes
    ----------
    annulus : Annulus
    energy : float
        ``E*``.
    dgamma_dE : float
        ``dGamma/dE(E*)``.
    period : float
        ``T(E*)``.
    stable : bool
        ``mu dGamma/dE < 0``.
    floquet_multiplier : float
        ``exp(mu dGamma/dE(E*))``.
    x_min, x_max : float
        The turning points ``x-(E*)``, ``x+(E*)``.
    harmonics : numpy.ndarray
        Complex ``c_m`` of ``x = sum_m c_m e^{i m omega t}``, ``m = 0..15``, time 0 at ``x+``.
    error : float
        Estimated relative error of the orbit quadratures.
    period_sensitivity : float
        ``mu oint |h v| dt |dT/dE| / T``: the relative change of the period across
        the energy's swing in one cycle.  The expansion in ``mu`` assumes it small;
        above about 1 (near a separatrix, or an orbit crawling through a nearly flat
        stretch of ``G``) the higher orders stop improving on the first.
    separatrix_margin : float
        Distance of ``E*`` to the nearest separatrix energy bounding the annulus,
        over ``mu oint |h v| dt`` (the scale of the energy's swing over one
        cycle); ``inf`` without bounding separatrix.  Below about 1 the cycle's
        energy swings across the separatrix within a period and the expansion in
        ``mu`` beyond first order is not to be trusted.
    """

    annulus: Annulus
    energy: float
    dgamma_dE: float
    period: float
    stable: bool
    floquet_multiplier: float
    x_min: float
    x_max: float
    harmonics: np.ndarray
    error: float
    separatrix_margin: float = float("inf")
    period_sensitivity: float = 0.0

    @property
    def amplitude_first_harmonic(self) -> float:
        """``2 |c_1|``."""
        return float(2 * abs(self.harmonics[1]))


def gamma_function(annulus: Annulus, hv=None, *, tol: float = 1e-12):
    """``E -> (Gamma(E), dGamma/dE(E), T(E), error)`` on one annulus, vectorised.

    Parameters
    ----------
    annulus : Annulus
    hv : callable, optional
        ``dh/dv(x, v)``; without it the slope is not computed (returned as NaN).
    tol : float
        Relative tolerance of the quadratures.
    """
    h = annulus._fun[3]

    def fun(E):
        funs = [lambda x, v, sq: 2.0 / sq,
                lambda x, v, sq: (h(x, v) - h(x, -v)) * v / sq]
        if hv is not None:
            funs.append(lambda x, v, sq: (hv(x, v) + hv(x, -v)) / sq)
        vals, err, _, _ = annulus.orbit_integrals(E, funs, tol=tol)
        slope = vals[2] if hv is not None else np.full_like(vals[0], np.nan)
        return vals[1], slope, vals[0], err
    return fun


def _scan_energies(a: Annulus, n: int, energy_max: float) -> tuple[np.ndarray, bool]:
    lo = a.energy_min
    if a.bounded:
        u = (np.arange(n) + 0.5) / n
        return lo + (a.energy_max - lo) * (1 - np.cos(np.pi * u)) / 2, True
    top = max(energy_max, 10 * abs(lo) + 10)
    span = top - lo
    return lo + np.geomspace(1e-8 * span, span, n), False


def harmonics(annulus: Annulus, E, n_harmonics: int = 16, *, n_nodes: int = 512) -> np.ndarray:
    """Fourier coefficients ``c_m`` of ``x(t)`` on the orbits of energies ``E`` (time 0 at ``x+``).

    With ``x = c - r cos s`` the time from ``x-`` is ``t(s) = int_0^s ds'/sq``; the
    cosine series of the even periodic ``1/sq`` (a DCT of the midpoint samples)
    integrates exactly, and ``c_m = (-1)**m (2/T) int_0^pi x cos(m omega t(s)) ds/sq``
    has a smooth even periodic integrand: the midpoint rule is spectrally accurate.

    Returns
    -------
    numpy.ndarray
        Complex (real-valued) array of shape ``(len(E), n_harmonics)``.
    """
    from scipy.fft import dct

    G = annulus._fun[2]
    E = np.atleast_1d(np.asarray(E, float))
    xm, xp = annulus.turning_points(E)
    c, r = 0.5 * (xp + xm), 0.5 * (xp - xm)
    n = n_nodes
    s = (np.arange(n) + 0.5) * np.pi / n
    xs = c[:, None] - r[:, None] * np.cos(s)
    rs = r[:, None] * np.sin(s)
    inv_sq = 1 / np.sqrt(2 * np.maximum((E[:, None] - G(xs)) / rs**2, np.finfo(float).tiny))
    a = dct(inv_sq, type=2, axis=-1) / n
    a[:, 0] /= 2
    k = np.arange(1, n)
    t = a[:, :1] * s + (a[:, 1:] / k) @ np.sin(np.outer(k, s))
    T = 2 * np.pi * a[:, 0]
    omega = 2 * np.pi / T
    m = np.arange(n_harmonics)
    w = np.pi / n
    cm = (2 / T)[:, None] * w * np.einsum("es,ems->em", xs * inv_sq,
                                          np.cos(m[None, :, None] * (omega[:, None] * t)[:, None, :]))
    cm[:, 0] /= 2
    return (cm * (-1.0) ** m).astype(complex)


def _newton(fun, lo, hi, sign_lo, max_iter: int = 40) -> np.ndarray:
    """Roots of ``Gamma`` in the brackets ``(lo, hi)``: Newton with the orbit-integral
    slope, bisection when a step leaves the bracket (vectorised over the brackets)."""
    lo, hi = lo.astype(float), hi.astype(float)
    E = 0.5 * (lo + hi)
    for k in range(max_iter):
        gam, slope, _, err = fun(E)
        neg_side = np.sign(gam) == sign_lo        # the root lies above E
        lo = np.where(neg_side, E, lo)
        hi = np.where(neg_side, hi, E)
        with np.errstate(divide="ignore", invalid="ignore"):
            step = E - gam / slope
        ok = (step >= lo) & (step <= hi)
        new = np.where(ok, step, 0.5 * (lo + hi))
        small = np.abs(new - E) <= 1e-14 * np.maximum(1.0, np.abs(E))
        E = new
        if np.all(small) or np.all(hi - lo <= 1e-14 * np.maximum(1.0, np.abs(hi))):
            break
    return E


def _hidden_pairs(a: Annulus, E: np.ndarray, q: np.ndarray, well: bool, tol: float):
    """Pairs of roots between two scan energies: at every sampled extremum of ``q`` that
    turns towards zero without a sign change (``|q_i| <= |q_{i+-1}|``, same signs), the
    extremum is located by bounded minimisation of ``sign * q`` (``xatol`` 1e-13 of the
    energy scale); where it has crossed zero, the two brackets on either side are
    returned as ``(lo, extremum, hi, sign at lo)``.  A pair of roots closer than the scan
    spacing is found down to a separation where ``q`` at its extremum is below the
    quadrature's resolution (``~tol`` relative; about 1e-6 of the energy for a quadratic
    extremum): near the fold of ``(-nu + x^2 - x^4) x'`` at ``nu = 0.12499`` the roots
    0.0089 apart in ``a`` were lost by the 96-point scan (34 % spacing) and are found here."""
    from scipy.optimize import minimize_scalar

    if len(E) < 3:
        return []
    sgn = np.sign(q)
    g = gamma_function(a, tol=tol)
    out = []
    for i in range(1, len(E) - 1):
        if not (sgn[i - 1] == sgn[i] == sgn[i + 1] != 0):
            continue
        if not (abs(q[i]) <= abs(q[i - 1]) and abs(q[i]) <= abs(q[i + 1])):
            continue
        sign = sgn[i]
        lo, hi = E[i - 1], E[i + 1]

        def f(e, sign=sign):
            val = g(np.array([e]))[0][0]
            return sign * (val / (e - a.energy_min) if well else val)

        res = minimize_scalar(f, bounds=(lo, hi), method="bounded",
                              options={"xatol": 1e-13 * max(1.0, abs(hi))})
        if res.fun < 0:
            out.append((lo, float(res.x), hi, sign))
    return out


def balance_cycles(portrait: Portrait, *, n_scan: int = 96, energy_max: float | None = None,
                   n_theta: int = 256, tol: float = 1e-12) -> tuple[BalanceCycle, ...]:
    """Every root of ``Gamma(E)`` on every annulus of ``portrait``, sorted by energy.

    Parameters
    ----------
    portrait : Portrait
        From :func:`numerics.energy.portrait.phase_portrait`.
    n_scan : int
        Energies per annulus where the sign of ``Gamma`` (of ``Gamma/(E - E_c)``
        in a well, which vanishes at its center ``E_c``) is scanned; roots
        closer together than the scan spacing can be missed.  Bounded annuli are
        scanned on Chebyshev-clustered energies, the outer one geometrically.
    energy_max : float, optional
        Top of the scan of the outer annulus (default ``1e4 (1 + |E_lo|)``).
    n_theta : int
        Samples per period of the orbit for the harmonics.
    tol : float
        Relative tolerance of the quadratures.

    Returns
    -------
    tuple of BalanceCycle
    """
    split = portrait.split
    mu = split.mu
    hv = split.h_velocity_function()

    def hvf(x, v):
        return np.broadcast_to(np.asarray(hv(x, v), float), np.broadcast(x, v).shape)

    split_h = portrait.functions[3]
    out = []
    for a in portrait.annuli:
        fun = gamma_function(a, hvf, tol=tol)
        top = energy_max if energy_max is not None else 1e4 * (1 + abs(a.energy_min))
        E, _ = _scan_energies(a, n_scan, top)
        gam = gamma_function(a, tol=1e-7)(E)[0]
        well = len(a.wells) == 1
        s = np.sign(gam / (E - a.energy_min) if well else gam)
        exact = E[s == 0]
        idx = np.nonzero(s[:-1] * s[1:] < 0)[0]
        lo_b, hi_b, sg = list(E[idx]), list(E[idx + 1]), list(s[idx])
        q = gam / (E - a.energy_min) if well else gam
        for lo_p, mid, hi_p, sign in _hidden_pairs(a, E, q, well, tol):
            lo_b += [lo_p, mid]
            hi_b += [mid, hi_p]
            sg += [sign, -sign]
        R = (_newton(fun, np.array(lo_b), np.array(hi_b), np.array(sg)) if lo_b
             else np.zeros(0))
        R = np.sort(np.concatenate([exact, R]))
        if not len(R):
            continue
        _, slope, T, err = fun(R)
        xm, xp = a.turning_points(R)
        harm = harmonics(a, R, 16, n_nodes=n_theta)
        swing = a.orbit_integrals(R, [lambda x, v, sq: (np.abs(split_h(x, v)) + np.abs(
            split_h(x, -v))) * v / sq])[0][0] * abs(mu)
        seps = [e for e, is_sep in ((a.energy_min, len(a.wells) > 1),
                                    (a.energy_max, a.bounded)) if is_sep]
        dist = np.min([np.abs(R - e) for e in seps], axis=0) if seps else np.full(len(R), np.inf)
        margin = dist / np.maximum(swing, 1e-300)
        dE = 1e-5 * np.maximum(1.0, np.abs(R))
        dE = np.minimum(dE, 0.25 * (R - a.energy_min))
        if a.bounded:
            dE = np.minimum(dE, 0.25 * (a.energy_max - R))
        Tpm = a.period(np.concatenate([R - dE, R + dE]))
        sens = swing * np.abs(Tpm[len(R):] - Tpm[:len(R)]) / (2 * dE) / T
        for k, e in enumerate(R):
            out.append(BalanceCycle(
                annulus=a, energy=float(e), dgamma_dE=float(slope[k]), period=float(T[k]),
                stable=bool(mu * slope[k] < 0),
                floquet_multiplier=float(np.exp(mu * slope[k])), x_min=float(xm[k]),
                x_max=float(xp[k]), harmonics=harm[k], error=float(err[k]),
                separatrix_margin=float(margin[k]), period_sensitivity=float(sens[k])))
    out.sort(key=lambda c: (c.energy, c.x_max))
    return tuple(out)
