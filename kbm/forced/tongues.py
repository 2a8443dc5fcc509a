"""Transition curves (instability tongues) of parametric resonance, as series in ``mu``.

For ``F`` linear in ``(x, x')`` the slow flow is ``da/dt = a alpha(phi)``,
``dphi/dt = beta(phi) - (q/p) sigma`` (``alpha``, ``beta`` series in ``mu``); the trivial
state changes stability where a periodic solution of any amplitude exists, i.e. where
``alpha(phi) = 0`` and ``beta(phi) = (q/p) sigma`` have a common solution.  Written as
``phi = phi0 + sum mu**k phi_k``, ``sigma = sigma0 + sum mu**k sigma_k``, the leading
equations give the ends ``(phi0, sigma0)`` of the tongue and every further order one
linear system with the same matrix: an order-``N`` expansion gives ``sigma`` through
``mu**(N-1)``.

For the Mathieu equation ``x'' + (delta + eps cos s) x = 0`` (the built-in ``mathieu``
model: ``omega0 = 1/2``, ``nu = 1 + mu sigma``, ``s = nu t``, ``delta = 1/(4 nu^2)``,
``eps = mu/nu^2``) :func:`mathieu_transition` turns them into ``delta(eps)``, to be compared
with the characteristic values ``a_1``, ``b_1`` (Abramowitz & Stegun 20.2.25, with
``a = 4 delta``, ``q = 2 eps``).
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from ..errors import ModelError
from ..symbols import a, mu
from .model import phi, sigma
from .result import ForcedKBMResult

__all__ = ["TransitionCurve", "transition_curves", "mathieu_transition", "epsilon"]

#: the Mathieu amplitude ``eps`` of ``x'' + (delta + eps cos s) x = 0``
epsilon = sp.Symbol("epsilon")


@dataclass(frozen=True)
class TransitionCurve:
    """One boundary ``sigma(mu)`` of an instability tongue, a polynomial in ``mu``."""

    phase: sp.Expr
    sigma: sp.Expr
    order: int

    def latex(self) -> str:
        """``\\sigma = ...``."""
        return r"\sigma = " + sp.latex(self.sigma)

    def lambdify(self):
        """``sigma(mu, *parameters)`` as a numpy function (parameters sorted by name)."""
        params = sorted(self.sigma.free_symbols - {mu}, key=lambda s: s.name)
        return sp.lambdify((mu, *params), self.sigma, modules="numpy")


def transition_curves(result: ForcedKBMResult) -> list[TransitionCurve]:
    """The transition curves ``sigma(mu)`` through ``mu**(N-1)`` of a parametric resonance.

    Raises
    ------
    kbm.errors.ModelError
        If ``F`` is not linear in ``(x, x')`` (the rates are then not ``a alpha(phi)``,
        ``beta(phi)``), if there is no resonance, or if the first-order equations have no
        simple root (the tongue opens at a higher order: not treated).
    """
    res = result.resonance
    if res is None:
        raise ModelError("transition curves need a declared resonance p/q")
    N = result.order
    alphas = [sp.expand(sp.cancel(A / a)) for A in result.A]
    betas = [sp.expand(B) for B in result.B]
    if any(e.has(a) for e in alphas + betas):
        raise ModelError(f"the rates of {result.model.name!r} depend on the amplitude: F must "
                         "be linear in x and xdot (a parametric excitation) for transition "
                         "curves")
    qp = sp.Rational(res.q, res.p)
    eq1 = alphas[0]
    eq2 = betas[0] - qp * sigma
    if not eq1.has(phi):
        raise ModelError(f"the first-order amplitude rate of {result.model.name!r} at the "
                         f"resonance {res} does not depend on phi (A_1 = {result.A[0]}): this "
                         "tongue opens at a higher order of mu, which transition_curves does "
                         "not treat; its edges can be located numerically (Floquet)")
    roots = sp.solve(eq1, phi)
    per = 2 * sp.pi / res.p
    phis = []
    for r in roots:
        if r.is_real is False:
            continue
        r = sp.nsimplify(r % per) if r.is_number else r  # symbolic roots: kept as solved
        if r not in phis:
            phis.append(r)
    phis.sort(key=lambda r: (not r.is_number, float(r) if r.is_number else 0.0, str(r)))
    out = []
    eta = sp.Symbol("eta")
    e1 = sum(mu**n * alphas[n] for n in range(N))
    e2 = sum(mu**n * betas[n] for n in range(N)) - qp * sigma
    for p0 in phis:
        s0 = sp.solve(eq2.subs(phi, p0), sigma)
        if len(s0) != 1:
            continue
        s0 = s0[0]
        M = sp.Matrix([[sp.diff(eq1, phi), sp.diff(eq1, sigma)],
                       [sp.diff(eq2, phi), sp.diff(eq2, sigma)]]).subs({phi: p0, sigma: s0})
        if sp.simplify(M.det()) == 0:
            raise ModelError("the first-order transition equations have a double root: the "
                             "tongue opens at a higher order, which is not treated")
        # phi = p0 + eta: sin/cos of multiples of phi as polynomials in eta (Taylor), then
        # order by order eta = (known) + mu^k f, sigma = (known) + mu^k s: the coefficient
        # of mu^k is linear in (f, s)
        f, s_ = sp.symbols("f s")
        taylor = [_in_eta(e, p0, eta, N) for e in (e1, e2)]
        eta_known, sig_known = sp.Integer(0), s0
        for k in range(1, N):
            subs = {eta: eta_known + mu**k * f, sigma: sig_known + mu**k * s_}
            c = [_coeff(T, subs, k) for T in taylor]
            step = sp.solve(c, [f, s_], dict=True)
            if not step:
                raise ModelError(f"no solution of the order-{k} transition equations")
            eta_known += mu**k * sp.nsimplify(step[0][f])
            sig_known += mu**k * sp.nsimplify(step[0][s_])
        out.append(TransitionCurve(phase=p0, sigma=sp.expand(sig_known), order=N))
    return out


def _in_eta(expr: sp.Expr, p0: sp.Expr, eta: sp.Symbol, n: int) -> sp.Expr:
    """``expr`` with ``phi = p0 + eta`` and every ``sin``/``cos`` Taylor-expanded in ``eta``."""
    def taylor(f):
        k = f.args[0].coeff(phi)
        base = k * p0
        c0, s0 = sp.cos(base), sp.sin(base)
        ce = sum((-1)**j * (k * eta)**(2 * j) / sp.factorial(2 * j) for j in range(n))
        se = sum((-1)**j * (k * eta)**(2 * j + 1) / sp.factorial(2 * j + 1) for j in range(n))
        if isinstance(f, sp.cos):
            return c0 * ce - s0 * se
        return s0 * ce + c0 * se

    reps = {f: taylor(f) for f in expr.atoms(sp.sin, sp.cos) if f.has(phi)}
    return sp.expand(expr.xreplace(reps))


def _coeff(expr: sp.Expr, subs: dict, k: int) -> sp.Expr:
    """The coefficient of ``mu**k`` of ``expr`` (a polynomial in ``mu``, ``eta``, ``sigma``)
    after ``subs`` (``eta``, ``sigma`` as polynomials in ``mu``, ``eta = O(mu)``)."""
    poly = sp.Poly(expr, mu, *subs)
    out = sp.Integer(0)
    vals = list(subs.values())
    for exps, c in poly.terms():
        if exps[0] > k or exps[0] + exps[1] > k:  # eta = O(mu)
            continue
        term = sp.Integer(1)
        for v, e in zip(vals, exps[1:]):
            term = _trunc(sp.expand(term * v**e), k - exps[0])
        out += c * term.coeff(mu, k - exps[0]) if k - exps[0] else c * term.subs(mu, 0)
    return sp.expand(out)


def _trunc(expr: sp.Expr, n: int) -> sp.Expr:
    """``expr`` (expanded) without the powers of ``mu`` above ``n``."""
    return sp.Add(*[t for t in sp.Add.make_args(expr) if sp.degree(t, mu) <= n])


def _mul(u: list, v: list, n: int) -> list:
    out = [sp.Integer(0)] * n
    for i, x in enumerate(u[:n]):
        if x:
            for j, y in enumerate(v[:n - i]):
                out[i + j] += x * y
    return out


def _inv(u: list, n: int) -> list:
    """``1/u`` as a truncated power series (``u[0] != 0``)."""
    out = [1 / u[0]] + [sp.Integer(0)] * (n - 1)
    for k in range(1, n):
        out[k] = -sum(u[j] * out[k - j] for j in range(1, min(k, len(u) - 1) + 1)) / u[0]
    return out


def _compose(u: list, v: list, n: int) -> list:
    """``u(v(x))`` for ``v[0] = 0`` (truncated)."""
    out = [sp.Integer(0)] * n
    power = [sp.Integer(1)] + [sp.Integer(0)] * (n - 1)
    for k in range(n):
        if k < len(u):
            out = [o + u[k] * p for o, p in zip(out, power)]
        power = _mul(power, v, n)
    return out


def mathieu_transition(curve: TransitionCurve, order: int | None = None) -> sp.Expr:
    """``delta(eps)`` of ``x'' + (delta + eps cos s) x = 0`` from a transition curve of the
    built-in ``mathieu`` model, expanded through ``eps**order`` (default the curve's order).

    With ``nu = 1 + mu sigma(mu)``: ``eps = mu/nu**2``, ``delta = 1/(4 nu**2)``; ``mu`` is
    eliminated by series reversion.
    """
    n = (curve.order if order is None else order) + 1
    sig = sp.Poly(curve.sigma, mu).all_coeffs()[::-1] if curve.sigma.has(mu) else [curve.sigma]
    nu_ = [sp.Integer(1)] + [sp.Rational(c) for c in sig] + [sp.Integer(0)] * n
    inv2 = _inv(_mul(nu_, nu_, n), n)  # 1/nu^2 as a series in mu
    eps_of_mu = [sp.Integer(0)] + inv2[:n - 1]
    # revert eps = mu + c2 mu^2 + ...: mu = eps - (c2 mu^2 + ...), iterated
    m = [sp.Integer(0), sp.Integer(1)] + [sp.Integer(0)] * (n - 2)
    for _ in range(n):
        e = _compose(eps_of_mu, m, n)
        m = [mi - (ei - (1 if i == 1 else 0)) for i, (mi, ei) in enumerate(zip(m, e))]
    delta = _compose([c / 4 for c in inv2], m, n)
    return sp.Add(*[c * epsilon**i for i, c in enumerate(delta)])
