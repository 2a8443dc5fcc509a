"""The KBM recursion for a periodically forced oscillator, near a resonance, to any order.

For ``x'' + omega0**2 x = mu F(x, x', theta)``, ``theta = nu t``,
``nu = nu0 + mu sigma`` with ``nu0 = (p/q) omega0`` (:class:`~kbm.forced.model.Resonance`):

``x = a cos(psi) + sum_{n>=1} mu**n u_n(a, psi, theta)``,
``da/dt = sum mu**n A_n(a, psi, theta)``, ``dpsi/dt = omega0 + sum mu**n B_n(a, psi, theta)``,

where ``A_n``, ``B_n`` hold only the *slow* harmonics ``cos(j (p psi - q theta))``,
``sin(...)`` — functions of the resonant phase ``phi = psi - (q/p) theta``, since
``p psi - q theta = p phi`` — and no ``u_n`` holds a *resonant* harmonic
``(m, k) = (+-1 + j p, -j q)`` (those of frequency ``+-omega0`` at ``nu = nu0``), so that
``a`` is exactly the amplitude of the response's component at the frequency
``(q/p) nu``.  With ``L0 = omega0 d/dpsi + nu0 d/dtheta`` (which annihilates the slow
harmonics) and ``D_j = A_j d/da + B_j d/dpsi (+ sigma d/dtheta for j = 1)``:

``V_m = L0 u_m + sum_{j=1}^m D_j u_{m-j}``, ``[x'']_m = L0 V_m + sum_{j=1}^m D_j V_{m-j}``;

at order ``n`` the unknowns enter as ``(L0**2 + omega0**2) u_n - 2 omega0 A_n sin(psi)
- 2 omega0 a B_n cos(psi)``.  With ``R_n`` the coefficient of ``mu**(n-1)`` of ``F`` minus
the known part of ``[x'']_n``, its resonant part ``P(p phi) cos(psi) + Q(p phi) sin(psi)``
gives ``A_n = -Q/(2 omega0)``, ``B_n = -P/(2 omega0 a)`` and every other harmonic is divided
by ``omega0**2 - (m omega0 + k nu0)**2`` (never zero).  The slow flow is autonomous:
``da/dt = sum mu**n A_n(a, phi)``, ``dphi/dt = -mu (q/p) sigma + sum mu**n B_n(a, phi)``.

Without a declared resonance (``nu`` given, not near one) the same recursion keeps only
``(m, k) = (1, 0)`` secular; a harmonic whose divisor is small (within ``tolerance`` of a
resonance) is refused with the resonance named (:class:`SmallDivisorError`).

All arithmetic is exact: two-angle Fourier series (:mod:`kbm.forced.two_angle`) with
Laurent-polynomial coefficients over Q in ``a``, the parameters and ``sigma``.

References
----------
N. N. Bogoliubov and Y. A. Mitropolsky, *Asymptotic Methods in the Theory of Non-Linear
Oscillations* (1961), ch. 3 (resonance case).  A. H. Nayfeh and D. T. Mook, *Nonlinear
Oscillations* (1979), sec. 4.1.
"""

from __future__ import annotations

from fractions import Fraction

import sympy as sp
from sympy.simplify.fu import TR8

from ..algebra.laurent import Laurent, LaurentRing, Q
from ..algebra.lazy_series import Builder, Leaf
from ..errors import ModelError, OrderError, ParameterError
from ..symbols import a, psi, x, xdot
from .model import ForcedOscillator, Resonance, get_forced_model, phi, sigma, theta
from .result import ForcedKBMResult
from .two_angle import TwoAngle

__all__ = ["derive_forced", "SmallDivisorError", "MAX_ORDER"]

#: highest order of the forced expansion (cost grows quickly with the harmonics of theta)
MAX_ORDER = 12


class SmallDivisorError(ModelError):
    """A harmonic of the expansion is (nearly) resonant but the resonance was not declared."""


class _Algebra:
    """Two-angle series over Laurent coefficients, with the resonance structure."""

    def __init__(self, model: ForcedOscillator, res: Resonance | None, ratio: Fraction,
                 tolerance: float):
        gens = sorted((model.F.free_symbols | model.omega0.free_symbols) - {x, xdot, theta},
                      key=lambda s: s.name)
        self.res, self.r, self.tol = res, ratio, tolerance
        self.ring = LaurentRing([a, *gens, *([sigma] if res else [])])
        w0 = model.omega0
        if w0.is_Symbol:
            i = self.ring.gens.index(w0)
            self.w0, self.w0inv = self.ring.gen(i), self.ring.gen(i, -1)
        else:
            self.w0 = self.ring.const(Q(int(w0.p), int(w0.q)))
            self.w0inv = self.ring.const(Q(int(w0.q), int(w0.p)))
        self.nu0 = self.w0.scale(Q(ratio.numerator, ratio.denominator))
        self.a_inv = self.ring.gen(0, -1)
        self.sig = self.ring.gen(len(self.ring.gens) - 1) if res else None
        self.model = model

    # -- the ring protocol of the lazy series ------------------------------------------
    def zero(self) -> TwoAngle:
        return TwoAngle(self.ring)

    def coef(self, expr: sp.Expr) -> TwoAngle:
        return self.const(expr)

    def scale(self, f: TwoAngle, c) -> TwoAngle:
        return f.scale(c)

    def const(self, expr: sp.Expr) -> TwoAngle:
        """A sympy expression in theta (trigonometric polynomial) and the parameters."""
        e = sp.expand(TR8(expr)) if expr.has(sp.sin, sp.cos) else sp.expand(expr)
        out = self.zero()
        for term in sp.Add.make_args(e):
            trig = [f for f in sp.Mul.make_args(term) if f.has(theta)]
            coeff = sp.Mul(*[f for f in sp.Mul.make_args(term) if not f.has(theta)])
            if not trig:
                out = out + TwoAngle(self.ring, {(0, 0): self._laurent(coeff, expr)})
                continue
            (f,) = trig  # TR8 leaves one sin or cos of k theta + c per term
            arg = sp.expand(f.args[0])
            k = int(arg.coeff(theta))
            c = sp.expand(arg - k * theta)
            kinds = [("cos", sp.cos(c)), ("sin", -sp.sin(c))] if isinstance(f, sp.cos) \
                else [("sin", sp.cos(c)), ("cos", sp.sin(c))]
            for kind, w in kinds:
                if w != 0:
                    out = out + TwoAngle.harmonic(self.ring, 0, k,
                                                  self._laurent(coeff * w, expr), kind)
        return out

    def _laurent(self, c: sp.Expr, where: sp.Expr) -> Laurent:
        try:
            return self.ring.from_expr(c)
        except (TypeError, sp.PolynomialError, sp.GeneratorsNeeded):
            raise ModelError(f"the coefficient {c} (in {where}) is not a rational function "
                             "of the parameters with a monomial denominator; the exact forced "
                             "averaging needs rational numbers (no pi, no sqrt, no floats)") \
                from None

    # -- calculus ------------------------------------------------------------------
    def L0(self, f: TwoAngle) -> TwoAngle:
        return f.d_angle(0).scale(self.w0) + f.d_angle(1).scale(self.nu0)

    def resonant(self, m: int, k: int) -> tuple[int, int] | None:
        """``(j, s)`` with ``m psi + k theta = s psi + j (p psi - q theta)``, or ``None``."""
        if self.res is None:
            return (0, 1) if (m, k) == (1, 0) else None
        p, q = self.res.p, self.res.q
        if k % q:
            return None
        j = -k // q
        s = m - j * p
        return (j, s) if s in (1, -1) else None

    def secular(self, R: TwoAngle) -> tuple[TwoAngle, TwoAngle]:
        """``(A_n, B_n)``: the resonant part of ``R_n`` as slow series."""
        res, _ = R.split(lambda m, k: self.resonant(m, k) is not None)
        ring = self.ring
        p, q = (self.res.p, self.res.q) if self.res else (1, 0)
        P, Qs = self.zero(), self.zero()
        for kind, table in (("cos", res.cos), ("sin", res.sin)):
            for (m, k), c in table.items():
                j, s = self.resonant(m, k)
                jp, jq = j * p, -j * q
                if kind == "cos":  # cos(s psi + j Phi) = cos psi cos jPhi - s sin psi sin jPhi
                    P = P + TwoAngle.harmonic(ring, jp, jq, c, "cos")
                    Qs = Qs + TwoAngle.harmonic(ring, jp, jq, -c if s > 0 else c, "sin")
                else:  # sin(s psi + j Phi) = s sin psi cos jPhi + cos psi sin jPhi
                    P = P + TwoAngle.harmonic(ring, jp, jq, c, "sin")
                    Qs = Qs + TwoAngle.harmonic(ring, jp, jq, c if s > 0 else -c, "cos")
        half = Q(-1, 2)
        return Qs.scale(self.w0inv.scale(half)), P.scale((self.w0inv * self.a_inv).scale(half))

    def solve(self, R: TwoAngle, n: int) -> TwoAngle:
        """``u_n``: every non-resonant harmonic over ``omega0**2 - (m omega0 + k nu0)**2``."""
        _, rest = R.split(lambda m, k: self.resonant(m, k) is not None)
        w2inv = self.w0inv * self.w0inv

        def divide(mk, c):
            m, k = mk
            f = m + k * self.r
            d = 1 - f * f
            if self.res is None:
                self._check_divisor(m, k, f, n)
            return (c * w2inv).scale(Q(d.denominator, d.numerator))

        return rest.map_coefficients(divide)

    def _check_divisor(self, m: int, k: int, f: Fraction, n: int) -> None:
        gap = abs(abs(f) - 1)
        if gap > self.tol:
            return
        # m + k r = +-1: the forcing is near nu = (1 -+ m)/k omega0 (or exactly at it)
        near = Fraction(1 - m, k) if f > 0 else Fraction(-1 - m, k)
        near = abs(near)
        what = "exactly at" if gap == 0 else f"within {float(gap):.3g} omega0 of"
        arg = " + ".join(t for t in (_times(m, "psi"), _times(k, "theta")) if t)
        raise SmallDivisorError(
            f"the forcing frequency nu = {self.r} omega0 is {what} the resonance "
            f"nu = {near} omega0: the harmonic cos({arg}) of R_{n} has the small "
            f"divisor omega0^2 (1 - ({m} + {k} nu/omega0)^2) and the non-resonant expansion "
            f"breaks down; declare it: resonance='{near.numerator}/{near.denominator}' "
            f"(--resonance {near.numerator}/{near.denominator}) with the detuning "
            f"sigma = (nu - {near} omega0)/mu")


def _times(c: int, name: str) -> str:
    return "" if c == 0 else name if c == 1 else f"-{name}" if c == -1 else f"{c}*{name}"


def _recursion(alg: _Algebra, F: sp.Expr, order: int):
    zero = alg.zero
    x0 = TwoAngle(alg.ring, {(1, 0): alg.ring.gen(0)})
    v0 = alg.L0(x0)
    X, V = Leaf(zero, x0), Leaf(zero, v0)
    Fnode = Builder(alg, X, V).build(F)
    A: list[TwoAngle] = []
    B: list[TwoAngle] = []
    U: list[TwoAngle] = []

    def D(j: int, f: TwoAngle) -> TwoAngle:
        out = zero()
        if not A[j - 1].is_zero():
            out = out + A[j - 1] * f.da()
        if not B[j - 1].is_zero():
            out = out + B[j - 1] * f.d_angle(0)
        if j == 1 and alg.sig is not None:
            out = out + f.d_angle(1).scale(alg.sig)
        return out

    Xs, Vs = [x0], [v0]
    for n in range(1, order + 1):
        v_known = zero()
        for j in range(1, n):
            v_known = v_known + D(j, Xs[n - j])
        acc_known = alg.L0(v_known)
        for j in range(1, n):
            acc_known = acc_known + D(j, Vs[n - j])
        R = Fnode.coeff(n - 1) - acc_known
        An, Bn = alg.secular(R)
        A.append(An)
        B.append(Bn)
        un = alg.solve(R, n)
        U.append(un)
        if n == order:
            break
        vn = alg.L0(un) + D(n, x0) + v_known
        Xs.append(un)
        Vs.append(vn)
        X.append(un)
        V.append(vn)
    return A, B, U


def _slow_expr(f: TwoAngle, res: Resonance | None) -> sp.Expr:
    """A slow series (harmonics ``(j p, -j q)``) as a function of ``a`` and ``phi``."""
    p = res.p if res else 1
    parts = []
    for kind, table in (("cos", f.cos), ("sin", f.sin)):
        fn = sp.cos if kind == "cos" else sp.sin
        for (m, _k), c in sorted(table.items()):
            parts.append(c.as_primitive_expr() * (fn(m * phi) if m else 1))
    return sp.Add(*parts)


def derive_forced(model: ForcedOscillator | str, order: int, params: dict | None = None, *,
                  resonance: Resonance | str | None = None, nu: object = None,
                  tolerance: float = 0.05) -> ForcedKBMResult:
    """KBM expansion of ``x'' + omega0**2 x = mu F(x, x', nu t)`` near a resonance, order ``N``.

    Parameters
    ----------
    model
        A :class:`~kbm.forced.model.ForcedOscillator` or a built-in forced model's name.
    order
        Highest power of ``mu`` kept (``A_1..A_N``, ``B_1..B_N``, ``u_1..u_N``).
    params
        Exact parameter values substituted first (``"0.1"`` is ``1/10``).
    resonance
        The declared resonance ``p/q`` (``nu = (p/q) omega0 + mu sigma``); default the
        model's own.
    nu
        Instead of a resonance: a fixed forcing frequency (a number; ``omega0`` numeric),
        for the non-resonant expansion; refused with the resonance named when a harmonic
        comes within ``tolerance`` (relative to ``omega0``) of resonance.

    Returns
    -------
    ForcedKBMResult
        The slow flow ``da/dt = sum mu**n A_n(a, phi)``, ``dphi/dt = -mu (q/p) sigma +
        sum mu**n B_n(a, phi)`` and the corrections ``u_n(a, psi, theta)``.

    Raises
    ------
    kbm.errors.OrderError
        If ``order`` is not an integer in ``1..MAX_ORDER``.
    SmallDivisorError
        Non-resonant expansion near an undeclared resonance (the resonance named).

    Examples
    --------
    >>> r = derive_forced("duffing-forced", 1)
    >>> r.A[0]
    -a*zeta - h*sin(phi)/2
    >>> r.B[0]
    3*a**2*alpha/8 - h*cos(phi)/(2*a)
    """
    if isinstance(model, str):
        model = get_forced_model(model)
    if params:
        model = model.substitute(params)
    if not isinstance(order, int) or isinstance(order, bool) or not 1 <= order <= MAX_ORDER:
        raise OrderError(f"the order must be an integer from 1 to {MAX_ORDER}, got {order!r}")
    if nu is not None and resonance is not None:
        raise ParameterError("give either a resonance p/q (with the detuning sigma) or a fixed "
                             "forcing frequency nu, not both")
    if nu is not None:
        if not model.omega0.is_Rational:
            raise ParameterError(f"a fixed forcing frequency needs a numeric omega0, got "
                                 f"{model.omega0}; give its value")
        nu_val = sp.nsimplify(sp.sympify(str(nu)), rational=True)
        if not (nu_val.is_Rational and nu_val > 0):
            raise ParameterError(f"nu must be a positive number, got {nu!r}")
        ratio = Fraction(str(nu_val / model.omega0))
        res = None
    else:
        res = Resonance.parse(resonance) if resonance is not None else model.resonance
        ratio = res.ratio
    alg = _Algebra(model, res, ratio, tolerance)
    A, B, U = _recursion(alg, sp.expand(model.F), order)
    return ForcedKBMResult(
        model=model, order=order, resonance=res, nu_ratio=ratio,
        A=tuple(_slow_expr(f, res) for f in A),
        B=tuple(_slow_expr(f, res) for f in B),
        u=tuple(f.as_expr(psi, theta) for f in U))
