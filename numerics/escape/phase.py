"""Phase diffusion (the linewidth) of a noisy limit cycle, from first-order averaging.

For ``x'' + omega0**2 x = mu F(x, x') + sqrt(2 D) xi(t)`` write ``x = a cos psi``,
``x' = -a omega0 sin psi``.  Stochastic averaging at first order (Stratonovich;
Khasminskii) gives the Ito equations

``da = [mu A_1(a) + D/(2 omega0**2 a)] dt + sqrt(D)/omega0 dW_1``,
``dpsi = [omega0 + mu B_1(a)] dt + sqrt(D)/(omega0 a) dW_2``

with independent ``W_1, W_2`` (the cross term ``sin psi cos psi`` averages to zero).
About the stable cycle ``a_0`` (``A_1(a_0) = 0``, ``lambda = -mu A_1'(a_0) > 0``) the
amplitude is an Ornstein-Uhlenbeck process, ``delta a`` of variance ``D/(2 omega0**2
lambda)``, and the phase picks it up through the shear ``mu B_1'(a_0)`` (the isochrons
are tilted).  The phase variance grows like ``2 D_phi t`` with

``D_phi = D / (2 omega0**2 a_0**2) * [1 + (a_0 B_1'(a_0)/A_1'(a_0))**2]``

(the direct term and the amplitude-phase coupling; for van der Pol ``B_1 = 0`` and
``D_phi = D/(2 a_0**2) = D/8``).  The spectrum of ``x`` is then a Lorentzian of
half-width ``D_phi`` at ``omega0 + mu B_1(a_0)``.

References
----------
R. L. Stratonovich, *Topics in the Theory of Random Noise*, vol. 2 (1967), ch. 9
(oscillator fluctuations); M. Lax, Phys. Rev. 160 (1967) 290 (amplitude-phase
coupling in the oscillator linewidth).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import sympy as sp

from kbm.errors import ModelError

from .envelope import noise_level

__all__ = ["PhaseDiffusion", "phase_diffusion"]


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


def phase_diffusion(model, params: dict, D: object) -> PhaseDiffusion:
    """Phase diffusion coefficient of the stable first-order averaged cycle.

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
    >>> phase_diffusion("vdp", {"mu": 0.05}, 0.01)
    PhaseDiffusion(a0=2, D_phi=0.00125)
    """
    import kbm
    from kbm.model.builtins import get_model

    D = noise_level(D)
    m = get_model(model) if isinstance(model, str) else model
    params = {k: v for k, v in dict(params).items() if k != "D"}
    vals = m.resolve(params)
    r = kbm.derive(m, 1)
    subs = {sp.Symbol(k): v for k, v in vals.items() if k != "mu"}
    a = sp.Symbol("a", positive=True)
    A1 = sp.sympify(r.A[1]).subs(subs)
    B1 = sp.sympify(r.B[1]).subs(subs)
    A1 = A1.subs(sp.Symbol("a"), a)
    B1 = B1.subs(sp.Symbol("a"), a)
    w0 = float(sp.sympify(r.B[0]).subs(subs))
    muv = float(vals.get("mu", 0.0))
    if muv <= 0:
        raise ModelError("phase diffusion needs mu > 0 in params (the limit cycle of mu A_1)")
    fA = sp.lambdify(a, A1, "numpy")
    dA = sp.lambdify(a, sp.diff(A1, a), "numpy")
    fB = sp.lambdify(a, B1, "numpy")
    dB = sp.lambdify(a, sp.diff(B1, a), "numpy")
    grid = np.linspace(1e-3, 50, 20001)
    val = np.asarray(fA(grid), float) * np.ones_like(grid)
    roots = []
    for i in np.nonzero(np.sign(val[:-1]) * np.sign(val[1:]) < 0)[0]:
        from scipy.optimize import brentq
        a0 = brentq(lambda z: float(fA(z)), grid[i], grid[i + 1], xtol=1e-14)
        if float(dA(a0)) < 0:
            roots.append(a0)
    if not roots:
        raise ModelError("the first-order amplitude equation mu A_1(a) has no stable root "
                         "in 0 < a < 50: no limit cycle whose phase could diffuse")
    a0 = roots[0]
    shear = a0 * float(dB(a0)) / float(dA(a0))
    direct = D / (2 * w0**2 * a0**2)
    return PhaseDiffusion(float(a0), w0 + muv * float(fB(a0)), -muv * float(dA(a0)), shear,
                          direct * (1 + shear**2), direct)
