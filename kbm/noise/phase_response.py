"""The phase response of the averaged cycle pulled back through the KBM transform.

For the averaged flow ``a' = A(a)``, ``psi' = omega0 + B(a)`` of
``x'' + omega0^2 x = mu F(x, x')`` the asymptotic phase is ``theta = psi + h(a)``,
``h' = -(B(a) - B(a*))/A(a)``, so ``h'(a*) = -B'(a*)/A'(a*) = g/lambda``.  The near-identity
transform ``x = sum_{k < n} mu^k u_k(a, psi)`` and ``v = dx/dt`` along the averaged flow
carry it to the phase plane: with ``J = d(x, v)/d(a, psi)`` the phase gradient is
``J^{-T} (h', 1)``, whose ``v`` component is the response to a velocity kick,

``Z_v = (J_xa - h' J_xpsi)/det J``,

and ``D <Z_v^2>`` over ``psi`` at the cycle is the small-noise half width of the line
(Kuramoto, *Chemical Oscillations, Waves, and Turbulence* (1984), sec. 3.2; Demir, Mehrotra
and Roychowdhury, IEEE Trans. Circuits Syst. I 47, 655 (2000)).

:func:`phase_response` of order ``n`` keeps ``u_0 .. u_{n-1}``, the terms of ``v`` to
``mu^{n-1}`` and the rates ``A_1 .. A_n``, ``B_1 .. B_n`` (``h'`` is a ratio of ``O(mu)``
rates, so it needs one order more than the transform); evaluated at the cycle of ``A_1 +
.. + mu^{n-1} A_n`` its ``<Z_v^2>`` is right through ``mu^{n-1}``.  Order 1 is Lax's
formula, order 3 the one ``kbm spectrum --order 2`` uses (:func:`response_order`):
van der Pol's ``<Z_v^2> = 1/8 + 7 mu^2/256 + O(mu^4)`` (order 2 gave ``1/8 - 69
mu^2/512``; :func:`kbm.noise.phase_diffusion.linewidth_series`).
"""

from __future__ import annotations

import sympy as sp

from ..errors import ParameterError
from ..expansion.cost import COST_BUDGET, expansion_cost
from ..expansion.one_dof import symbolic_order_limit
from ..symbols import a, mu, psi

__all__ = ["phase_response", "response_order", "response_parts", "cycle_coefficients",
           "mean_psi", "taylor"]


def response_order(model, order: int) -> int:
    """The order of the phase response behind the averaging of order ``order``: ``1`` at
    order 1 (Lax), ``3`` at order 2 (right through ``mu^2``, as the order-2 line centre)
    where the symbolic expansion reaches order 3 (polynomial ``F`` with rational
    coefficients within :data:`kbm.expansion.cost.COST_BUDGET`), else ``2`` (right through
    ``mu``: a transcendental ``F`` such as the SEDF's ``sin(k x)``, whose Bessel sums stay
    symbolic to order 2 only)."""
    if order < 2:
        return 1
    if symbolic_order_limit(model) < 3:
        return 2
    cost = expansion_cost(model.F, 3)
    return 3 if cost is None or cost[0] <= COST_BUDGET else 2


def response_parts(res, order: int) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """``(J_xa - h' J_xpsi, det J, rate)``: the numerator and denominator of ``Z_v`` and the
    amplitude rate over ``mu``, ``A_1 + mu A_2 + .. + mu^{order-1} A_order``, whose stable
    root is the cycle (the rates over ``mu``, so that ``h'`` stays finite at ``mu = 0``)."""
    if not 1 <= order <= res.order:
        raise ParameterError(f"order = {order!r}: the phase response needs 1 <= order <= "
                             f"{res.order}, the derivation's order")
    u, A, B = res.u, res.A, res.B  # A[0] = 0, B[0] = omega0
    rate_a = sum(mu**(n - 1) * A[n] for n in range(1, order + 1))
    rate_b = sum(mu**(n - 1) * B[n] for n in range(1, order + 1))
    h = -sp.diff(rate_b, a) / sp.diff(rate_a, a)
    x_of = sum(mu**k * u[k] for k in range(order))
    # dx/dt = (A d_a + (omega0 + B) d_psi) x, the terms of mu^k for k < order
    v_of = sum(mu**k * sum(A[k - j] * sp.diff(u[j], a) + B[k - j] * sp.diff(u[j], psi)
                           for j in range(k + 1)) for k in range(order))
    jxa, jxp = sp.diff(x_of, a), sp.diff(x_of, psi)
    jva, jvp = sp.diff(v_of, a), sp.diff(v_of, psi)
    return jxa - h * jxp, jxa * jvp - jxp * jva, rate_a


def phase_response(res, order: int) -> sp.Expr:
    """``Z_v(a, psi)``: the phase response to a velocity kick, through the KBM transform.

    ``Z_v = (J_xa - h' J_xpsi)/det J`` (exact 2x2 inverse, no expansion; the ratio
    ``h' = -B'/A'`` kept whole) with ``x = a cos psi + mu u_1 + .. + mu^{order-1}
    u_{order-1}``, ``v`` the time derivative of ``x`` along the averaged flow to the same
    power (``omega0 d_psi x + mu (A_1 d_a + B_1 d_psi) u_0 + mu^2 [(A_2 d_a + B_2 d_psi)
    u_0 + (A_1 d_a + B_1 d_psi) u_1] + ..``) and ``h'`` from the rates of order ``order``.
    On the cycle ``a*`` of ``A_1 + .. + mu^{order-1} A_order`` (:func:`response_parts`'
    rate) ``<Z_v^2>`` is the true cycle's through ``mu^{order-1}``: order 1 is Lax's ``(1/a^2
    + g^2/lambda^2)/(2 omega0^2)``, order 2 right to ``O(mu)`` (van der Pol: ``1/8 - 69
    mu^2/512``, whose ``mu^2`` term is not the true one), order 3 right through ``mu^2``
    (van der Pol: ``1/8 + 7 mu^2/256 + O(mu^4)``, the adjoint Floquet cycle's;
    tests/test_spectrum_order2_vdp.py).

    Parameters
    ----------
    res : kbm.expansion.one_dof.KBMResult
        A derivation of order ``>= order`` (``u``, ``A``, ``B``).
    order : int
        ``1 <= order <= res.order``.

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
    num, det, _ = response_parts(res, order)
    return num / det


def mean_psi(expr: sp.Expr) -> sp.Expr:
    """The mean over ``psi`` of a trigonometric polynomial in ``psi``."""
    e = sp.expand(sp.expand(expr).rewrite(sp.exp))
    terms = e.args if isinstance(e, sp.Add) else (e,)
    return sp.factor(sp.Add(*[t for t in terms if not t.has(psi)]))


def taylor(expr: sp.Expr, terms: int) -> list[sp.Expr]:
    """The coefficients of ``mu^0 .. mu^{terms-1}`` of ``expr`` at ``mu = 0``."""
    out, d = [], expr
    for k in range(terms):
        out.append(sp.expand(d.subs(mu, 0)) / sp.factorial(k))
        d = sp.diff(d, mu)
    return out


def cycle_coefficients(rate: sp.Expr, a0: sp.Expr, terms: int) -> list[sp.Expr]:
    """``[a_0, a_1, ..]``: the root ``a* = a_0 + mu a_1 + mu^2 a_2 + ..`` of ``rate(a, mu)``
    (a series in ``mu``) near its ``mu = 0`` root ``a_0``, by matching powers of ``mu``."""
    coef = [a0]
    slope = sp.diff(rate.subs(mu, 0), a).subs(a, a0)
    for k in range(1, terms):
        a_mu = sum(mu**j * c for j, c in enumerate(coef))
        rest = taylor(rate.subs(a, a_mu), k + 1)[k]  # the mu^k term without a_k
        coef.append(sp.simplify(-rest / slope))
    return coef
