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
        ``theta = psi + h(a)``, ``h'(a*) = g/lambda``, through the near-identity transform of
        order ``order - 1`` (:func:`phase_response`); ``D <Z_v^2>`` over ``psi`` at ``a*`` is
        the small-noise linewidth, Lax's ``D_eff`` at order 1 and with its ``O(mu)``
        correction at order 2.
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
    res = derive(m, order, fixed or None)
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
                         phase_response(res, order))
    _CACHE[key] = out
    return out


def phase_response(res, order: int) -> sp.Expr:
    """``Z_v(a, psi)``: the phase response to a velocity kick, through the KBM transform.

    The averaged flow ``a' = A(a)``, ``psi' = omega0 + B(a)`` (rates of order ``order``) has
    the asymptotic phase ``theta = psi + h(a)``, ``h' = -(B(a) - B(a*))/A(a)``, so ``h'(a*) =
    g/lambda`` (the ratio ``B'/(-A')`` kept whole, not expanded in ``mu``).  The near-identity
    transform ``x = a cos psi + mu u_1``, ``v = dx/dt`` along the averaged flow (``v =
    omega0 d_psi x + mu (A_1 d_a + B_1 d_psi) a cos psi``; order 2 keeps ``u_1`` and ``A_1,
    B_1``, order 1 only ``a cos psi``) has the Jacobian ``J = d(x, v)/d(a, psi)``; the
    phase gradient is ``J^{-T} (h', 1)``, whose ``v`` component is

    ``Z_v = (J_xa - h' J_xpsi)/det J``  (exact 2x2 inverse, no expansion).

    On the cycle ``a = a*`` the phase ``theta`` advances uniformly with ``psi``, so the
    small-noise linewidth (Kuramoto 1984, sec. 3.2; Demir et al. 2000) is ``D <Z_v^2>_psi``.
    At order 1 it is Lax's ``D/(2 omega0^2) (1/a^2 + g^2/lambda^2)``; at order 2 it carries
    the ``O(mu)`` corrections (the transform's ``mu u_1``, the second-order rates in
    ``g/lambda``, and ``a*`` from ``A_1 + mu A_2``), with an error ``O(mu^2)`` against the
    true cycle's ``D <Z_v^2>``.  Its own ``mu^2`` terms (from the exact inverse) are not the
    true ones, and may be further off than order 1: van der Pol's ``<Z_v^2>`` is ``1/8 - 69
    mu^2/512`` here, the true cycle's ``1/8 + 7 mu^2/256``; the missing ``mu^2`` terms are
    those of the second-order transform (``u_2``: ``+40/512``; ``v``'s ``mu^2 (A_2 d_a + B_2
    d_psi) u_0 + mu^2 (A_1 d_a + B_1 d_psi) u_1``: ``+44/512``) and ``a*``'s shift by ``A_3``
    (``-1/512``; tests/test_spectrum_order2_vdp.py).

    Parameters
    ----------
    res : kbm.expansion.one_dof.KBMResult
        A derivation of order ``>= order`` (``u``, ``A``, ``B``).
    order : {1, 2}

    Returns
    -------
    sympy.Expr
        ``Z_v`` in ``a``, ``psi``, ``mu``.

    Examples
    --------
    Van der Pol at order 1: ``Z_v = -cos(psi)/a``, ``<Z_v^2> = 1/(2 a^2)``:

    >>> from kbm.expansion.one_dof import derive
    >>> sp.simplify(phase_response(derive("vdp", 1), 1))
    -cos(psi)/a
    """
    w0 = res.model.omega0
    u0 = res.u[0]
    # the rates over mu, so that h' stays finite at mu = 0
    A = sum(mu**(n - 1) * res.A[n] for n in range(1, order + 1))
    B = sum(mu**(n - 1) * res.B[n] for n in range(1, order + 1))
    h = -sp.diff(B, a) / sp.diff(A, a)
    x_of = u0
    v_of = w0 * sp.diff(u0, psi)
    if order >= 2:
        x_of = u0 + mu * res.u[1]
        v_of = v_of + mu * (res.A[1] * sp.diff(u0, a) + res.B[1] * sp.diff(u0, psi)
                            + w0 * sp.diff(res.u[1], psi))
    jxa, jxp = sp.diff(x_of, a), sp.diff(x_of, psi)
    jva, jvp = sp.diff(v_of, a), sp.diff(v_of, psi)
    return (jxa - h * jxp) / (jxa * jvp - jxp * jva)


def _mean_psi(expr: sp.Expr) -> sp.Expr:
    """The mean over ``psi`` of a trigonometric polynomial in ``psi``."""
    e = sp.expand(sp.expand(expr).rewrite(sp.exp))
    terms = e.args if isinstance(e, sp.Add) else (e,)
    return sp.factor(sp.Add(*[t for t in terms if not t.has(psi)]))


def linewidth_series(model: Oscillator | str,
                     params: dict | None = None) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """The small-noise linewidth to one power of ``mu`` beyond Lax: ``D_eff = D (c_0 + mu
    c_1) + O(mu^2 D)``, in closed form.

    With ``a_0`` the stable root of ``A_1``, ``a* = a_0 + mu a_1``, ``a_1 = -A_2(a_0)/A_1'(a_0)``,
    and ``Z_v = z_0 + mu z_1 + O(mu^2)`` (:func:`phase_response` at order 2, expanded;
    ``z_0 = -(cos psi + (g_1/lambda_1) a sin psi)/(omega0 a)`` for ``u_0 = a cos psi``),

    ``c_0 = <z_0^2>(a_0)`` (Lax: ``(1/a_0^2 + g_1^2/lambda_1^2)/(2 omega0^2)``),
    ``c_1 = <2 z_0 z_1>(a_0) + a_1 d<z_0^2>/da(a_0)``.

    Parameters
    ----------
    model : str or kbm.model.builtins.Oscillator
        A polynomial autonomous model (``A_1 = 0`` solved exactly).
    params : dict, optional
        Model parameters, exact numbers (``mu`` stays symbolic).

    Returns
    -------
    a0, c0, c1 : sympy.Expr

    Raises
    ------
    kbm.errors.ParameterError
        ``A_1`` has no stable positive root in closed form.

    Examples
    --------
    Van der Pol has no ``O(mu)`` correction (``F`` odd in ``x'``); the cubic stiffness
    ``-alpha x^3`` at ``alpha = 1`` narrows the line by ``67 mu/8`` of ``D``:

    >>> linewidth_series("vdp")
    (2, 1/8, 0)
    >>> from kbm.model.builtins import custom_model
    >>> linewidth_series(custom_model("(1 - x**2)*xdot - alpha*x**3"), {"alpha": 1})
    (2, 5/4, -67/8)
    """
    pd = phase_diffusion(model, 2, params)
    A = sp.expand(pd.A)
    A1, A2 = A.coeff(mu, 1), A.coeff(mu, 2)
    roots = [r for r in sp.solve(A1, a) if r.is_positive and sp.diff(A1, a).subs(a, r) < 0]
    if not roots:
        raise ParameterError("A_1(a) = 0 has no stable positive root in closed form: give "
                             "numbers for the model's parameters or evaluate numerically "
                             "(numerics.spectrum.phase_diffusion)")
    a0 = min(roots)
    Z = pd.phase_response
    # no simplify of z0, z1: _mean_psi expands them in exponentials of psi anyway
    # (simplifying them first took 80 % of the time)
    z0 = Z.subs(mu, 0)
    z1 = sp.diff(Z, mu).subs(mu, 0)
    m0 = _mean_psi(z0**2)
    m1 = _mean_psi(2 * z0 * z1)
    a1 = -A2.subs(a, a0) / sp.diff(A1, a).subs(a, a0)
    c1 = sp.nsimplify(sp.simplify(m1.subs(a, a0) + a1 * sp.diff(m0, a).subs(a, a0)))
    return a0, sp.simplify(m0.subs(a, a0)), c1
