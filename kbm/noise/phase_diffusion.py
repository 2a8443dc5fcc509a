"""Phase diffusion and linewidth of a noisy self-excited oscillator, by stochastic averaging.

The noisy oscillator of :mod:`kbm.noise.stochastic` (the paper's eq. 1, unit mass),

``x'' + omega0^2 x = mu F(x, x') + sqrt(2 D) xi(t)``,  ``<xi(t) xi(t')> = delta(t - t')``,

written ``x = a cos psi + mu u_1(a, psi) + ...``, ``psi = omega0 t + phi``, obeys after
averaging over ``psi`` the Ito equations (Stratonovich-Khasminskii; :mod:`kbm.noise.stochastic`)

``da   = [A(a) + D/(2 omega0^2 a)] dt + (sqrt(D)/omega0) dW_1``,
``dphi = B(a) dt + (sqrt(D)/(omega0 a)) dW_2``,

with ``A = sum_n mu^n A_n``, ``B = sum_n mu^n B_n`` the KBM rates (:func:`kbm.derive`; the
first order is the Stratonovich-Khasminskii limit, a higher order adds the deterministic
corrections only) and ``W_1, W_2`` independent.  About a stable cycle ``a*`` (``A(a*) =
0``, ``A'(a*) < 0``) let ``a = a* + delta``.  Then

* the amplitude relaxes at the rate ``lambda = -A'(a*)``, with the variance
  ``<delta^2> = D/(2 omega0^2 lambda)`` (Ornstein-Uhlenbeck) and the mean shift
  ``<delta> = [D/(2 omega0^2 a*) + A''(a*) <delta^2>/2]/lambda``;
* the phase diffuses, ``var phi(t) = 2 D_phi t``, with ``D_phi = D/(2 omega0^2 a*^2)``
  (half the variance rate of ``phi``);
* the frequency depends on the amplitude, ``g = B'(a*)`` (nonisochronicity, Kuramoto's
  shear), so ``phi' = B(a*) + g delta + ...``: the amplitude noise feeds the phase.  The
  integral of ``delta``'s autocorrelation is ``2 <delta^2>/lambda``, so ``var phi`` grows at
  ``2 D_phi + 2 g^2 <delta^2>/lambda``:

  ``D_eff = D_phi + g^2 D_a/lambda^2 = D/(2 omega0^2) [1/a*^2 + g^2/lambda^2]``,

  ``D_a = D/(2 omega0^2)`` (Lax's formula; the factor ``1 + (g a*/lambda)^2`` is Henry's
  ``1 + alpha^2`` of the laser linewidth);
* the mean frequency is ``Omega = omega0 + B(a*) + g <delta> + B''(a*) <delta^2>/2`` (the
  last two terms: the noise-induced shift).

The phase ``psi`` of ``x`` is a Wiener process with drift ``Omega`` and intensity
``D_eff``, so ``<exp(i k (psi(t+tau) - psi(t)))> = exp(i k Omega tau - k^2 D_eff |tau|)``:
harmonic ``k`` of the cycle, ``x = sum_k |c_k| cos(k psi + theta_k)``, is a Lorentzian line
at ``k Omega`` of half width at half maximum ``k^2 D_eff`` that carries the variance
``|c_k|^2/2``.  These are the linearised (small ``D/mu``) forms; beyond them the averaged
equations give the long-time phase diffusion exactly as a quadrature over the stationary
density ``P(a)`` (:attr:`PhaseDiffusion.log_density`; evaluated in
:mod:`numerics.spectrum.phase_diffusion`).

References
----------
M. Lax, Phys. Rev. 160, 290 (1967) (classical noise V: the noise of self-sustained
oscillators); R. L. Stratonovich, *Topics in the Theory of Random Noise*, vol. 2 (1967),
ch. 9; Y. Kuramoto, *Chemical Oscillations, Waves, and Turbulence* (1984), sec. 2.3 and
ch. 5; C. H. Henry, IEEE J. Quantum Electron. 18, 259 (1982).
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from ..expansion.one_dof import derive
from ..errors import ParameterError
from ..output.latex import equation_lines, latex
from ..model.builtins import Oscillator
from .phase_response import (cycle_coefficients, mean_psi, phase_response, response_order,
                             response_parts, taylor)
from .stochastic import NOISE, noisy_model
from ..symbols import a, mu, psi

__all__ = ["PhaseDiffusion", "phase_diffusion", "phase_response", "linewidth_series"]

_CACHE: dict = {}  # one derivation per model, order and fixed parameters


@dataclass(frozen=True)
class PhaseDiffusion:
    """The averaged amplitude-phase diffusion of a noisy self-excited oscillator, symbolic in
    the amplitude ``a``, ``mu`` and ``D``.

    Attributes
    ----------
    model : kbm.model.builtins.Oscillator
    order : int
        The KBM order of the deterministic rates (the noise terms are of the first order).
    A, B : sympy.Expr
        ``sum_n mu^n A_n(a)`` and ``sum_n mu^n B_n(a)`` (``psi' = omega0 + B``).
    relaxation : sympy.Expr
        ``lambda(a) = -dA/da``.
    shear : sympy.Expr
        ``g(a) = dB/da``.
    phase_diffusion : sympy.Expr
        ``D_phi(a) = D/(2 omega0^2 a^2)``: half the variance rate of the phase.
    amplitude_diffusion : sympy.Expr
        ``D_a = D/(2 omega0^2)``: half the variance rate of the amplitude.
    linewidth : sympy.Expr
        ``D_eff(a) = D_phi + g^2 D_a/lambda^2``: the half width at half maximum of the
        fundamental (angular), at ``a = a*``.
    amplitude_shift : sympy.Expr
        ``<a> - a*`` to first order in ``D``.
    frequency_shift : sympy.Expr
        The noise-induced shift of the mean angular frequency, first order in ``D``.
    displacement : sympy.Expr
        ``x(a, psi) = a cos psi + sum_n mu^n u_n``: the harmonics' weights.
    phase_response : sympy.Expr
        ``Z_v(a, psi)``: the velocity component of the gradient of the asymptotic phase
        ``theta = psi + h(a)``, ``h'(a*) = g/lambda``, through the near-identity transform
        (:func:`kbm.noise.phase_response.phase_response` of order ``response_order``);
        ``D <Z_v^2>`` over ``psi`` at the stable root of ``response_rate`` is the
        small-noise linewidth: Lax's ``D_eff`` at order 1, right through ``mu^2`` at order 2
        (through ``mu`` only where the expansion stops at order 2).
    response_order : int
        The phase response's order (:func:`kbm.noise.phase_response.response_order`): 1 at
        order 1; at order 2, 3 (``u_1``, ``u_2``, ``v`` to ``mu^2``, the rates to
        ``A_3``, ``B_3``) for a polynomial ``F``, else 2 (``u_1``, the rates to ``A_2``,
        ``B_2``; the SEDF's ``sin(k x)``).
    response_rate : sympy.Expr
        ``sum_n mu^n A_n`` to ``n = response_order``: its stable root (near ``a*``) is the
        cycle at which ``<Z_v^2>`` is taken (at order 2, ``a*`` shifted by ``mu^3 A_3``,
        ``O(mu^2)``; van der Pol: ``2 + mu^2/64``).
    """

    model: Oscillator
    order: int
    A: sp.Expr
    B: sp.Expr
    relaxation: sp.Expr
    shear: sp.Expr
    phase_diffusion: sp.Expr
    amplitude_diffusion: sp.Expr
    linewidth: sp.Expr
    amplitude_shift: sp.Expr
    frequency_shift: sp.Expr
    displacement: sp.Expr
    phase_response: sp.Expr = sp.S.Zero
    response_order: int = 1
    response_rate: sp.Expr = sp.S.Zero

    def __repr__(self) -> str:
        return f"PhaseDiffusion({self.model.name}, order {self.order}: D_eff = {self.linewidth})"

    @property
    def drift_a(self) -> sp.Expr:
        """The Ito drift ``A + D/(2 omega0^2 a)`` of the amplitude."""
        return self.A + NOISE / (2 * self.model.omega0**2 * a)

    @property
    def parameters(self) -> tuple[str, ...]:
        """The model's parameter names (besides ``a``, ``mu``, ``D``), sorted."""
        syms = set().union(*[e.free_symbols for e in (self.A, self.B, self.displacement)])
        return tuple(sorted(s.name for s in syms - {a, mu, NOISE, psi}))

    def latex(self, width: int = 62) -> str:
        """``align`` lines: ``lambda``, ``g``, ``D_phi`` and ``D_eff`` as functions of ``a``
        (deterministic: the same bytes whatever ``PYTHONHASHSEED``)."""
        eff = (latex(self.phase_diffusion) if self.shear == 0 else
               latex(self.phase_diffusion) + " + " + latex(self.amplitude_diffusion)
               + r"\,\frac{g(a)^2}{\lambda(a)^2}")
        return " \\\\\n".join([
            equation_lines(r"\lambda(a)", sp.factor(self.relaxation), width),
            equation_lines("g(a)", sp.factor(self.shear), width),
            r"D_\varphi(a) &= " + latex(self.phase_diffusion),
            r"D_{\mathrm{eff}}(a) &= " + eff])


def phase_diffusion(model: Oscillator | str, order: int = 1,
                    params: dict | None = None) -> PhaseDiffusion:
    """The averaged phase diffusion of ``x'' + omega0^2 x = mu F + sqrt(2 D) xi``.

    Parameters
    ----------
    model : str or kbm.model.builtins.Oscillator
        An autonomous model of one degree of freedom.
    order : {1, 2}
        KBM order of the deterministic rates ``A``, ``B`` and of ``x(a, psi)``.
    params : dict, optional
        Model parameters substituted exactly before the algebra (``mu``, ``D`` stay
        symbolic).

    Raises
    ------
    kbm.errors.ParameterError
        An order other than 1 or 2, or a model parameter named ``D``.
    kbm.errors.NonAutonomousError
        For a driven model.

    Examples
    --------
    Van der Pol: ``lambda(2) = mu``, no shear, ``D_eff = D/8`` at ``a* = 2``:

    >>> pd = phase_diffusion("vdp")
    >>> pd.relaxation.subs(a, 2), pd.shear, pd.linewidth.subs(a, 2)
    (mu, 0, D/8)

    A cubic stiffness ``-alpha x^3`` adds the shear ``g = 3 alpha mu a/4``, which widens the
    line ``1 + (g a/lambda)^2 = 10`` times at ``alpha = 1``:

    >>> from kbm.model.builtins import custom_model
    >>> pd = phase_diffusion(custom_model("(1 - x**2)*xdot - alpha*x**3"), params={"alpha": 1})
    >>> pd.shear, sp.simplify(pd.linewidth.subs(a, 2) / (NOISE / 8))
    (3*a*mu/4, 10)
    """
    if order not in (1, 2):
        raise ParameterError(f"order = {order!r}: the phase diffusion is averaged to order 1 or "
                             "2")
    m, fixed = noisy_model(model, params, "the phase-diffusion averaging")
    key = (m.name, str(m.F), str(m.omega0), order,
           tuple(sorted((k, str(v)) for k, v in fixed.items())))
    if key in _CACHE:
        return _CACHE[key]
    n_z = response_order(m, order)
    # one derivation: its lower orders are those of the order asked for
    res = derive(m, max(order, n_z), fixed or None)
    w0 = res.model.omega0
    A = sp.expand(sum(mu**n * res.A[n] for n in range(1, order + 1)))
    B = sp.expand(sum(mu**n * res.B[n] for n in range(1, order + 1)))
    lam = sp.expand(-sp.diff(A, a))
    g = sp.expand(sp.diff(B, a))
    d_phi = NOISE / (2 * w0**2 * a**2)
    d_a = NOISE / (2 * w0**2)
    var_a = NOISE / (2 * w0**2 * lam)
    shift_a = (NOISE / (2 * w0**2 * a) + sp.diff(A, a, 2) * var_a / 2) / lam
    shift_w = g * shift_a + sp.diff(B, a, 2) * var_a / 2
    x_of = res.u[0] + sum(mu**n * res.u[n] for n in range(1, order + 1))
    out = PhaseDiffusion(res.model, order, A, B, lam, g, d_phi, d_a,
                         d_phi + g**2 * d_a / lam**2, shift_a, shift_w, x_of,
                         phase_response(res, n_z), n_z,
                         sp.expand(sum(mu**n * res.A[n] for n in range(1, n_z + 1))))
    _CACHE[key] = out
    return out


def linewidth_series(model: Oscillator | str, params: dict | None = None,
                     terms: int = 2) -> tuple[sp.Expr, ...]:
    """The small-noise linewidth as a series in ``mu``: ``D_eff = D (c_0 + mu c_1 + mu^2 c_2)
    + O(mu^terms D)``, in closed form.

    With ``a_0`` the stable root of ``A_1`` and ``a* = a_0 + mu a_1 + mu^2 a_2`` the cycle
    of ``A_1 + mu A_2 + mu^2 A_3`` (powers of ``mu`` matched: ``a_1 = -A_2(a_0)/A_1'(a_0)``),
    and ``Z_v(a*, psi) = z_0 + mu z_1 + mu^2 z_2 + ..`` (:func:`phase_response` of order
    ``terms``, expanded at the cycle; ``z_0 = -(cos psi + (g_1/lambda_1) a sin psi)/(omega0
    a)`` for ``u_0 = a cos psi``),

    ``c_0 = <z_0^2>`` (Lax: ``(1/a_0^2 + g_1^2/lambda_1^2)/(2 omega0^2)``),
    ``c_1 = <2 z_0 z_1>``, ``c_2 = <z_1^2 + 2 z_0 z_2>``.

    ``c_2`` needs the third-order transform (``u_2``, ``A_3``, ``B_3``): the phase response
    of ``kbm spectrum --order 2`` (:func:`kbm.noise.phase_response.response_order`).

    Parameters
    ----------
    model : str or kbm.model.builtins.Oscillator
        A polynomial autonomous model (``A_1 = 0`` solved exactly).
    params : dict, optional
        Model parameters, exact numbers (``mu`` stays symbolic).
    terms : {2, 3}
        How many coefficients: ``c_0, c_1`` or ``c_0, c_1, c_2``.

    Returns
    -------
    a0, c0, c1[, c2] : sympy.Expr

    Raises
    ------
    kbm.errors.ParameterError
        ``terms`` not 2 or 3, ``terms = 3`` for a model whose expansion stops at order 2,
        or ``A_1`` has no stable positive root in closed form.

    Examples
    --------
    Van der Pol has no ``O(mu)`` correction (``F`` odd in ``x'``) and ``7 mu^2/256`` (the
    adjoint Floquet cycle's, tests/test_spectrum_order2_vdp.py); the cubic stiffness
    ``-alpha x^3`` at ``alpha = 1`` narrows the line by ``67 mu/8`` of ``D``:

    >>> linewidth_series("vdp", terms=3)
    (2, 1/8, 0, 7/256)
    >>> from kbm.model.builtins import custom_model
    >>> linewidth_series(custom_model("(1 - x**2)*xdot - alpha*x**3"), {"alpha": 1})
    (2, 5/4, -67/8)
    """
    if terms not in (2, 3):
        raise ParameterError(f"terms = {terms!r}: the linewidth series has 2 or 3 terms")
    m, fixed = noisy_model(model, params, "the linewidth series")
    if response_order(m, 2) < terms:
        raise ParameterError(f"the expansion of {m.name!r} stops at order 2 (a transcendental "
                             "F), so its linewidth series has 2 terms: give terms=2")
    res = derive(m, terms, fixed or None)
    num, det, rate = response_parts(res, terms)
    A1 = res.A[1]
    roots = [r for r in sp.solve(A1, a) if r.is_positive and sp.diff(A1, a).subs(a, r) < 0]
    if not roots:
        raise ParameterError("A_1(a) = 0 has no stable positive root in closed form: give "
                             "numbers for the model's parameters or evaluate numerically "
                             "(numerics.spectrum.phase_diffusion)")
    a0 = min(roots)
    a_mu = sum(mu**k * c for k, c in enumerate(cycle_coefficients(rate, a0, terms)))
    # Z_v = num/det at the cycle, term by term; det's first term is -omega0 a_0 for u_0 =
    # a cos psi (no psi), so every z_k is a trigonometric polynomial in psi
    p, q = taylor(num.subs(a, a_mu), terms), taylor(det.subs(a, a_mu), terms)
    z: list = []
    for k in range(terms):
        z.append(sp.expand((p[k] - sum(z[j] * q[k - j] for j in range(k))) / q[0]))
    return (a0, *[sp.simplify(mean_psi(sum(z[j] * z[k - j] for j in range(k + 1))))
                  for k in range(terms)])
