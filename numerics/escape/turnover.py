"""The escape rate across Kramers' turnover for a well with two symmetric exits.

The well at the origin of ``x'' + gamma x' + g(x) = sqrt(2 D) xi`` (``g`` odd, ``kT =
D/gamma``) is bounded by two saddles ``+-x_s`` at the same energy ``E_b`` (above the
bottom ``E_0``); a particle that crosses either one is taken away (the Fokker-Planck
rate's setting, :mod:`numerics.fokker_planck.escape`: a sink at the next wells' bottoms).
With ``nu_0 = omega_0/2 pi``, ``omega_b = sqrt(-g'(x_s))`` the barrier frequency,
``I = I(E_b)`` the action of the separatrix loop and ``delta = gamma I/kT``:

``r = (lambda_+/omega_b) 2 A(delta/2) nu_0 exp(-(E_b - E_0)/kT)``,

``lambda_+ = sqrt(gamma^2/4 + omega_b^2) - gamma/2``, ``A`` Mel'nikov-Meshkov's
depopulation factor (:func:`melnikov_meshkov_factor`).

Derivation of ``2 A(delta/2)`` (V. I. Mel'nikov and S. V. Meshkov, J. Chem. Phys. 85
(1986) 1018; V. I. Mel'nikov, Phys. Rep. 209 (1991) 1, secs. 2.3-2.5 (the single well)
and 2.7 (the double well); Hanggi, Talkner and Borkovec (HTB), Rev. Mod. Phys. 62 (1990)
251, secs. IV and VIII).  Measure the
energy at a barrier encounter as ``e = (E - E_b)/kT``.  Along a conservative path from one
turning point to the next the energy changes by ``dE = -gamma v^2 dt + v sqrt(2 D) dW``:
mean ``-gamma int v dx`` and variance ``2 D int v dx``.  Between the right saddle and the
left one the path is half the loop, and ``int |v| dx = I/2`` on either half for any
potential (time reversal maps one half on the other), so the kernel from one encounter to
the next is

``P(e | e') = (4 pi s)^(-1/2) exp(-(e - e' + s)^2/(4 s))``, ``s = delta/2``

(the single-exit well of Mel'nikov-Meshkov meets its barrier once a full loop: ``s =
delta``).  Particles arriving at the right saddle with ``e > 0`` leave; those with ``e < 0``
are reflected and arrive at the left saddle with the density ``f_L(e) = int_{-inf}^0 P(e |
e') f_R(e') de'``, and the same from left to right.  The barriers being equal, ``f_L =
f_R = f`` solves Mel'nikov-Meshkov's Wiener-Hopf equation ``f(e) = int_{-inf}^0 P(e | e')
f(e') de'`` with ``f -> e^e`` (Boltzmann) deep in the well, whose escaping flux
``int_0^inf f de`` is ``A(s)`` times the equilibrium one (Mel'nikov 1991, sec. 2.4-2.5;
HTB eq. 4.49).  Each exit thus carries ``A(delta/2) nu_0 exp(-E_b/kT)``: the total is
``2 A(delta/2) nu_0 exp(-E_b/kT)``.

Limits.  ``delta -> 0``: ``A(s) = s (1 + zeta(1/2) (s/pi)^(1/2) + O(s))`` (from the
integral, ``int_0^inf [1/(e^(t^2) - 1) - 1/t^2] dt = (pi^(1/2)/2) zeta(1/2)``), so ``2
A(delta/2) -> delta`` and ``r -> (gamma I/kT) nu_0 exp(-E_b/kT)``, Kramers' energy-diffusion
rate with the full loop's action (Kramers 1940; HTB eq. 4.8: at low friction the
particle leaves by whichever exit it meets above ``E_b``, the rate does not count the
exits).  ``delta -> inf``: ``1 - A(s) ~ 2 exp(-s/4)/(pi s)^(1/2)`` and ``r -> 2
(lambda_+/omega_b) nu_0 exp(-E_b/kT)``, Kramers' spatial-diffusion rate over two saddles
(Kramers 1940; HTB sec. IV for each saddle, the Markovian case of Grote-Hynes).  The
product of the two factors is Mel'nikov-Meshkov's uniform turnover formula (Mel'nikov and
Meshkov 1986; HTB sec. IV), with one exit's ``A(delta)`` replaced by the two exits'
``2 A(delta/2)``.  Both factors are asymptotic in ``E_b/kT``: the formula carries
``O(kT/E_b)`` corrections (docs/noise-escape.rst measures them against the Fokker-Planck
rate).
"""

from __future__ import annotations

import math


from kbm.errors import ParameterError

__all__ = ["melnikov_meshkov_factor", "spatial_diffusion_factor", "two_exit_factor",
           "turnover_rate"]


def melnikov_meshkov_factor(delta: float) -> float:
    """``A(delta) = exp[(1/2 pi) int_R ln(1 - exp(-delta (y^2 + 1/4))) dy/(y^2 + 1/4)]``
    (Mel'nikov and Meshkov 1986; ``A -> delta`` as ``delta -> 0``)."""
    from scipy.integrate import quad  # here: kbm noise imports this module, not quad

    def f(y):
        return math.log(-math.expm1(-delta * (y * y + 0.25))) / (y * y + 0.25)
    val = quad(f, 0, math.inf, limit=400, epsrel=1e-12)[0] * 2
    return math.exp(val / (2 * math.pi))


def _positive(**values: float) -> None:
    for name, val in values.items():
        if not (isinstance(val, (int, float)) and math.isfinite(val) and val > 0):
            raise ParameterError(f"{name} = {val!r}: the turnover rate needs a positive, "
                                 f"finite {name}")


def spatial_diffusion_factor(gamma: float, omega_b: float) -> float:
    """Kramers' spatial-diffusion factor ``lambda_+/omega_b``, ``lambda_+ = sqrt(gamma^2/4 +
    omega_b^2) - gamma/2`` the unstable rate of ``x'' + gamma x' - omega_b^2 x = 0`` at the
    saddle (Kramers 1940; HTB sec. IV), computed as ``omega_b/(sqrt(gamma^2/4 + omega_b^2)
    + gamma/2)`` (no cancellation at large ``gamma``: ``-> omega_b/gamma``).

    Raises
    ------
    kbm.errors.ParameterError
        ``gamma`` or ``omega_b`` not positive and finite.
    """
    _positive(gamma=gamma, omega_b=omega_b)
    return omega_b / (math.hypot(gamma / 2, omega_b) + gamma / 2)


def two_exit_factor(delta: float) -> float:
    """The depopulation factor of a well with two equal exits, ``2 A(delta/2)``
    (``delta = gamma I(E_b)/kT`` the full loop's loss; module docstring): ``-> delta`` as
    ``delta -> 0``, ``-> 2`` as ``delta -> inf``.

    Raises
    ------
    kbm.errors.ParameterError
        ``delta`` not positive and finite.
    """
    _positive(delta=delta)
    return 2 * melnikov_meshkov_factor(delta / 2)


def turnover_rate(gamma: float, kT: float, barrier: float, action: float, omega0: float,
                  omega_b: float) -> float:
    """``(lambda_+/omega_b) 2 A(delta/2) (omega_0/2 pi) exp(-E_b/kT)``, ``delta = gamma
    I(E_b)/kT``: the escape rate over two equal saddles at any linear friction (module
    docstring: its derivation and limits).

    Parameters
    ----------
    gamma : float
        The linear friction (``mu`` of the CDC).
    kT : float
        ``D/gamma``.
    barrier : float
        ``E_b - E_0``.
    action : float
        ``I(E_b)``, the action of the separatrix loop around the well.
    omega0, omega_b : float
        ``sqrt(g'(0))`` and ``sqrt(-g'(x_s))`` at either saddle.

    Returns
    -------
    float

    Raises
    ------
    kbm.errors.ParameterError
        A parameter not positive and finite.
    """
    _positive(kT=kT, barrier=barrier, action=action, omega0=omega0)
    return (spatial_diffusion_factor(gamma, omega_b) * two_exit_factor(gamma * action / kT)
            * omega0 / (2 * math.pi) * math.exp(-barrier / kT))
