"""Exact ``mu``-series of the limit cycle of the averaged equations (polynomial ``F``).

A limit cycle of the KBM approximation is a positive root ``a*`` of
``A(a) = sum_{n>=1} mu**n A_n(a)`` (:mod:`kbm.slowflow.averaged`).  For polynomial ``F``
the root and the frequency ``omega* = omega0 + sum mu**n B_n(a*)`` are expanded
here as exact series in ``mu``: with ``a* = a_0 + sum_j c_j mu**j``,
``A_1(a_0) = 0``, every ``c_j`` solves a linear equation with the coefficient
``A_1'(a_0)``, so the series exists when the first-order cycle is hyperbolic.
The rates come from :func:`kbm.expansion.one_dof.run_recursion` in exact rational
arithmetic; no ``u_n`` beyond the last one needed is computed.

That route costs about ``order**6``.  When ``F`` is a polynomial with rational
coefficients and ``a_0`` is rational, the same coefficients come much faster
from the Lindstedt-Poincare recursion on the cycle itself
(:mod:`kbm.slowflow.cycle_series`: van der Pol to ``mu**40`` in a fraction of a second, to
``mu**100`` in seconds); :func:`limit_cycle_series` takes that route by default
and keeps the averaged one as ``method="kbm"``.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

import sympy as sp

from ..algebra.laurent import Q
from ..expansion.one_dof import MAX_ORDER, run_recursion
from ..errors import AveragedCycleError, OrderError, ParameterError
from ..output.latex import align_block, equation_lines
from ..model.builtins import Oscillator, get_model
from ..symbols import parse, a, mu

__all__ = ["LimitCycleSeries", "limit_cycle_series", "MAX_SERIES_ORDER"]

#: highest order of the exact series by the Lindstedt route (van der Pol: mu**100 takes
#: ~12 s, mu**200 several minutes; the cost grows like order**5)
MAX_SERIES_ORDER = 200

_METHODS = ("auto", "lindstedt", "kbm")


@dataclass(frozen=True)
class LimitCycleSeries:
    """Exact series ``a* = sum amplitude[n] mu**n``, ``omega* = sum omega[n] mu**n``."""

    order: int
    amplitude: tuple[sp.Expr, ...]
    omega: tuple[sp.Expr, ...]

    def amplitude_expr(self) -> sp.Expr:
        """``a* = sum_n amplitude[n] mu**n`` (truncated)."""
        return sp.Add(*[c * mu**n for n, c in enumerate(self.amplitude)])

    def omega_expr(self) -> sp.Expr:
        """``omega* = sum_n omega[n] mu**n`` (truncated)."""
        return sp.Add(*[c * mu**n for n, c in enumerate(self.omega)])

    def latex(self, width: int = 90) -> str:
        """Both series as a LaTeX ``align*`` block (long lines broken)."""
        o = f" + O(\\mu^{{{self.order + 1}}})"
        return align_block([
            equation_lines(r"\omega^*", self.omega_expr(), width, "rev-lex") + o,
            equation_lines(r"a^*", self.amplitude_expr(), width, "rev-lex") + o])

    def _repr_latex_(self) -> str:
        return "$\\displaystyle " + self.latex().replace("align*", "aligned") + "$"


def limit_cycle_series(model, order: int, *, root: object | None = None,
                       method: str = "auto") -> LimitCycleSeries:
    """Exact ``mu``-series of the limit-cycle amplitude and frequency (polynomial ``F``).

    Parameters
    ----------
    model
        A model or built-in name; ``F`` must be polynomial (exact rational algebra).
    order
        Highest power of ``mu`` in both series, ``0 <= order <= MAX_SERIES_ORDER``
        (``order <= MAX_ORDER - 1`` by the averaged route).
    root
        The first-order amplitude ``a_0`` (a positive root of ``A_1``); default:
        the only positive root, an error if there are several.
    method
        ``"lindstedt"``: the recursion on the cycle (:mod:`kbm.slowflow.cycle_series`), for
        ``F`` a polynomial with rational coefficients and rational ``a_0``;
        ``"kbm"``: the root of the averaged equations (needs ``A_1..A_{order+1}``,
        ``B_1..B_order``; also for irrational ``a_0``); ``"auto"``: the first when
        it applies, else the second.  Both give the same coefficients.

    Returns
    -------
    LimitCycleSeries
        ``amplitude[n]``, ``omega[n]``: exact coefficients of ``mu**n``.

    Raises
    ------
    kbm.errors.OrderError
        For an order out of range, or ``F`` that is not polynomial.
    kbm.errors.AveragedCycleError
        If ``A_1`` has no (or several) positive roots, or the cycle is not hyperbolic.
    kbm.errors.ParameterError
        If ``F`` has parameters without values, or ``root`` is not a root of ``A_1``.

    Examples
    --------
    >>> s = limit_cycle_series("vdp", 4)
    >>> s.omega
    (1, 0, -1/16, 0, 17/3072)
    >>> s.amplitude[:3]
    (2, 0, 1/64)
    """
    if not isinstance(order, int) or isinstance(order, bool) or order < 0:
        raise OrderError(f"the series order must be an integer >= 0, got {order!r}")
    if method not in _METHODS:
        raise ParameterError(f"unknown method {method!r}; use one of {', '.join(_METHODS)}")
    if order > MAX_SERIES_ORDER:
        raise OrderError(f"series order {order} is above the limit {MAX_SERIES_ORDER} of the "
                         f"exact series (its cost grows like order^5: mu^100 takes ~12 s); ask "
                         f"for order <= {MAX_SERIES_ORDER}, or use numeric_cycle_series for "
                         f"floating-point coefficients to higher orders")
    model, A1, a0 = first_order_cycle(model, root)
    terms = lindstedt_terms(model)
    fast = terms is not None and a0.is_Rational
    if method == "lindstedt" and not fast:
        raise OrderError("the Lindstedt route needs F polynomial with rational coefficients, "
                         f"a rational omega0 and a rational first-order amplitude (a0 = {a0}); "
                         "use method='kbm'")
    if fast and method != "kbm":
        return _lindstedt_exact(model, terms, a0, order)
    return _kbm_series(model, a0, order)


def first_order_cycle(model, root: object | None = None) -> tuple[Oscillator, sp.Expr, sp.Expr]:
    """``(model, A_1, a_0)``: the model checked, its first-order rate and the cycle's amplitude.

    Raises the errors of :func:`limit_cycle_series` for a model without an exact
    first-order cycle.
    """
    if isinstance(model, str):
        model = get_model(model)
    try:
        raw = run_recursion(model, 1, last_u=False)
    except OrderError as exc:  # pragma: no cover - order 1 is always available
        raise OrderError(str(exc)) from None
    if not raw.exact:
        raise OrderError("exact limit-cycle series need a polynomial F with rational "
                         "coefficients (the Bessel models go to KBM order 2 only); use "
                         "averaged_cycles for them")
    A1 = sp.expand(raw.A[0].as_expr())
    return raw.model, A1, _first_order_root(A1, root)


def lindstedt_terms(model: Oscillator) -> list | None:
    """``F``'s terms ``(i, j, c)`` if the Lindstedt route applies to ``model`` (``F`` a
    polynomial with rational coefficients, ``omega0`` a positive rational), else ``None``."""
    from .cycle_series import polynomial_terms

    w0 = model.omega0
    if not (w0.is_Rational and w0 > 0):
        return None
    return polynomial_terms(model.F)


def _lindstedt_exact(model: Oscillator, terms, a0: sp.Expr, order: int) -> LimitCycleSeries:
    from ..algebra.zfourier import arithmetic
    from .cycle_series import lindstedt_series

    ar = arithmetic("exact")
    w0 = model.omega0
    raw = lindstedt_series(terms, Fraction(int(w0.p), int(w0.q)),
                           ar.num(Fraction(int(a0.p), int(a0.q))), order, ar)
    return LimitCycleSeries(order=order, amplitude=(a0, *map(_rational, raw.amplitude[1:])),
                            omega=tuple(map(_rational, raw.omega)))


def _rational(v) -> sp.Rational:
    """A sympy Rational from a ``gmpy2.mpq``, ``fractions.Fraction`` or ``flint.fmpq``."""
    p = getattr(v, "numerator", None)
    if p is None:  # python-flint's fmpq
        return sp.Rational(int(v.p), int(v.q))
    return sp.Rational(int(p), int(v.denominator))


def _kbm_series(model: Oscillator, a0: sp.Expr, order: int) -> LimitCycleSeries:
    """The root of the averaged equations expanded in ``mu`` (the reference route)."""
    if order >= MAX_ORDER:
        raise OrderError(f"series order {order} is above the limit {MAX_ORDER - 1} of the "
                         f"averaged route (it needs the KBM expansion to order {order + 1}, "
                         f"and that is bounded by {MAX_ORDER}); ask for order <= "
                         f"{MAX_ORDER - 1}")
    raw = run_recursion(model, order + 1, last_u=False)
    # the exact algebra's coefficients are Laurent polynomials: expanded sympy polynomials
    A = [None] + [c.as_expr() for c in raw.A]
    B = [raw.model.omega0] + [c.as_expr() for c in raw.B]
    N = order
    exact_q = a0.is_Rational and all(sp.Poly(sp.expand(e), a).domain.is_QQ
                                     or sp.Poly(sp.expand(e), a).domain.is_ZZ
                                     for e in A[1:] + B)

    def num(v):
        v = sp.expand(v)
        return Q(int(v.p), int(v.q)) if exact_q else v

    def taylor(expr):  # at least to k = 1: A_1'(a0) is needed even for order 0
        p = sp.Poly(sp.expand(expr), a)
        out, k_fact = [], 1
        for k in range(max(N, 1) + 1):
            out.append(num(p.eval(a0) / k_fact))
            p = p.diff(a)
            k_fact *= k + 1
        return out

    TA = [None] + [taylor(A[n]) for n in range(1, N + 2)]
    TB = [taylor(B[n]) for n in range(0, N + 1)]
    zero = num(sp.Integer(0))
    one = num(sp.Integer(1))
    slope = TA[1][1]
    if slope == 0:
        raise AveragedCycleError(f"A_1'(a0) = 0 at a0 = {a0}: the cycle is not hyperbolic "
                                 "and has no regular series in mu")

    def mul(p, q):
        r = [zero] * (N + 1)
        for i, pi in enumerate(p):
            if pi == 0:
                continue
            for j in range(N + 1 - i):
                if q[j] != 0:
                    r[i + j] = r[i + j] + pi * q[j]
        return r if exact_q else [sp.expand(v) for v in r]

    def powers_of(c):
        pw = [[one] + [zero] * N]
        for _ in range(N):
            pw.append(mul(pw[-1], c))
        return pw

    c = [zero] * (N + 1)  # a* - a0 = sum_j c[j] mu**j
    for j in range(1, N + 1):
        # coefficient of mu**j in sum_n mu**(n-1) A_n(a0 + delta), the c_j term left out
        pw = powers_of(c)
        total = zero
        for n in range(1, j + 2):
            for k in range(N + 1):
                total = total + TA[n][k] * pw[k][j - (n - 1)]
        c[j] = -total / slope if exact_q else sp.radsimp(sp.expand(-total / slope))
    pw = powers_of(c)
    omega = [zero] * (N + 1)
    for n in range(N + 1):
        for k in range(N + 1):
            for j in range(N + 1 - n):
                omega[n + j] = omega[n + j] + TB[n][k] * pw[k][j]

    def out(v):
        return _rational(v) if exact_q else sp.radsimp(sp.expand(v))

    return LimitCycleSeries(order=N, amplitude=(a0, *[out(v) for v in c[1:]]),
                            omega=tuple(out(v) for v in omega))


def _first_order_root(A1: sp.Expr, root: object | None) -> sp.Expr:
    """``a_0``: the given ``root`` checked against ``A_1``, or the only positive root of ``A_1``."""
    if A1 == 0:
        raise AveragedCycleError("A_1 = 0: the first-order amplitude equation has no isolated "
                                 "cycle")
    free = sorted(map(str, A1.free_symbols - {a}))
    if free:
        example = ", ".join(f"{p!r}: 1" for p in free)
        raise ParameterError(f"A_1 = {A1} has parameters {free}; give them values for an exact "
                             f"series (e.g. get_model(name, {{{example}}}) or "
                             f"model.substitute({{{example}}}))")
    if root is None:
        cands = sorted((r for r in sp.roots(sp.Poly(A1, a)).keys() if r.is_positive),
                       key=float)
        if not cands:
            raise AveragedCycleError(f"A_1 = {A1} has no positive root: the first-order "
                                     "amplitude equation has no limit cycle")
        if len(cands) != 1:
            raise AveragedCycleError(f"A_1 = {A1} has {len(cands)} positive roots "
                                     f"{', '.join(map(str, cands))}; choose one with root=")
        return cands[0]
    a0 = sp.nsimplify(parse(root) if isinstance(root, str) else root)
    if sp.simplify(A1.subs(a, a0)) != 0:
        raise ParameterError(f"a0 = {a0} is not a root of A_1 = {A1}")
    if a0 == 0:  # a root of every A_1: a ZeroDivisionError traceback, or a* = 0 printed
        raise AveragedCycleError(f"a0 = 0 is the rest state, not a limit cycle; the cycles "
                                 f"are the positive roots of A_1 = {A1}: choose one with root=")
    return a0
