"""Limit cycles of the averaged equations ``da/dt = sum mu**n A_n(a)``.

A limit cycle of the KBM approximation is a positive root ``a*`` of
``A(a) = sum_{n=1}^N mu**n A_n(a)``; it is stable when ``dA/da(a*) < 0``, its
frequency is ``omega* = omega0 + sum mu**n B_n(a*)`` and the non-trivial
Floquet multiplier it predicts is ``exp(T dA/da(a*))`` with ``T = 2 pi/omega*``.

For polynomial ``F`` the root and the frequency are also expanded as exact
series in ``mu`` (:func:`limit_cycle_series`): with ``a* = a_0 + sum_j c_j mu**j``,
``A_1(a_0) = 0``, every ``c_j`` solves a linear equation with the coefficient
``A_1'(a_0)``, so the series exists when the first-order cycle is hyperbolic.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np
import sympy as sp

from .errors import KBMError, OrderError, ParameterError
from .result import KBMResult
from .symbols import a, mu

__all__ = ["AveragedCycle", "AveragedRates", "averaged_cycles", "averaged_rates",
           "LimitCycleSeries", "limit_cycle_series"]


@dataclass(frozen=True)
class AveragedCycle:
    """A limit cycle of the order-``order`` averaged equations.

    Attributes
    ----------
    amplitude
        ``a*``, the predicted first-harmonic amplitude.
    frequency, period
        ``omega* = omega0 + sum mu**n B_n(a*)`` and ``2 pi/omega*``.
    dA_da
        Slope of the amplitude equation at ``a*``.
    stable
        ``dA_da < 0``.
    floquet_multiplier
        The predicted non-trivial Floquet multiplier ``exp(period * dA_da)``.
    """

    order: int
    amplitude: float
    frequency: float
    period: float
    dA_da: float
    stable: bool
    floquet_multiplier: float


def _values(result: KBMResult, values: Mapping[str, object]) -> tuple[float, list[float]]:
    vals = dict(values)
    if "mu" not in vals:
        raise ParameterError("the averaged limit cycle needs a value of mu")
    missing = [p for p in result.params if p not in vals]
    if missing:
        raise ParameterError(f"give values for {', '.join(missing)} (e.g. --param "
                             f"{missing[0]}=1)")
    extra = set(vals) - set(result.params) - {"mu"}
    if extra:
        raise ParameterError(f"unknown parameter(s) {', '.join(sorted(extra))}; this result has "
                             f"{', '.join(result.params) or 'no parameters'} and mu")
    return float(sp.sympify(vals["mu"])), [float(sp.sympify(vals[p])) for p in result.params]


def averaged_cycles(result: KBMResult, values: Mapping[str, object], *,
                    order: int | None = None, a_max: float = 20.0,
                    n_grid: int = 4000) -> tuple[AveragedCycle, ...]:
    """All limit cycles ``0 < a* <= a_max`` of the averaged amplitude equation.

    Parameters
    ----------
    result
        A KBM derivation.
    values
        ``mu`` and every parameter left symbolic in ``result`` (numbers).
    order
        Use ``A_1..A_order`` (default: all of ``result``).
    a_max, n_grid
        Roots are bracketed by sign changes of ``A(a)/a`` on ``n_grid`` points of
        ``(0, a_max]`` and refined with Brent's method to ``1e-14``; roots
        closer together than the grid spacing can be missed.

    Returns
    -------
    tuple of AveragedCycle
        In increasing amplitude; empty when the averaged equation has no cycle
        (e.g. pure damping).  Roots where the averaged frequency
        ``omega0 + sum mu**n B_n`` is not positive are left out: the truncated
        expansion has broken down there.

    Examples
    --------
    >>> from kbm import derive
    >>> c, = averaged_cycles(derive("vdp", 2), {"mu": 0.1})
    >>> round(c.amplitude, 12), c.stable
    (2.0, True)
    """
    return averaged_rates(result, order=order).cycles(values, a_max=a_max, n_grid=n_grid)


@dataclass(frozen=True)
class AveragedRates:
    """The averaged equations of a derivation as numerical functions of ``(a, mu, *params)``.

    Lambdifying is the costly step of :func:`averaged_cycles`; an
    ``AveragedRates`` is built once (:func:`averaged_rates`) and evaluated for
    many parameter values (as the limit-cycle guesses of a sweep do).

    Attributes
    ----------
    order, params
        The truncation order and the names of the parameters after ``mu``.
    rate, slope, frequency
        ``A(a) = sum_{n<=order} mu**n A_n(a)``, ``dA/da`` and
        ``omega0 + sum mu**n B_n(a)`` (vectorised in ``a``).
    """

    order: int
    params: tuple[str, ...]
    rate: Callable
    slope: Callable
    frequency: Callable
    result: KBMResult

    def cycles(self, values: Mapping[str, object], *, a_max: float = 20.0,
               n_grid: int = 4000) -> tuple[AveragedCycle, ...]:
        """The cycles ``0 < a* <= a_max`` at ``values``; see :func:`averaged_cycles`."""
        from scipy.optimize import brentq

        m, pars = _values(self.result, values)
        f, df, phase = self.rate, self.slope, self.frequency
        grid = np.linspace(a_max / n_grid, a_max, n_grid)
        g = f(grid, m, *pars) / grid
        if not np.all(np.isfinite(g)):
            bad = grid[~np.isfinite(g)][0]
            raise KBMError(f"the averaged amplitude equation is not finite at a = {bad:.6g}")
        sg = np.sign(g)
        roots = list(grid[sg == 0])
        for i in np.nonzero(sg[:-1] * sg[1:] < 0)[0]:
            roots.append(brentq(lambda s: float(f(s, m, *pars)) / s, grid[i], grid[i + 1],
                                xtol=1e-15, rtol=1e-14))
        cycles = []
        for root in sorted(roots):
            slope = float(df(root, m, *pars))
            omega = float(phase(root, m, *pars))
            if not omega > 0:
                # the truncated phase equation gives no rotation here: the expansion has
                # broken down at this amplitude, so this root is not a cycle it predicts
                continue
            T = 2 * np.pi / omega
            cycles.append(AveragedCycle(order=self.order, amplitude=float(root),
                                        frequency=omega, period=T, dA_da=slope,
                                        stable=slope < 0,
                                        floquet_multiplier=float(np.exp(T * slope))))
        return tuple(cycles)


def averaged_rates(result: KBMResult, *, order: int | None = None) -> AveragedRates:
    """Lambdify the averaged equations of ``result`` up to ``order`` (default: all)."""
    from .evaluate import numpy_function

    N = result._order(order)
    rate = sp.Add(*[mu**n * result.A[n] for n in range(1, N + 1)])
    args = [a, mu, *[sp.Symbol(p) for p in result.params]]
    return AveragedRates(
        order=N, params=tuple(result.params), result=result,
        rate=numpy_function(rate, args), slope=numpy_function(sp.diff(rate, a), args),
        frequency=numpy_function(sp.Add(*[mu**n * result.B[n] for n in range(0, N + 1)]),
                                 args))


@dataclass(frozen=True)
class LimitCycleSeries:
    """Exact series ``a* = sum amplitude[n] mu**n``, ``omega* = sum omega[n] mu**n``."""

    order: int
    amplitude: tuple[sp.Expr, ...]
    omega: tuple[sp.Expr, ...]

    def amplitude_expr(self) -> sp.Expr:
        return sp.Add(*[c * mu**n for n, c in enumerate(self.amplitude)])

    def omega_expr(self) -> sp.Expr:
        return sp.Add(*[c * mu**n for n, c in enumerate(self.omega)])

    def latex(self, width: int = 90) -> str:
        """Both series as a LaTeX ``align*`` block (long lines broken)."""
        from .latex import equation_lines

        o = f" + O(\\mu^{{{self.order + 1}}})"
        return ("\\begin{align*}\n"
                + equation_lines(r"\omega^*", self.omega_expr(), width, "rev-lex") + o
                + " \\\\\n" + equation_lines(r"a^*", self.amplitude_expr(), width, "rev-lex") + o
                + "\n\\end{align*}")

    def _repr_latex_(self) -> str:
        return "$\\displaystyle " + self.latex().replace("align*", "aligned") + "$"


def limit_cycle_series(model, order: int, *, root: object | None = None) -> LimitCycleSeries:
    """Exact ``mu``-series of the limit-cycle amplitude and frequency (polynomial ``F``).

    Parameters
    ----------
    model
        A model or built-in name; ``F`` must be polynomial (exact rational algebra).
    order
        Highest power of ``mu`` in both series (needs ``A_1..A_{order+1}`` and
        ``B_1..B_order``).
    root
        The first-order amplitude ``a_0`` (a positive root of ``A_1``); default:
        the only positive root, an error if there are several.

    Returns
    -------
    LimitCycleSeries
        ``amplitude[n]``, ``omega[n]``: exact coefficients of ``mu**n``.

    Examples
    --------
    >>> s = limit_cycle_series("vdp", 4)
    >>> s.omega
    (1, 0, -1/16, 0, 17/3072)
    >>> s.amplitude[:3]
    (2, 0, 1/64)
    """
    from ._laurent import _Q
    from .averaging import _derive_raw, _PolyAlgebra

    if not isinstance(order, int) or isinstance(order, bool) or order < 0:
        raise OrderError(f"the series order must be an integer >= 0, got {order!r}")
    model, alg, (A_raw, B_raw, _) = _derive_raw(model, order + 1, last_u=False)
    if not isinstance(alg, _PolyAlgebra):
        raise OrderError("exact limit-cycle series need a polynomial F; use averaged_cycles "
                         "for the Bessel models")
    A = [None] + [c.as_expr() for c in A_raw]
    B = [model.omega0] + [c.as_expr() for c in B_raw]
    A1 = sp.expand(A[1])
    if A1 == 0:
        raise KBMError("A_1 = 0: the first-order amplitude equation has no isolated cycle")
    if A1.free_symbols - {a}:
        raise KBMError(f"A_1 = {A1} has parameters {sorted(map(str, A1.free_symbols - {a}))}; "
                       "give them values (--param) for an exact series")
    if root is None:
        cands = sorted((r for r in sp.roots(sp.Poly(A1, a)).keys() if r.is_positive),
                       key=float)
        if len(cands) != 1:
            raise KBMError(f"A_1 = {A1} has {len(cands)} positive roots {cands}; "
                           "choose one with root=")
        a0 = cands[0]
    else:
        a0 = sp.nsimplify(root)
        if sp.simplify(A1.subs(a, a0)) != 0:
            raise KBMError(f"a0 = {a0} is not a root of A_1 = {A1}")
    N = order
    exact_q = a0.is_Rational and all(sp.Poly(sp.expand(e), a).domain.is_QQ
                                     or sp.Poly(sp.expand(e), a).domain.is_ZZ
                                     for e in A[1:] + B)

    def num(v):
        v = sp.expand(v)
        return _Q(int(v.p), int(v.q)) if exact_q else v

    def taylor(expr):
        p = sp.Poly(sp.expand(expr), a)
        out, k_fact = [], 1
        for k in range(N + 1):
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
        raise KBMError(f"A_1'(a0) = 0 at a0 = {a0}: the cycle is not hyperbolic and has no "
                       "regular series in mu")

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
        if exact_q:
            return sp.Rational(int(v.numerator), int(v.denominator))
        return sp.radsimp(sp.expand(v))

    return LimitCycleSeries(order=N, amplitude=(a0, *[out(v) for v in c[1:]]),
                            omega=tuple(out(v) for v in omega))
