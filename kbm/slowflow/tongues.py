"""Transition curves (instability tongues) of parametric resonance, as series in ``mu``.

The slow flow
-------------
For ``F`` linear in ``(x, x')`` the slow flow of :func:`~kbm.expansion.forced.derive_forced` is
``da/dt = a alpha``, ``dphi/dt = beta - mu (q/p) sigma`` with ``alpha = sum mu**n alpha_n``
(``alpha_n = A_n/a``) and ``beta = sum mu**n beta_n`` (``beta_n = B_n``) functions of
``phi`` and ``sigma`` alone.  ``sigma`` enters them only through ``nu = nu0 + mu sigma``,
so ``alpha_n``, ``beta_n`` are polynomials in ``sigma`` of degree at most ``n - 1``.  In
the complex amplitude ``z = a exp(i phi)`` the flow is linear,
``dz/dt = lambda z + kappa zbar``: a linear ``F`` has the resonant ``psi``-harmonics
``+-1`` only, so ``phi`` enters through ``2 phi`` (``cos``/``sin``) and only through
``kappa``.  The trivial state ``z = 0`` changes stability where a solution of constant
``(a, phi)`` exists, i.e. where

.. math::  E_1 = \\sum_n \\mu^{n-1}\\alpha_n(\\varphi, \\sigma) = 0, \\qquad
           E_2 = \\sum_n \\mu^{n-1}\\beta_n(\\varphi, \\sigma) - (q/p)\\,\\sigma = 0

have a common solution ``phi`` (equivalently ``|lambda| = |kappa|``).

The opening order
-----------------
Let ``m`` be the lowest order at which ``alpha_m`` depends on ``phi`` (the *opening
order*).  For the Mathieu equation ``x'' + (delta + eps cos s) x = 0`` the tongue at
``delta = n**2/4`` opens at ``m = n``: its width is ``O(eps**n)``.  Below ``m`` the rates
are ``phi``-free; ``alpha_n = 0`` for ``n < m`` is required (a ``phi``-free ``alpha_n``,
e.g. a damping, is then larger than the parametric term at small ``mu``: no tongue).

The perturbation scheme (any ``m >= 1``): write

.. math::  \\sigma = c(\\mu) + \\mu^{m-1}\\tau(\\mu), \\qquad
           c = s_0 + s_1\\mu + \\dots + s_{m-2}\\mu^{m-2},

where the *centre* ``c(mu)``, common to both edges, makes the ``phi``-free equation
``E_2`` vanish through ``mu**(m-2)`` (at ``mu**k`` the unknown ``s_k`` enters only as
``-(q/p) s_k``, the ``sigma``-dependence of ``beta_n`` carrying a factor ``mu``: one linear
equation per order).  Then ``G_i = E_i(phi, c + mu**(m-1) tau)/mu**(m-1)`` are power series
in ``mu`` whose leading terms are

.. math::  \\alpha_m(\\varphi_0, s_0) = 0, \\qquad
           -(q/p)\\,\\tau_0 + \\beta_m(\\varphi_0, s_0) + b_{m-1} = 0

(``b_{m-1}`` the ``mu**(m-1)`` coefficient of the ``phi``-free part of ``E_2`` at
``sigma = c``): the simple roots ``phi0`` of ``alpha_m`` are the two edges, which split at
``mu**(m-1)`` in ``sigma`` (``mu**m`` in ``nu``).  With ``phi = phi0 + sum mu**k phi_k``
every further order ``k`` is one linear system in ``(phi_k, tau_k)`` with the matrix
``d(G_1, G_2)/d(phi, tau)`` at ``mu = 0``, nonsingular at a simple root.  An order-``N``
expansion knows ``alpha_n``, ``beta_n`` for ``n <= N``, hence ``G`` through
``mu**(N-m)``, ``tau`` through ``mu**(N-m)`` and ``sigma`` through ``mu**(N-1)``, for every
``m <= N`` (``N >= m`` is needed).  For ``m = 1`` the scheme is the first-order one
(``c = 0``, ``tau = sigma``).  The linear symmetry ``x -> -x`` (``phi -> phi + pi``) makes
roots ``pi`` apart the same edge.

This is the averaging counterpart of the strained-parameter (Lindstedt-Poincare) transition
curves of the Mathieu equation (Nayfeh, *Perturbation Methods*, 1973, ch. 3; Nayfeh &
Mook, *Nonlinear Oscillations*, 1979, ch. 5; Rand, *Lecture Notes on Nonlinear
Vibrations*, the two-variable expansion of the ``delta = 1`` tongue, ``delta = 1 + 5 eps**2
/12``, ``1 - eps**2/12``).

Mathieu
-------
``x'' + omega0**2 x = -mu x cos(nu t)`` with ``s = nu t`` is ``x'' + (delta + eps cos s)
x = 0`` with ``delta = omega0**2/nu**2``, ``eps = mu/nu**2``; the tongue at ``delta =
n**2/4`` is the resonance ``nu0 = 2 omega0/n`` (``p/q = 2/n``).  The built-ins ``mathieu``
(``n = 1``: ``omega0 = 1/2``, 2/1), ``mathieu-2`` (``omega0 = 1``, 1/1) and ``mathieu-3``
(``omega0 = 3/2``, 2/3) cover the first three.  :func:`mathieu_transition` turns a curve
into ``delta(eps)``, to be compared with the characteristic values ``a_n``, ``b_n``
(Abramowitz & Stegun 20.2.25, with ``a = 4 delta``, ``q = 2 eps``).

Examples
--------
>>> from kbm.expansion.forced import derive_forced
>>> cs = transition_curves(derive_forced("mathieu-2", 2))
>>> [c.opens_at for c in cs], [c.sigma for c in cs]
([2, 2], [-5*mu/24, mu/24])
>>> [mathieu_transition(c) for c in cs]
[5*epsilon**2/12 + 1, 1 - epsilon**2/12]
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from ..errors import ModelError
from ..symbols import a, mu
from ..model.forced import phi, sigma, theta
from ..algebra.power_series import series_compose, series_product, series_reciprocal
from ..expansion.forced_result import ForcedKBMResult

__all__ = ["TransitionCurve", "transition_curves", "mathieu_transition", "epsilon"]

#: the Mathieu amplitude ``eps`` of ``x'' + (delta + eps cos s) x = 0``
epsilon = sp.Symbol("epsilon")


@dataclass(frozen=True)
class TransitionCurve:
    """One boundary ``sigma(mu)`` of an instability tongue, a polynomial in ``mu``.

    Attributes
    ----------
    phase
        ``phi0``: the resonant phase of the edge's periodic solution at ``mu = 0``.
    sigma
        ``sigma(mu)`` through ``mu**(order-1)``.
    order
        ``N``, the order of the expansion it comes from.
    opens_at
        ``m``, the order at which the tongue opens (``alpha_m`` depends on ``phi``); the two
        edges split at ``mu**(m-1)``.
    omega0, nu0, F
        The model's ``omega0``, the forcing frequency ``nu0 = (p/q) omega0`` at
        ``sigma = 0`` and its ``F`` (for :func:`mathieu_transition`); ``None`` when not
        known.
    """

    phase: sp.Expr
    sigma: sp.Expr
    order: int
    opens_at: int = 1
    omega0: sp.Expr | None = None
    nu0: sp.Expr | None = None
    F: sp.Expr | None = None

    def latex(self) -> str:
        """``\\sigma = ...``."""
        return r"\sigma = " + sp.latex(self.sigma)

    def lambdify(self):
        """``sigma(mu, *parameters)`` as a numpy function (parameters sorted by name)."""
        params = sorted(self.sigma.free_symbols - {mu}, key=lambda s: s.name)
        return sp.lambdify((mu, *params), self.sigma, modules="numpy")


def transition_curves(result: ForcedKBMResult) -> list[TransitionCurve]:
    """The transition curves ``sigma(mu)`` through ``mu**(N-1)`` of a parametric resonance.

    The tongue may open at any order ``m <= N`` (see the module docstring for the
    scheme): the edges share ``sigma``'s terms below ``mu**(m-1)`` and split there.

    Parameters
    ----------
    result
        An order-``N`` resonant expansion of a model with ``F`` linear in ``(x, x')``.

    Returns
    -------
    list of TransitionCurve
        One per edge (a simple root ``phi0`` of ``alpha_m``, modulo ``pi``), sorted by
        ``phi0``.

    Raises
    ------
    kbm.errors.ModelError
        If ``F`` is not linear in ``(x, x')`` (the rates are then not ``a alpha(phi)``,
        ``beta(phi)``), if there is no resonance, if no ``A_n`` (``n <= N``) depends on
        ``phi`` (the message gives the order at which the tongue opens, found by a
        derivation to a higher order, or why it never opens), if a ``phi``-free amplitude
        rate (a damping) comes before the opening order, or if the leading equations have
        no simple root.
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
    m = next((n + 1 for n, e in enumerate(alphas) if e.has(phi)), None)
    if m is None:
        raise ModelError(_no_opening_message(result))
    for n in range(m - 1):
        if betas[n].has(phi):
            raise ModelError(f"B_{n + 1} of {result.model.name!r} depends on phi but A_{n + 1} "
                             "does not: not the slow flow of a linear parametric excitation")
        if alphas[n] != 0:
            raise ModelError(
                f"the amplitude rate of {result.model.name!r} has the phi-free part A_{n + 1} "
                f"= {result.A[n]} (a damping or growth) before the tongue opens at order {m}: "
                f"at small mu the term mu^{n + 1} A_{n + 1} dominates the parametric term "
                f"mu^{m} A_{m}, so there is no tongue at fixed parameters; one needs its "
                f"coefficient to be O(mu^{m - n - 1}) (remove it here, or locate the edges "
                "numerically with Floquet multipliers)")
    if m == 1:
        eq1 = alphas[0]
        eq2 = betas[0] - qp * sigma
        e1 = sum(mu**n * alphas[n] for n in range(N))
        e2 = sum(mu**n * betas[n] for n in range(N)) - qp * sigma
        centre = sp.Integer(0)
    else:
        centre, e1, e2 = _rescaled(alphas, betas, qp, m, N)
        eq1, eq2 = e1.subs(mu, 0), e2.subs(mu, 0)
    K = N - m + 1  # the orders mu^0..mu^(N-m) of the rescaled equations are known
    roots = sp.solve(eq1, phi)
    per = 2 * sp.pi / res.p
    phis = []
    for r in roots:
        if r.is_real is False:
            continue
        r = sp.nsimplify(r % per) if r.is_number else r  # symbolic roots: kept as solved
        if r not in phis and not (r.is_number and sp.nsimplify((r + sp.pi) % per) in phis):
            phis.append(r)  # phi and phi + pi: x -> -x, the same edge
    phis.sort(key=lambda r: (not r.is_number, float(r) if r.is_number else 0.0, str(r)))
    out = []
    eta = sp.Symbol("eta")
    for p0 in phis:
        s0 = sp.solve(eq2.subs(phi, p0), sigma)
        if len(s0) != 1:
            continue
        s0 = s0[0]
        M = sp.Matrix([[sp.diff(eq1, phi), sp.diff(eq1, sigma)],
                       [sp.diff(eq2, phi), sp.diff(eq2, sigma)]]).subs({phi: p0, sigma: s0})
        if sp.simplify(M.det()) == 0:
            raise ModelError(f"the leading (order-{m}) transition equations of "
                             f"{result.model.name!r} have a double root at phi = {p0}: a "
                             "degenerate tongue, which is not treated")
        # phi = p0 + eta: sin/cos of multiples of phi as polynomials in eta (Taylor), then
        # order by order eta = (known) + mu^k f, sigma = (known) + mu^k s: the coefficient
        # of mu^k is linear in (f, s)
        f, s_ = sp.symbols("f s")
        taylor = [_in_eta(e, p0, eta, K) for e in (e1, e2)]
        eta_known, sig_known = sp.Integer(0), s0
        for k in range(1, K):
            subs = {eta: eta_known + mu**k * f, sigma: sig_known + mu**k * s_}
            c = [_coeff(T, subs, k) for T in taylor]
            step = sp.solve(c, [f, s_], dict=True)
            if not step:
                raise ModelError(f"no solution of the order-{k} transition equations")
            eta_known += mu**k * sp.nsimplify(step[0][f])
            sig_known += mu**k * sp.nsimplify(step[0][s_])
        out.append(TransitionCurve(
            phase=p0, sigma=sp.expand(centre + mu**(m - 1) * sig_known), order=N, opens_at=m,
            omega0=result.model.omega0,
            nu0=sp.Rational(res.p, res.q) * result.model.omega0, F=result.model.F))
    return out


def _rescaled(alphas: list, betas: list, qp: sp.Rational, m: int,
              N: int) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """The centre ``c(mu)`` and the rescaled equations ``G_1``, ``G_2`` (in ``phi`` and
    ``tau``, written ``sigma``) of a tongue opening at order ``m >= 2``, through
    ``mu**(N-m)``; see the module docstring."""
    s = sp.symbols(f"s0:{m - 1}")
    c = sum(s[k] * mu**k for k in range(m - 1))
    free = sp.expand((sum(mu**n * betas[n] for n in range(m - 1)) - qp * sigma)
                     .xreplace({sigma: c}))
    known: dict = {}
    for k in range(m - 1):
        ck = sp.expand(free.coeff(mu, k).xreplace(known))
        sol = sp.solve(ck, s[k])
        if len(sol) != 1:
            raise ModelError(f"the centre of the tongue is not determined at mu^{k} "
                             f"({ck} = 0)")
        known[s[k]] = sp.expand(sol[0])  # exact (a linear equation)
    centre = sp.expand(c.xreplace(known))
    sig = centre + mu**(m - 1) * sigma

    def series(e: sp.Expr, lo: int, hi: int) -> list:
        e = sp.expand(e)
        return [sp.expand(e.coeff(mu, k)) for k in range(lo, hi + 1)]

    g1 = series(sum(mu**n * alphas[n] for n in range(m - 1, N)).xreplace({sigma: sig}),
                m - 1, N - 1)
    num = (sum(mu**n * betas[n] for n in range(N)) - qp * sigma).xreplace({sigma: sig})
    low = series(num, 0, m - 2)
    if any(sp.simplify(v) != 0 for v in low):
        raise ModelError("internal: the centre of the tongue does not cancel the phi-free "
                         f"rates ({low})")
    g2 = series(num, m - 1, N - 1)
    return (centre, sp.Add(*[v * mu**k for k, v in enumerate(g1)]),
            sp.Add(*[v * mu**k for k, v in enumerate(g2)]))


def _no_opening_message(result: ForcedKBMResult) -> str:
    """Why no ``A_n`` of ``result`` depends on ``phi``, and at which order it would."""
    from ..expansion.forced import MAX_ORDER, derive_forced

    res, N, model = result.resonance, result.order, result.model
    head = (f"A_1..A_{N} of {model.name!r} at the resonance {res} do not depend on phi "
            f"(no instability tongue through order {N})")
    if not model.shifted(model.omega0).has(theta):
        return head + ": F has no parametric (theta-dependent) term, so no tongue opens at "             "any order; add one, e.g. -h*x*cos(theta)"
    if res.p > 2:
        return head + f": a linear F has the resonant harmonics psi = +-1 only, which meet "             f"p phi = p psi - q theta for p = 1 or 2, so at p/q = {res} no tongue opens at "             "any order (a Mathieu tongue is at nu = 2 omega0/n: resonance 2/n)"
    probe = min(MAX_ORDER, max(N + 1, -(-2 * res.q // res.p)))
    if probe > N:
        r = derive_forced(model, probe, resonance=res)
        m = next((n + 1 for n, A in enumerate(r.A) if sp.cancel(A / a).has(phi)), None)
        if m is not None:
            return head + f": the tongue opens at order {m} (A_{m} depends on phi); derive "                 f"at order N >= {m} (order N gives sigma through mu^(N-1), the edges "                 f"splitting at mu^{m - 1})"
        return head + f" nor through order {probe}: the tongue opens later, if at all "             f"(the order is limited to {MAX_ORDER})"
    return head + f" (the order is limited to {MAX_ORDER})"


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


def mathieu_transition(curve: TransitionCurve, order: int | None = None) -> sp.Expr:
    """``delta(eps)`` of ``x'' + (delta + eps cos s) x = 0`` from a transition curve of a
    Mathieu model ``F = -x cos(theta)``, expanded through ``eps**order`` (default the
    curve's order).

    With ``s = nu t``, ``nu = nu0 + mu sigma(mu)``: ``x'' + omega0**2 x = -mu x cos(nu t)``
    is the Mathieu equation with ``delta = omega0**2/nu**2`` and ``eps = mu/nu**2``; ``mu``
    is eliminated by series reversion.  Any ``omega0`` and resonance: the built-ins
    ``mathieu``, ``mathieu-2``, ``mathieu-3`` give the tongues at ``delta = 1/4, 1, 9/4``.

    Raises
    ------
    kbm.errors.ModelError
        If the curve's model is not ``F = -x cos(theta)`` with a numeric ``omega0`` (or the
        curve does not say: not from :func:`transition_curves`).
    """
    if curve.F is None or curve.omega0 is None or curve.nu0 is None:
        raise ModelError("mathieu_transition needs a curve from transition_curves (which "
                         "records omega0, nu0 and F)")
    from ..symbols import x

    if sp.expand(curve.F + x * sp.cos(theta)) != 0 or not curve.omega0.is_Rational:
        raise ModelError(f"mathieu_transition is for F = -x*cos(theta) with a numeric omega0 "
                         f"(x'' + omega0^2 x = -mu x cos(nu t)), got F = {curve.F}, omega0 = "
                         f"{curve.omega0}")
    n = (curve.order if order is None else order) + 1
    sig = sp.Poly(curve.sigma, mu).all_coeffs()[::-1] if curve.sigma.has(mu) else [curve.sigma]
    nu_ = [sp.Rational(curve.nu0)] + [sp.Rational(c) for c in sig] + [sp.Integer(0)] * n
    inv2 = series_reciprocal(series_product(nu_, nu_, n), n)  # 1/nu^2 as a series in mu
    eps_of_mu = [sp.Integer(0)] + inv2[:n - 1]
    # revert eps = e1 mu + e2 mu^2 + ... (e1 = 1/nu0^2): mu = (eps - (e2 mu^2 + ...))/e1,
    # iterated
    e1 = eps_of_mu[1]
    m = [sp.Integer(0), 1 / e1] + [sp.Integer(0)] * (n - 2)
    for _ in range(n):
        e = series_compose(eps_of_mu, m, n)
        m = [mi - (ei - (1 if i == 1 else 0)) / e1 for i, (mi, ei) in enumerate(zip(m, e))]
    delta = series_compose([curve.omega0**2 * c for c in inv2], m, n)
    return sp.Add(*[c * epsilon**i for i, c in enumerate(delta)])
