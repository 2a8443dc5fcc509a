"""Mean first-passage time over the barrier of the well at the origin, from the
averaged energy process, and Kramers' low-friction rate.

The averaged energy (:mod:`numerics.escape.envelope`) is a diffusion on
``[E_0, E_b]`` (``E_0`` the well bottom, reflecting; ``E_b`` the lowest saddle
energy bounding the well, absorbing).  Its mean first-passage time from ``E`` is
the classical double integral (Gardiner, *Handbook of Stochastic Methods*, eq. 5.2.158)

``tau(E) = int_E^{E_b} dy / (sigma^2 p)(y) * 2 int_{E_0}^y p(z) dz``,  ``p`` the
stationary density of ``E``.  With ``p = T f``, ``sigma^2 = 2 D I/T`` and ``T = dI/dE``
the inner integral is ``int T f = I f - (mu/D) int Gamma f`` and

``tau(E) = (1/D) int_E^{E_b} [1 - mu/(D I(y) f(y)) int_{E_0}^y Gamma(z) f(z) dz] dy``,

an integrand free of the logarithmic singularity of ``T`` at the separatrix.  For
linear damping (``Gamma = -I``, ``f = exp(-E/kT)``) and ``E_b/kT -> inf`` it reduces
to Kramers' low-friction (energy-diffusion) rate

``r_K = (mu I(E_b)/kT) (omega_0/2 pi) exp(-E_b/kT)``

(H. A. Kramers, Physica 7 (1940) 284; Hanggi, Talkner and Borkovec, Rev. Mod. Phys.
62 (1990) 251, eq. 4.8), ``I(E_b)`` the action of the separatrix loop.  At finite
damping the population near the barrier is depleted within one cycle; the
Mel'nikov-Meshkov factor ``A(delta)/delta`` (``delta = mu I(E_b)/kT``; V. I. Mel'nikov
and S. V. Meshkov, J. Chem. Phys. 85 (1986) 1018; Hanggi et al. eq. 4.49)
corrects for it: ``r_MM = A(delta) (omega_0/2 pi) exp(-E_b/kT)`` (``rate_melnikov``: one
exit, no spatial-diffusion factor).  The well at the origin of the CDC/SEDF has two equal
exits; the rate across the whole turnover is ``rate_turnover``, ``(lambda_+/omega_b) 2
A(delta/2) (omega_0/2 pi) exp(-E_b/kT)`` (:mod:`numerics.escape.turnover`: derivation,
limits), which tends to ``r_K`` at low friction and to Kramers' spatial-diffusion rate over
both saddles at high friction.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from kbm.errors import ModelError

from ._panels import Piecewise
from .envelope import EnergyEnvelope, no_origin_well
from .turnover import melnikov_meshkov_factor, turnover_rate

__all__ = ["EscapeRate", "averaged_escape", "separatrix_action", "kramers_low_friction", "central_well", "barrier_frequency"]


def central_well(env: EnergyEnvelope):
    """The annulus of the well at the origin and its barrier, or a one-line reason.

    Raises
    ------
    kbm.errors.ModelError
        No centre at ``x = 0``, or the well reaches infinity (no barrier).
    """
    for p in env.pieces:
        if 0.0 in [round(w, 9) for w in p.annulus.wells] and len(p.annulus.wells) == 1:
            if not p.annulus.bounded:
                break
            return p
    raise no_origin_well(env.portrait)


def separatrix_action(split, Eb: float, xl: float, xr: float) -> float:
    """``I(E_b) = oint x' dx = 2 int_{xl}^{xr} sqrt(2 (E_b - G)) dx`` by adaptive quadrature
    (``xl < 0 < xr`` the turning points of the separatrix loop around the origin)."""
    from scipy.integrate import quad  # here: kbm noise imports this module, not quad

    G = split.numpy_functions()[2]
    val = quad(lambda z: math.sqrt(max(2 * (Eb - float(G(np.array(z)))), 0.0)), xl, xr,
               limit=400, epsabs=0, epsrel=1e-12)[0]
    return 2 * val


def kramers_low_friction(mu: float, kT: float, Eb: float, action: float, omega0: float) -> float:
    """Kramers' energy-diffusion rate ``(mu I(E_b)/kT) (omega_0/2 pi) exp(-E_b/kT)``
    (Hanggi, Talkner, Borkovec 1990, eq. 4.8)."""
    return mu * action / kT * omega0 / (2 * math.pi) * math.exp(-Eb / kT)


@dataclass(frozen=True)
class EscapeRate:
    """Escape from the well at the origin by energy diffusion.

    Attributes
    ----------
    rate_averaged : float
        ``1/tau(E_0)`` from the averaged energy process.
    mfpt : float
        ``tau(E_0)``.
    barrier : float
        ``E_b - E_0``.
    saddles : tuple of float
        The saddles ``(x_l, x_r)`` bounding the well.
    action : float
        ``I(E_b)``.
    omega0 : float
        ``sqrt(g'(0))``.
    kT : float or None
        ``D/mu`` for linear damping, else ``None``.
    rate_kramers, rate_melnikov : float or None
        Kramers' low-friction rate and the Mel'nikov-Meshkov rate ``A(delta) (omega_0/2 pi)
        exp(-E_b/kT)`` of a well with one exit (linear damping only).
    omega_b : float or None
        ``sqrt(-g'(x_s))`` at the saddles, where both have the barrier's energy and the
        same curvature (else ``None``).
    rate_turnover : float or None
        ``(lambda_+/omega_b) 2 A(delta/2) (omega_0/2 pi) exp(-E_b/kT)``: two equal exits,
        any friction (:func:`numerics.escape.turnover.turnover_rate`; linear damping and
        ``omega_b`` only).
    """

    rate_averaged: float
    mfpt: float
    barrier: float
    saddles: tuple
    action: float
    omega0: float
    kT: float | None
    rate_kramers: float | None
    rate_melnikov: float | None
    omega_b: float | None = None
    rate_turnover: float | None = None

    def __repr__(self) -> str:
        return (f"EscapeRate(averaged={self.rate_averaged:.4g}, barrier={self.barrier:.4g}, "
                f"kramers={self.rate_kramers})")


def _linear_damping(env: EnergyEnvelope) -> bool:
    import sympy as sp

    from kbm.symbols import xdot
    return sp.simplify(env.split.h + xdot) == 0


def averaged_escape(env: EnergyEnvelope) -> EscapeRate:
    """Mean first-passage time from the bottom of the well at the origin to its barrier
    energy, and the rate ``1/tau``, from the averaged energy diffusion.

    Parameters
    ----------
    env : EnergyEnvelope

    Returns
    -------
    EscapeRate
    """
    p = central_well(env)
    E0, Eb = p.lo, p.hi
    mu, D = env.mu, env.D
    # inner: J(y) = int_{E0}^y Gamma f dz, on the panels of the well's interpolants
    ref = float(p.log_f(E0))
    J = Piecewise.sample(p.action.breaks,
                         lambda z: p.gamma(z) * np.exp(p.log_f(z) - ref)).integ()
    y, wy = p.rule()
    with np.errstate(over="ignore", divide="ignore", invalid="ignore"):  # said below
        integrand = 1.0 - mu / D * J(y) / (p.action(y) * np.exp(p.log_f(y) - ref))
        tau = float(np.sum(wy * integrand)) / D
    if not (math.isfinite(tau) and tau > 0):
        raise ModelError(f"the mean first-passage time came out as {tau}: the averaged "
                         "energy process does not reach the barrier (check mu > 0 and D > 0), "
                         "or the barrier is several hundred times D/mu and the MFPT "
                         "overflows double precision (raise D)")
    split = env.split
    sad = [e.x for e in env.portrait.equilibria if e.kind == "saddle"]
    xl = max([s for s in sad if s < 0], default=-math.inf)
    xr = min([s for s in sad if s > 0], default=math.inf)
    g, dg, G, _ = split.numpy_functions()
    omega0 = math.sqrt(float(dg(np.array(0.0))))
    # the separatrix loop: turning points at E_b on each side (one is the saddle)
    xm, xp = p.annulus.turning_points(np.array([Eb * (1 - 1e-14)]))
    action = separatrix_action(split, Eb, float(xm[0]), float(xp[0]))
    omega_b = barrier_frequency(split, (xl, xr), Eb - E0)
    kT = rk = rmm = rt = None
    if _linear_damping(env):
        kT = D / mu
        rk = kramers_low_friction(mu, kT, Eb - E0, action, omega0)
        rmm = melnikov_meshkov_factor(mu * action / kT) * omega0 / (2 * math.pi) * math.exp(
            -(Eb - E0) / kT)
        if omega_b is not None:
            rt = turnover_rate(mu, kT, Eb - E0, action, omega0, omega_b)
    return EscapeRate(1.0 / tau, tau, Eb - E0, (xl, xr), action, omega0, kT, rk, rmm,
                      omega_b, rt)


def barrier_frequency(split, saddles, barrier: float) -> float | None:
    """``omega_b = sqrt(-g'(x_s))`` where the two saddles bounding the well are equal exits:
    both finite, at the same energy and curvature (to 1e-9 relative), as in an even
    potential; else ``None`` (the two-exit turnover formula does not apply).

    Parameters
    ----------
    split : the conservative split of the model
    saddles : (float, float)
        ``(x_l, x_r)``.
    barrier : float
        ``E_b - E_0``, the scale of the energies' agreement.
    """
    if not all(math.isfinite(s) for s in saddles):
        return None
    _, dg, G, _ = split.numpy_functions()
    curv = [-float(dg(np.array(s))) for s in saddles]
    energy = [float(G(np.array(s))) for s in saddles]
    if min(curv) <= 0 or abs(curv[0] - curv[1]) > 1e-9 * max(curv) or (
            abs(energy[0] - energy[1]) > 1e-9 * barrier):
        return None
    return math.sqrt(curv[1])
