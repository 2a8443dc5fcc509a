"""The averaged line of a noisy self-excited oscillator, evaluated at numbers.

:mod:`kbm.noise.phase_diffusion` gives the averaged Ito equations of amplitude and phase,

``da = [A(a) + D/(2 omega0^2 a)] dt + (sqrt(D)/omega0) dW_1``,
``dphi = B(a) dt + (sqrt(D)/(omega0 a)) dW_2``,

and their linearisation about the stable cycle ``a*`` (Lax's ``D_eff = D_phi + g^2
D_a/lambda^2``).  Here they are evaluated at parameter values, and the averaged equations
are also solved without the linearisation: the amplitude is a one-dimensional diffusion
with the stationary density ``P(a) = a exp((2 omega0^2/D) int_0^a A)/Z`` and the phase
increments are ``int B(a) dt`` plus a martingale of variance rate ``D/(omega0^2 a^2)``,
independent of it.  The long-time phase diffusion is therefore (central limit theorem for
additive functionals of a one-dimensional diffusion; Pavliotis, *Stochastic Processes and
Applications* (2014), sec. 3.6)

``D_eff = (D/(2 omega0^2)) <1/a^2> + sigma^2/2``,
``sigma^2 = int 4 [int_0^a (B - <B>) P]^2/(s P) da``,  ``s = D/omega0^2``,

and the mean angular frequency is ``Omega = omega0 + <B>``, both averages over ``P``.  For
small ``D/mu`` they reduce to the linearised forms (a test checks it).  ``<1/a^2>`` diverges
logarithmically at ``a = 0``, where the phase is undefined and the averaging does not hold;
the integrals start where ``P`` has fallen to ``exp(-60)`` of its peak (for a limit cycle
that part of ``P`` carries nothing measurable).

At order 2 the line is also corrected through ``mu^2``: the small-noise linewidth ``D
<Z_v^2>`` of the phase response pulled back through the second-order near-identity
transform (``u_1``, ``u_2``, ``x'`` along the averaged flow to ``mu^2``, the rates to
``A_3``, ``B_3``; :func:`kbm.noise.phase_response.phase_response` of order 3), taken at the
cycle of ``A`` to ``A_3``, replaces Lax's ``D_eff`` as the scale of the stationary-density
line: ``D_eff(order 2) = D_eff(quadrature) * D <Z_v^2>/D_eff(Lax)``.  Its error against the
true cycle's (:mod:`numerics.spectrum.floquet`) is ``O(mu^3)`` (``O(mu^4)`` for ``F`` odd
in ``x'``: van der Pol's ``1/8 + 7 mu^2/256``, 1.7e-5 off at ``mu = 0.1``; before, with the
first-order transform, ``1/8 - 69 mu^2/512``, six times order 1's error).  A transcendental
``F`` (the SEDF), whose expansion stops at order 2, keeps the first-order transform, right to
``O(mu)``.  The order-2 width states its error against the true cycle
(:func:`numerics.spectrum.result.line_errors`).

The spectrum of ``x`` is a sum of lines at ``k Omega``: a Lorentzian of half width
``k^2 D_eff`` carrying the coherent power ``<r_k>^2/2`` of harmonic ``k`` (``x = sum_k
r_k(a) cos(k psi + theta_k)``, from :attr:`kbm.noise.phase_diffusion.PhaseDiffusion.displacement`)
and a pedestal of half width ``lambda + k^2 D_eff`` carrying ``var(r_k)/2`` (the amplitude
fluctuations, relaxing at ``lambda``).

The first-order linearised phase diffusion alone: :func:`cycle_phase_diffusion`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import sympy as sp

from kbm.errors import ModelError, ParameterError
from kbm.noise.phase_diffusion import phase_diffusion
from kbm.noise.stochastic import NOISE
from kbm.parameters.names import noise_intensity
from kbm.symbols import mu

from ..errors import NoCycleError
from ._evaluate import at as _at, fn as _fn, numbers as _numbers
from .density import response_cycle as _response_cycle, stationary_density

__all__ = ["Line", "LineTheory", "line_theory", "PhaseDiffusion",
           "cycle_phase_diffusion", "LINEWIDTH_NEED"]

_PSI = 512  # points in psi for <Z_v^2> (a trigonometric rational: spectral accuracy)

#: why a linewidth refuses ``D = 0`` (:func:`kbm.parameters.names.noise_intensity`)
LINEWIDTH_NEED = "a linewidth needs noise"


@dataclass(frozen=True)
class Line:
    """One spectral line of ``x``: harmonic ``k`` at ``omega``.

    Attributes
    ----------
    k : int
    omega : float
        Centre ``k Omega`` (angular).
    hwhm : float
        Half width at half maximum ``k^2 D_eff`` (angular).
    power : float
        Variance in the Lorentzian (coherent part).
    pedestal : float
        Variance in the amplitude-noise pedestal (half width ``lambda + k^2 D_eff``).
    """

    k: int
    omega: float
    hwhm: float
    power: float
    pedestal: float


@dataclass(frozen=True, eq=False)
class LineTheory:
    """The averaged line of a noisy self-excited oscillator at parameter values.

    Attributes
    ----------
    name : str
    order : int
    mu, D, omega0 : float
    amplitude : float
        The stable cycle ``a*`` of ``A(a) = 0``.
    relaxation, shear : float
        ``lambda = -A'(a*)`` and ``g = B'(a*)``.
    phase_diffusion : float
        ``D_phi = D/(2 omega0^2 a*^2)``.
    linewidth_linear, frequency_linear : float
        Lax's ``D_eff`` and ``omega0 + B(a*) +`` the noise-induced shift (linearised).
    linewidth, frequency : float
        ``D_eff`` and ``Omega`` from the stationary density (no linearisation).
    frequency_cycle : float
        ``omega0 + B(a*)``: the deterministic cycle's frequency at this order.
    small_noise : float
        ``D <Z_v^2>`` at the cycle (:func:`kbm.noise.phase_response.phase_response`): Lax's
        ``D_eff`` at order 1, right through ``mu^2`` at order 2 (through ``mu`` for a
        transcendental ``F``).
    mean_amplitude : float
        ``<a>`` over ``P``.
    lines : tuple of Line
    """

    name: str
    order: int
    mu: float
    D: float
    omega0: float
    amplitude: float
    relaxation: float
    shear: float
    phase_diffusion: float
    linewidth_linear: float
    frequency_linear: float
    linewidth: float
    frequency: float
    frequency_cycle: float
    mean_amplitude: float
    lines: tuple
    small_noise: float = float("nan")

    def __repr__(self) -> str:
        return (f"LineTheory({self.name}, mu={self.mu:g}, D={self.D:g}: a* = "
                f"{self.amplitude:.6g}, HWHM = {self.linewidth:.6g}, Omega = "
                f"{self.frequency:.8g})")

    @property
    def enhancement(self) -> float:
        """``1 + (g a*/lambda)^2``: how many times the shear widens the line."""
        return 1.0 + (self.shear * self.amplitude / self.relaxation) ** 2

    def psd(self, omega) -> np.ndarray:
        """The one-sided PSD of ``x`` (angular, integral = variance) on ``omega``."""
        w = np.asarray(omega, float)
        out = np.zeros_like(w)

        def lor(c, g):
            return g / math.pi * (1.0 / ((w - c) ** 2 + g * g) + 1.0 / ((w + c) ** 2 + g * g))

        for ln in self.lines:
            out += ln.power * lor(ln.omega, ln.hwhm)
            if ln.pedestal > 0:
                out += ln.pedestal * lor(ln.omega, self.relaxation + ln.hwhm)
        return out

    def as_dict(self) -> dict:
        """Plain numbers for JSON."""
        return {"amplitude": self.amplitude, "mean_amplitude": self.mean_amplitude,
                "relaxation": self.relaxation, "shear": self.shear,
                "phase_diffusion": self.phase_diffusion, "enhancement": self.enhancement,
                "linewidth_linear": self.linewidth_linear,
                "frequency_linear": self.frequency_linear,
                "frequency_cycle": self.frequency_cycle,
                "linewidth_small_noise": self.small_noise,
                "lines": [{"k": ln.k, "omega": ln.omega, "hwhm": ln.hwhm, "power": ln.power,
                           "pedestal": ln.pedestal} for ln in self.lines]}


def _stable_cycle(A, dA, a_max: float = 50.0) -> float:
    """The smallest positive root of ``A`` with ``A' < 0``."""
    from scipy.optimize import brentq

    grid = np.concatenate([np.linspace(1e-4, 1.0, 2001)[:-1], np.geomspace(1.0, a_max, 4000)])
    with np.errstate(all="ignore"):
        vals = np.asarray(A(grid, 0.0), float) * np.ones_like(grid)
    for i in range(grid.size - 1):
        if vals[i] > 0 >= vals[i + 1] and np.isfinite(vals[i] + vals[i + 1]):
            r = brentq(lambda s: float(A(s, 0.0)), grid[i], grid[i + 1], xtol=1e-14)
            if float(dA(r, 0.0)) < 0:
                return r
    raise NoCycleError("the averaged amplitude equation A(a) = 0 has no stable root a* > 0 "
                       f"(up to a = {a_max:g}): no limit cycle, so no line to speak of; give "
                       "a self-excited model or parameters with a stable cycle")


def _linear(model, params: Mapping[str, object], D: float, order: int) -> tuple:
    """The linearised line at the stable cycle ``a*`` (:func:`line_theory`,
    :func:`cycle_phase_diffusion`): ``(pd, subs, mu, omega0, A, B, a*, lambda, g, D_phi,
    D_eff, omega0 + B(a*))``, ``A`` and ``B`` as numpy functions of ``(a, psi)``."""
    from kbm.parameters.bound import bind

    bm = bind(model, {k: v for k, v in dict(params).items() if k != "D"})
    bm.require(what="the averaged line")
    fixed = dict(bm.values)
    m_val = float(fixed.pop("mu"))
    if not m_val > 0:
        raise ParameterError(f"mu = {m_val:g} must be > 0 for a self-excited cycle")
    pd = phase_diffusion(bm.model, order, fixed or None)
    subs = {**_numbers(fixed), mu: sp.Float(m_val, 30), NOISE: sp.Float(D, 30)}
    w0 = float(sp.sympify(pd.model.omega0).subs(subs))
    A, dA = _fn(pd.A, subs, order == 1), _fn(-pd.relaxation, subs, order == 1)
    B = _fn(pd.B, subs, order == 1)
    a_star = _stable_cycle(A, dA)
    lam, g = _at(pd.relaxation, subs, a_star), _at(pd.shear, subs, a_star)
    return (pd, subs, m_val, w0, A, B, a_star, lam, g, D / (2 * w0**2 * a_star**2),
            _at(pd.linewidth, subs, a_star), w0 + float(B(a_star, 0.0)))


def line_theory(model, params: Mapping[str, object], D: float, *, order: int = 1,
                harmonics: int = 3) -> LineTheory:
    """The averaged linewidth, frequency and lines of ``x`` at parameter values.

    Parameters
    ----------
    model : str or kbm.model.builtins.Oscillator
        An autonomous model of one degree of freedom.
    params : mapping
        ``mu`` and the model's parameters.
    D : float
        Noise intensity of ``sqrt(2 D) xi`` (``> 0``).
    order : {1, 2}
        KBM order of the deterministic rates (:func:`kbm.noise.phase_diffusion.phase_diffusion`).
    harmonics : int
        How many harmonics get a line.

    Raises
    ------
    numerics.errors.NoCycleError
        No stable cycle of the averaged amplitude equation.
    kbm.errors.ParameterError
        ``D <= 0``, ``mu <= 0`` or a missing value.

    Examples
    --------
    >>> th = line_theory("vdp", {"mu": 0.1}, 0.001)
    >>> round(th.amplitude, 12), round(th.linewidth_linear / 0.001, 12)
    (2.0, 0.125)
    """
    D = noise_intensity(D, LINEWIDTH_NEED)
    pd, subs, m_val, w0, A, B, a_star, lam, g, d_phi, lw_lin, f_cyc = _linear(
        model, params, D, order)
    f_lin = f_cyc + _at(pd.frequency_shift, subs, a_star)

    # the stationary density on a grid that holds all but exp(-60) of it
    ag, lnp = stationary_density(A, a_star, lam, w0, D, order)
    da = ag[1] - ag[0]
    p = np.exp(lnp - lnp.max())
    p /= np.trapezoid(p, ag)
    inv_a2 = float(np.trapezoid(p / ag**2, ag))
    Bv = np.asarray(B(ag, 0.0), float) * np.ones_like(ag)
    mean_b = float(np.trapezoid(p * Bv, ag))
    fp = (Bv - mean_b) * p
    F = np.concatenate([[0.0], np.cumsum(0.5 * (fp[1:] + fp[:-1]) * da)])
    # above the peak, F = -int_a^inf (B - <B>) P: summed from the top, F/P stays accurate
    # where P is exp(-60) of its peak (from below it is a difference of O(1) numbers)
    Fr = -np.concatenate([np.cumsum((0.5 * (fp[1:] + fp[:-1]) * da)[::-1])[::-1], [0.0]])
    F = np.where(np.arange(F.size) > np.argmax(p), Fr, F)
    s = D / w0**2
    sigma2 = float(np.trapezoid(4 * F**2 / (s * p), ag))
    lw = D / (2 * w0**2) * inv_a2 + sigma2 / 2
    Zv = _fn(pd.phase_response, subs, order == 1)
    ps = 2 * math.pi * np.arange(_PSI) / _PSI
    a_z = _response_cycle(pd, subs, a_star, order)
    small = D * float(np.mean(np.asarray(Zv(a_z, ps), float) ** 2))
    if order >= 2:
        # the phase response's corrections (through mu^2: the transform's u_1, u_2, the
        # rates to A_3, B_3, the cycle's shift by A_3) scale the stationary-density line,
        # whose finite-D/mu part is of the first order
        lw *= small / lw_lin
    freq = w0 + mean_b
    if not freq > 0:
        raise NoCycleError(f"the averaged line centre Omega = {freq:.4g} at order {order} is "
                           f"not positive (cycle a* = {a_star:.4g}): the averaging's series in "
                           "mu does not hold at these values; give a smaller mu or forcing"
                           + (", or use --order 1" if order >= 2 else ""))
    mean_a = float(np.trapezoid(p * ag, ag))

    # harmonics of x(a, psi) on a coarser amplitude grid
    X = _fn(pd.displacement, subs, order == 1)
    n_psi = max(64, 8 * harmonics)
    ps = 2 * math.pi * np.arange(n_psi) / n_psi
    sub = np.linspace(0, ag.size - 1, min(ag.size, 801)).round().astype(int)
    aa, pp = ag[sub], p[sub]
    pp = pp / np.trapezoid(pp, aa)
    xs = np.asarray(X(aa[:, None], ps[None, :]), float) * np.ones((aa.size, n_psi))
    c = np.fft.rfft(xs, axis=1) / n_psi
    lines = []
    for k in range(1, harmonics + 1):
        r = 2 * np.abs(c[:, k])
        m1 = float(np.trapezoid(pp * r, aa))
        m2 = float(np.trapezoid(pp * r * r, aa))
        lines.append(Line(k, k * freq, k * k * lw, m1 * m1 / 2, max(m2 - m1 * m1, 0.0) / 2))
    name = model if isinstance(model, str) else pd.model.name
    return LineTheory(name, order, m_val, float(D), w0, a_star, lam, g, d_phi, lw_lin, f_lin,
                      lw, freq, f_cyc, mean_a, tuple(lines), small)


@dataclass(frozen=True)
class PhaseDiffusion:
    """First-order phase diffusion of a noisy limit cycle.

    Attributes
    ----------
    amplitude : float
        ``a_0``, the stable root of ``A_1``.
    frequency : float
        ``omega0 + mu B_1(a_0)``.
    relaxation : float
        ``lambda = -mu A_1'(a_0)``.
    shear : float
        ``a_0 B_1'(a_0)/A_1'(a_0)`` (zero when the frequency does not depend on ``a``).
    D_phi : float
        Phase diffusion coefficient: ``Var psi ~ 2 D_phi t``.
    D_phi_direct : float
        Its direct part ``D/(2 omega0**2 a_0**2)``.
    """

    amplitude: float
    frequency: float
    relaxation: float
    shear: float
    D_phi: float
    D_phi_direct: float

    def __repr__(self) -> str:
        return f"PhaseDiffusion(a0={self.amplitude:.4g}, D_phi={self.D_phi:.4g})"


def cycle_phase_diffusion(model, params: Mapping[str, object], D: object) -> PhaseDiffusion:
    """Phase diffusion coefficient of the stable first-order averaged cycle: the linearised
    line of :func:`line_theory` at order 1 (also for ``D = 0``).

    Parameters
    ----------
    model : str or kbm.model.builtins.Oscillator
    params : dict
        Parameter values, ``mu`` included (``D`` is taken apart if present).
    D : float
        Noise intensity ``>= 0``.

    Returns
    -------
    PhaseDiffusion

    Raises
    ------
    kbm.errors.ModelError
        No stable first-order cycle.

    Examples
    --------
    >>> cycle_phase_diffusion("vdp", {"mu": 0.05}, 0.01)
    PhaseDiffusion(a0=2, D_phi=0.00125)
    """
    try:
        *_, a0, lam, g, direct, d_phi, f_cyc = _linear(model, params, noise_intensity(D), 1)
    except NoCycleError:
        raise ModelError("the first-order amplitude equation mu A_1(a) has no stable root "
                         "in 0 < a < 50: no limit cycle whose phase could diffuse") from None
    return PhaseDiffusion(a0, f_cyc, lam, -a0 * g / lam, d_phi, direct)
