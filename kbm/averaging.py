"""The Krylov-Bogoliubov-Mitropolsky recursion, to any order.

For ``x'' + omega0**2 x = mu F(x, x')`` the expansion (Bogoliubov & Mitropolsky
1961, ch. 1, sec. 2) is

``x = a cos(psi) + sum_{n>=1} mu**n u_n(a, psi)``,
``da/dt = sum_{n>=1} mu**n A_n(a)``, ``dpsi/dt = omega0 + sum_{n>=1} mu**n B_n(a)``,

with the convention that **no** ``u_n`` contains a first harmonic, so that
``a`` is exactly the amplitude of the first harmonic of ``x``.

With ``D_j = A_j d/da + B_j d/dpsi`` the eps-coefficients of the velocity and
acceleration are ``V_m = omega0 du_m/dpsi + sum_{j=1}^m D_j u_{m-j}`` and
``[x'']_m = omega0 dV_m/dpsi + sum_{j=1}^m D_j V_{m-j}``.  At order ``n`` the
unknowns enter as ``omega0**2 (u_n'' + u_n) - 2 omega0 A_n sin(psi)
- 2 omega0 a B_n cos(psi)``; with ``R_n`` the coefficient of ``mu**(n-1)`` of
``F(x, x')`` minus every known term of ``[x'']_n``, removing the first
harmonic (secular terms) gives ``A_n = -R_n^{sin 1}/(2 omega0)``,
``B_n = -R_n^{cos 1}/(2 omega0 a)``, and ``u_n`` follows harmonic by harmonic.

Polynomial ``F`` is treated with exact rational arithmetic on Fourier series
with Laurent-polynomial coefficients (:mod:`kbm._fourier`), any order;
``F`` with ``sin(k x)``, ``cos(k x)`` with the Jacobi-Anger algebra of
:mod:`kbm._bessel`, order <= 2 (the Bessel sums stay symbolic).
"""

from __future__ import annotations


import sympy as sp

from . import _bessel
from ._fourier import PolyFourier
from ._laurent import LaurentRing, _Q
from ._series import Const, Leaf, Node, Product, Scaled, Sum, TrigOf
from .errors import OrderError, UnsupportedTermError
from .models import Oscillator, get_model
from .result import KBMResult
from .symbols import a, psi, x, xdot

__all__ = ["derive", "MAX_ORDER_TRIG"]

#: highest order available for F with sin(k x) or cos(k x)
MAX_ORDER_TRIG = 2


# ----------------------------------------------------------------------------- algebras
class _PolyAlgebra:
    """Exact arithmetic for polynomial F: Laurent coefficients in (a, parameters)."""

    def __init__(self, model: Oscillator):
        params = sorted((model.F.free_symbols | model.omega0.free_symbols) - {x, xdot},
                        key=lambda s: s.name)
        self.ring = LaurentRing([a, *params])
        w0 = model.omega0
        if w0.is_Symbol:
            i = self.ring.gens.index(w0)
            self.w0 = self.ring.gen(i)
            self.w0inv = self.ring.gen(i, -1)
        else:
            self.w0 = self.ring.const(_Q(int(w0.p), int(w0.q)))
            self.w0inv = self.ring.const(_Q(int(w0.q), int(w0.p)))
        self.a_inv = self.ring.gen(0, -1)

    def zero(self) -> PolyFourier:
        return PolyFourier(self.ring)

    def const(self, expr: sp.Expr) -> PolyFourier:
        return PolyFourier.constant(self.ring, self.ring.from_expr(expr))

    def coef(self, expr: sp.Expr):
        return self.ring.from_expr(expr)

    def x0(self) -> PolyFourier:
        return PolyFourier(self.ring, {1: self.ring.gen(0)})

    def scale(self, f: PolyFourier, c) -> PolyFourier:
        return f.scale(c)

    def dpsi(self, f):
        return f.dpsi()

    def da(self, f):
        return f.da()

    def secular(self, R: PolyFourier):
        c1, s1 = R.harmonic(1)
        half = _Q(-1, 2)
        A = (s1 * self.w0inv).scale(half)
        B = (c1 * self.w0inv * self.a_inv).scale(half)
        return A, B

    def solve(self, R: PolyFourier) -> PolyFourier:
        return R.solve_without_first(self.w0inv * self.w0inv)

    def coef_expr(self, c) -> sp.Expr:
        return c.as_primitive_expr() if c else sp.Integer(0)

    def series_expr(self, f: PolyFourier) -> sp.Expr:
        return f.as_expr(psi)

    def trig(self, *args):  # pragma: no cover - guarded by _is_polynomial
        raise UnsupportedTermError("sin/cos in the polynomial algebra")


class _SymAlgebra:
    """sympy coefficients and infinite Jacobi-Anger families of harmonics."""

    def __init__(self, model: Oscillator):
        self.w0 = model.omega0

    def zero(self):
        return _bessel.SymFourier()

    def const(self, expr):
        return _bessel.SymFourier.constant(expr)

    def coef(self, expr):
        return sp.sympify(expr)

    def x0(self):
        return _bessel.SymFourier.harmonic_term(_bessel.COS, 1, a)

    def scale(self, f, c):
        return f.scale(c)

    def dpsi(self, f):
        return f.dpsi()

    def da(self, f):
        return f.da(a)

    def secular(self, R):
        c1, s1 = R.harmonic(1)
        return -s1 / (2 * self.w0), -c1 / (2 * self.w0 * a)

    def solve(self, R):
        return R.solve_without_first(self.w0)

    def coef_expr(self, c) -> sp.Expr:
        return _tidy_sums(c)

    def series_expr(self, f) -> sp.Expr:
        return f.as_expr(psi)

    def trig(self, kind: str, c: sp.Expr):
        """Fourier series of ``f^(m)(c a cos psi)``, m = 0..3, for f = sin or cos."""
        s, co = _bessel.jacobi_anger(c * a)
        seq = [s, co, -s, -co]  # sin, sin', sin'', sin'''
        return seq if kind == "sin" else seq[1:] + seq[:1]


def _tidy_sums(expr: sp.Expr) -> sp.Expr:
    """Rename summation indices to n, merge sums with equal limits, tidy the rest."""
    expr = sp.expand(expr)
    sums: dict[tuple, list[sp.Expr]] = {}
    rest = []
    for term in sp.Add.make_args(expr):
        coeff, sm = sp.Integer(1), None
        for f in sp.Mul.make_args(term):
            if isinstance(f, sp.Sum) and sm is None:
                sm = f
            else:
                coeff *= f
        if sm is None:
            rest.append(term)
            continue
        limits = sm.limits
        ren = {lim[0]: _bessel.DISPLAY_INDEX[i] for i, lim in enumerate(limits)}
        body = sm.function.xreplace(ren) * coeff
        key = tuple((ren[l[0]], l[1], l[2]) for l in limits)
        sums.setdefault(key, []).append(body)
    out = [_bessel.tidy(sp.Add(*rest))]
    for key in sorted(sums, key=sp.default_sort_key):
        out.append(sp.Sum(_bessel.tidy(sp.Add(*sums[key])), *key))
    return sp.Add(*out)


# ----------------------------------------------------------------------------- F along the series
def _is_polynomial(model: Oscillator) -> bool:
    """Whether the exact algebra applies: F polynomial in x, xdot with coefficients that are
    Laurent polynomials in the parameters over Q, and omega0 rational or a symbol."""
    F = sp.expand(model.F)
    try:
        poly = sp.Poly(F, x, xdot)
    except sp.PolynomialError:
        return False
    w0 = model.omega0
    if not (w0.is_Symbol or w0.is_Rational):
        return False
    params = sorted((F.free_symbols | w0.free_symbols) - {x, xdot}, key=lambda s: s.name)
    ring = LaurentRing([a, *params])
    for c in poly.coeffs():
        try:
            ring.from_expr(c)
        except (TypeError, sp.PolynomialError, sp.GeneratorsNeeded):
            return False
    return True


class _Builder:
    """Turns F into a tree of lazy series nodes over one algebra."""

    def __init__(self, alg, X: Leaf, V: Leaf):
        self.alg, self.X, self.V = alg, X, V
        self.zero = alg.zero
        self._pow: dict[tuple, Node] = {}
        self._delta: Node | None = None

    def power(self, key, base: Node, e: int, low: int = 0) -> Node:
        if e == 1:
            return base
        k = (key, e)
        if k not in self._pow:
            half = self.power(key, base, e // 2, low)
            node = Product(self.zero, half, half, low * (e // 2), low * (e // 2))
            if e % 2:
                node = Product(self.zero, node, base, low * (e - 1), low)
            self._pow[k] = node
        return self._pow[k]

    def delta(self) -> Node:
        if self._delta is None:
            X = self.X

            class _Delta(Node):
                def _make(inner, n):
                    return self.zero() if n == 0 else X.coeff(n)

            self._delta = _Delta(self.zero)
        return self._delta

    def build(self, expr: sp.Expr) -> Node:
        if expr == x:
            return self.X
        if expr == xdot:
            return self.V
        if not expr.has(x, xdot):
            return Const(self.zero, self.alg.const(expr))
        if expr.is_Add:
            return Sum(self.zero, [self.build(t) for t in expr.args])
        if expr.is_Mul:
            const = [f for f in expr.args if not f.has(x, xdot)]
            var = [f for f in expr.args if f.has(x, xdot)]
            node = self.build(var[0])
            for f in var[1:]:
                node = Product(self.zero, node, self.build(f))
            if const:
                c = self.alg.coef(sp.Mul(*const))
                node = Scaled(self.zero, node, lambda s, c=c: self.alg.scale(s, c))
            return node
        if expr.is_Pow and expr.exp.is_Integer and expr.exp > 0:
            return self.power(expr.base, self.build(expr.base), int(expr.exp))
        if isinstance(expr, (sp.sin, sp.cos)):
            return self.trig(expr)
        raise UnsupportedTermError(_unsupported_message(expr))

    def trig(self, expr: sp.Expr) -> Node:
        arg = sp.expand(expr.args[0])
        c = arg.coeff(x)
        rest = sp.expand(arg - c * x)
        if c == 0 or c.has(x, xdot) or rest.has(x, xdot):
            raise UnsupportedTermError(
                f"the term {expr} is not supported: sin and cos must have an argument "
                "linear in x (k*x + phase), without xdot")
        if rest != 0:  # sin(c x + d) = sin(c x) cos d + cos(c x) sin d, etc.
            f = type(expr)
            if f is sp.sin:
                new = sp.sin(c * x) * sp.cos(rest) + sp.cos(c * x) * sp.sin(rest)
            else:
                new = sp.cos(c * x) * sp.cos(rest) - sp.sin(c * x) * sp.sin(rest)
            return self.build(sp.expand(new))
        kind = "sin" if isinstance(expr, sp.sin) else "cos"
        derivs = self.alg.trig(kind, c)
        delta = self.delta()

        def powers(m: int, delta=delta) -> Node:
            return self.power("__delta__", delta, m, low=1)

        def weight(m: int, c=c):
            return c**m / sp.factorial(m)

        return TrigOf(self.zero, derivs, powers, weight)


def _unsupported_message(term: sp.Expr) -> str:
    return (f"the term {term} of F is not supported: F must be a polynomial in x and xdot, "
            "possibly times sin(k*x) or cos(k*x); rewrite or approximate that term")


def _check_terms(F: sp.Expr) -> None:
    """Name the first unsupported term before any algebra is done."""
    def walk(e):
        if not e.has(x, xdot):
            return
        if e in (x, xdot):
            return
        if e.is_Add or e.is_Mul:
            for arg in e.args:
                walk(arg)
            return
        if e.is_Pow:
            if e.exp.is_Integer and e.exp > 0:
                walk(e.base)
                return
            raise UnsupportedTermError(_unsupported_message(e))
        if isinstance(e, (sp.sin, sp.cos)):
            arg = sp.expand(e.args[0])
            if arg.has(xdot) or not arg.is_polynomial(x) or sp.Poly(arg, x).degree() != 1:
                raise UnsupportedTermError(
                    f"the term {e} of F is not supported: sin and cos must have an argument "
                    "linear in x (k*x + phase), without xdot")
            return
        raise UnsupportedTermError(_unsupported_message(e))
    walk(F)


# ----------------------------------------------------------------------------- the recursion
def derive(model: Oscillator | str, order: int, params: dict | None = None) -> KBMResult:
    """KBM expansion of ``x'' + omega0**2 x = mu F(x, x')`` to order ``order``.

    Parameters
    ----------
    model
        An :class:`~kbm.models.Oscillator` or the name of a built-in model.
    order
        Highest power ``N`` of ``mu`` kept in ``da/dt``, ``dpsi/dt`` and ``x``
        (``A_1..A_N``, ``B_1..B_N``, ``u_1..u_N``).  Any ``N >= 1`` for
        polynomial ``F``; ``N <= 2`` when ``F`` contains ``sin(k x)`` or ``cos(k x)``.
    params
        Parameter values substituted before the derivation (exact: ``"0.1"``
        is read as ``1/10``).

    Returns
    -------
    KBMResult
        ``A``, ``B``, ``u``: tuples indexed by order, with ``A[0] = 0``,
        ``B[0] = omega0``, ``u[0] = a cos(psi)``.

    Raises
    ------
    kbm.errors.OrderError
        If ``order < 1`` (or > 2 for trigonometric ``F``).
    kbm.errors.UnsupportedTermError
        If ``F`` has a term that is not a polynomial in ``x``, ``xdot`` times
        ``sin``/``cos`` of a linear function of ``x`` (the term is named).
    kbm.errors.NonAutonomousError
        If the model depends on ``t`` (e.g. a slider with stage velocity ``v != 0``).

    References
    ----------
    N. N. Bogoliubov and Y. A. Mitropolsky, *Asymptotic Methods in the Theory of
    Non-Linear Oscillations*, Gordon and Breach (1961), ch. 1.

    Examples
    --------
    >>> res = derive("vdp", 2)
    >>> res.A[1]
    -a*(a**2 - 4)/8
    >>> res.B[2]
    -7*a**4/256 + a**2/8 - 1/8
    """
    model, alg, (A, B, U) = _derive_raw(model, order, params)
    return KBMResult(
        model=model, order=order,
        A=(sp.Integer(0), *[alg.coef_expr(c) for c in A]),
        B=(model.omega0, *[alg.coef_expr(c) for c in B]),
        u=(a * sp.cos(psi), *[alg.series_expr(f) for f in U]),
        exact=isinstance(alg, _PolyAlgebra),
    )


def _derive_raw(model, order, params=None, *, last_u: bool = True):
    """Validate the input and run the recursion; results stay in the algebra's types."""
    if isinstance(model, str):
        model = get_model(model)
    if params:
        model = model.substitute(params)
    if not isinstance(order, int) or isinstance(order, bool) or order < 1:
        raise OrderError(f"the order must be an integer >= 1, got {order!r}")
    model.require_autonomous("the KBM averaging")
    F = sp.expand(model.F)
    _check_terms(F)
    polynomial = _is_polynomial(model)
    if not polynomial and order > MAX_ORDER_TRIG:
        raise OrderError(
            f"order {order} is not available for {model.name!r}: with sin(k x) or cos(k x) in F "
            f"(or coefficients that are not rational, such as pi) the symbolic algebra goes to "
            f"order {MAX_ORDER_TRIG}; polynomial F with rational coefficients: any order")
    alg = _PolyAlgebra(model) if polynomial else _SymAlgebra(model)
    return model, alg, _recursion(alg, F, order, last_u)


def _recursion(alg, F: sp.Expr, order: int, last_u: bool = True):
    zero = alg.zero
    x0 = alg.x0()
    v0 = alg.scale(alg.dpsi(x0), alg.w0)
    X = Leaf(zero, x0)
    V = Leaf(zero, v0)
    Fnode = _Builder(alg, X, V).build(F)
    A: list = []
    B: list = []
    U: list = []

    def D(j: int, f):  # D_j f = A_j df/da + B_j df/dpsi   (j >= 1)
        out = zero()
        if A[j - 1]:
            out = out + alg.scale(alg.da(f), A[j - 1])
        if B[j - 1]:
            out = out + alg.scale(alg.dpsi(f), B[j - 1])
        return out

    Xs, Vs = [x0], [v0]
    for n in range(1, order + 1):
        Fn = Fnode.coeff(n - 1)
        v_known = zero()
        for j in range(1, n):
            v_known = v_known + D(j, Xs[n - j])
        acc_known = alg.scale(alg.dpsi(v_known), alg.w0)
        for j in range(1, n):
            acc_known = acc_known + D(j, Vs[n - j])
        R = Fn - acc_known
        An, Bn = alg.secular(R)
        A.append(An)
        B.append(Bn)
        if n == order and not last_u:
            break
        un = alg.solve(R)
        U.append(un)
        if n == order:
            break
        vn = alg.scale(alg.dpsi(un), alg.w0) + D(n, x0) + v_known
        Xs.append(un)
        Vs.append(vn)
        X.append(un)
        V.append(vn)
    return A, B, U
