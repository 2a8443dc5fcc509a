"""The KBM engine against independent references (issue 2).

- textbook closed forms (van der Pol, Duffing: Bogoliubov & Mitropolsky ch. 1;
  Nayfeh, *Perturbation Methods*, sec. 5.4);
- exact solutions (linear damping and stiffness) — every order;
- conservation: a conservative F never changes the amplitude, at any order;
- a purely numerical KBM recursion (tests/reference/numerical_kbm.py: FFT in psi,
  Chebyshev in a, Cauchy integral in eps; it only evaluates F);
- numpy, mpmath and sympy evaluation of the same expressions.
"""

from __future__ import annotations

import functools

import mpmath
import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings, strategies as st

from kbm import (ModelError, NonAutonomousError, OrderError, UnsupportedTermError, custom_model,
                 derive, get_model)

from reference.numerical_kbm import numerical_kbm

a, psi, eps = sp.symbols("a psi eps")
x, xdot = sp.symbols("x xdot")


def test_van_der_pol_textbook():
    """van der Pol: A_1 = (a/2)(1 - a^2/4), A_2 = 0, B_1 = 0, B_2 = -(1/8 - a^2/8 + 7a^4/256),
    u_1 = -(a^3/32) sin 3 psi."""
    r = derive("vdp", 2)
    assert sp.expand(r.A[1] - a / 2 * (1 - a**2 / 4)) == 0
    assert r.A[2] == 0 and r.B[1] == 0
    assert sp.expand(r.B[2] + sp.Rational(1, 8) - a**2 / 8 + sp.Rational(7, 256) * a**4) == 0
    assert sp.expand(r.u[1] + a**3 / 32 * sp.sin(3 * psi)) == 0


def test_duffing_textbook():
    """Duffing x'' + x + eps x^3 = 0: B_1 = 3a^2/8, B_2 = -15a^4/256, u_1 = (a^3/32) cos 3psi,
    A_n = 0."""
    r = derive("duffing", 3)
    assert sp.expand(r.B[1] - 3 * a**2 / 8) == 0
    assert sp.expand(r.B[2] + sp.Rational(15, 256) * a**4) == 0
    assert sp.expand(r.u[1] - a**3 / 32 * sp.cos(3 * psi)) == 0
    assert all(A == 0 for A in r.A)


def test_van_der_pol_limit_cycle_series():
    """omega* = 1 - eps^2/16 + 17 eps^4/3072 + 35 eps^6/884736 (Andersen & Geer 1982)."""
    from kbm import limit_cycle_series

    s = limit_cycle_series("vdp", 6)
    assert s.omega == (1, 0, sp.Rational(-1, 16), 0, sp.Rational(17, 3072), 0,
                       sp.Rational(35, 884736))


def test_limit_cycle_series_amplitude_against_numerical_root():
    """a* = sum amplitude[n] eps^n agrees with a root of sum eps^n A_n found numerically from
    the numerical reference's A_n (van der Pol, eps = 0.05, orders to 5)."""
    from scipy.optimize import brentq

    from kbm import limit_cycle_series

    e = 0.05
    s = limit_cycle_series("vdp", 4)
    series_root = float(sum(c * e**n for n, c in enumerate(s.amplitude)))

    def rate(av):
        ref = numerical_kbm(lambda X, V: (1 - X**2) * V, 1.0, 5, av)
        return sum(e**n * ref["A"][n] for n in range(1, 6))

    root = brentq(rate, 1.9, 2.1, xtol=1e-14)
    assert abs(root - series_root) < 5 * e**5


@settings(max_examples=15)
@given(st.fractions(min_value=-3, max_value=3, max_denominator=20).filter(lambda q: q != 0))
def test_linear_stiffness_exact_every_order(kappa):
    """x'' + (1 + eps kappa) x = 0: psi' = sqrt(1 + eps kappa) exactly, a' = 0, u_n = 0, so
    B_n are the Taylor coefficients of sqrt(1 + eps kappa)."""
    kap = sp.Rational(kappa.numerator, kappa.denominator)
    N = 6
    r = derive(get_model("linear_stiffness", {"kappa": kap}), N)
    exact = sp.series(sp.sqrt(1 + eps * kap), eps, 0, N + 1).removeO()
    for n in range(1, N + 1):
        assert sp.simplify(r.B[n] - exact.coeff(eps, n)) == 0
        assert r.A[n] == 0 and r.u[n] == 0


@settings(max_examples=15)
@given(st.fractions(min_value=-2, max_value=2, max_denominator=20).filter(lambda q: q != 0))
def test_linear_damping_exact_every_order(zeta):
    """x'' + 2 eps zeta x' + x = 0: x = a e^{-eps zeta t} cos(sqrt(1 - eps^2 zeta^2) t), so
    A = -eps zeta a exactly and B_n are the Taylor coefficients of sqrt(1 - eps^2 zeta^2)."""
    z = sp.Rational(zeta.numerator, zeta.denominator)
    N = 6
    r = derive(get_model("linear_damping", {"zeta": z}), N)
    exact = sp.series(sp.sqrt(1 - eps**2 * z**2), eps, 0, N + 1).removeO()
    assert sp.expand(r.A[1] + z * a) == 0
    for n in range(1, N + 1):
        if n > 1:
            assert r.A[n] == 0
        assert sp.simplify(r.B[n] - exact.coeff(eps, n)) == 0
        assert r.u[n] == 0


poly_terms = st.lists(st.tuples(st.integers(1, 5), st.fractions(-2, 2, max_denominator=9)),
                      min_size=1, max_size=3)


@settings(max_examples=12)
@given(poly_terms, st.sampled_from([0, 1, 2]))
def test_conservative_force_never_changes_the_amplitude(terms, trig):
    """F(x) conservative (polynomial in x, plus c sin(kx) or c cos(kx)): A_n = 0 at every
    order computed (no work over a cycle)."""
    F = sum(sp.Rational(c.numerator, c.denominator) * x**p for p, c in terms)
    if trig == 1:
        F += sp.Rational(3, 2) * sp.sin(2 * x)
    elif trig == 2:
        F += sp.Rational(1, 3) * sp.cos(3 * x)
    N = 2 if trig else 4
    r = derive(custom_model(F), N)
    f = r.functions("numpy")
    for n in range(1, N + 1):
        if r.exact:
            assert sp.simplify(r.A[n]) == 0
        else:
            vals = f.A[n](np.linspace(0.2, 2.5, 7))
            assert np.max(np.abs(vals)) < 1e-12


def _np_F(model, values):
    F = model.F.subs({sp.Symbol(k): v for k, v in values.items()})
    return sp.lambdify((x, xdot), F, modules="numpy")


@functools.lru_cache(maxsize=1)
def _polynomial_cases():
    """The models of the next test with their order and compiled functions, derived once for
    all its examples (the functions are kept on each result, not shared between results)."""
    cases = [(get_model("vdp"), 4), (get_model("rayleigh"), 3),
             (custom_model("(1 - x**2)*xdot - x**3 + x**2*xdot/2 - xdot**3/5"), 3)]
    return [(model, N, derive(model, N).functions("numpy")) for model, N in cases]


@settings(max_examples=6)
@given(st.floats(0.4, 2.6))
def test_polynomial_models_agree_with_numerical_kbm(av):
    """Every A_n, B_n, u_n of van der Pol (order 4), Rayleigh (3) and a mixed polynomial
    (3) agrees with the numerical recursion to ~1e-10 at random a."""
    for model, N, f in _polynomial_cases():
        ref = numerical_kbm(_np_F(model, {}), 1.0, N, av)
        for n in range(1, N + 1):
            assert abs(f.A[n](av) - ref["A"][n]) < 1e-10 * max(1, abs(ref["A"][n]))
            assert abs(f.B[n](av) - ref["B"][n]) < 1e-10 * max(1, abs(ref["B"][n]))
            assert np.max(np.abs(f.u[n](av, ref["psi"]) - ref["u"][n])) < 1e-10


@settings(max_examples=4)
@given(st.floats(0.3, 2.2), st.sampled_from(["sedf", "cdc"]))
def test_bessel_models_agree_with_numerical_kbm(av, name):
    """sedf and cdc (paper eqs. 3, 12; Jacobi-Anger Bessel sums) at order 2 agree with the
    numerical recursion (which only evaluates sin(k x)) to ~1e-10."""
    vals = {"beta": sp.Rational(7, 10), "delta": sp.Rational(3, 2), "k": sp.Rational(5, 2),
            "Omega": 1}
    vals = {k: v for k, v in vals.items() if sp.Symbol(k) in get_model(name).F.free_symbols
            or k == "Omega"}
    model = get_model(name, vals)
    r = derive(model, 2)
    f = r.functions("numpy")
    ref = numerical_kbm(_np_F(model, {}), 1.0, 2, av)
    for n in (1, 2):
        assert abs(f.A[n](av) - ref["A"][n]) < 1e-10
        assert abs(f.B[n](av) - ref["B"][n]) < 1e-10
        assert np.max(np.abs(f.u[n](av, ref["psi"]) - ref["u"][n])) < 1e-10


def test_sedf_first_order_phase_not_amplitude():
    """sedf first order: A_1 = (a/2)(1 - beta a^2/4), B_1 = delta J_1(k a)/(Omega a) — the
    paper's eq. (7) puts the J_1 term in the amplitude equation; it belongs in the phase."""
    r = derive("sedf", 1)
    beta, delta, k, Om = sp.symbols("beta delta k Omega")
    assert sp.expand(r.A[1] - a / 2 * (1 - beta * a**2 / 4)) == 0
    assert sp.simplify(r.B[1] - delta * sp.besselj(1, k * a) / (Om * a)) == 0


@pytest.mark.parametrize("name, order, skip_u2", [
    ("vdp", 3, False), ("sedf", 2, True),
    pytest.param("sedf", 2, False, marks=pytest.mark.slow)])
def test_numpy_mpmath_sympy_agree(name, order, skip_u2):
    """The numpy and 30-digit mpmath functions agree with sympy's own evaluation
    (Bessel sums: sympy evaluates the Sum by its own summation, not ours)."""
    vals = {"beta": 1, "delta": sp.Rational(1, 2), "k": 2, "Omega": 1}
    r = derive(name, order, params={k: v for k, v in vals.items()
                                    if sp.Symbol(k) in get_model(name).F.free_symbols
                                    or (k == "Omega" and name == "sedf")})
    fn, fm = r.functions("numpy"), r.functions("mpmath")
    av, pv = sp.Rational(13, 10), sp.Rational(7, 10)
    with mpmath.workdps(30):
        for n in range(1, order + 1):
            checks = [(r.A[n], fn.A[n], fm.A[n], (av,)), (r.B[n], fn.B[n], fm.B[n], (av,))]
            if not (skip_u2 and n == 2):  # the double sums of u_2 take sympy a minute
                checks.append((r.u[n], fn.u[n], fm.u[n], (av, pv)))
            for expr, num, mp_, args in checks:
                subs = dict(zip((a, psi), args))
                m_val = mp_(*[mpmath.mpf(str(v)) for v in args])
                n_val = float(num(*[float(v) for v in args]))
                assert abs(n_val - float(m_val)) < 1e-12 * max(1, abs(float(m_val)))
                ref = _sympy_value(expr.subs(subs))
                tol = mpmath.mpf(10) ** (-22 if not expr.has(sp.Sum) else -20)
                assert abs(m_val - mpmath.mpf(str(ref))) < tol * max(1, abs(m_val))


def _sympy_value(expr: sp.Expr) -> sp.Float:
    """sympy's own evaluation: each infinite Sum cut at 30 terms (the terms are products of
    J_m(1.3 k) with m > 60 there, below 1e-60) and summed exactly by sympy, then evalf."""
    def cut(s):
        body = s.function
        limits = [(v, lo, lo + 30) for v, lo, hi in s.limits]
        return sp.Sum(body, *limits).doit()
    while expr.has(sp.Sum):
        expr = expr.replace(lambda e: isinstance(e, sp.Sum) and not e.function.has(sp.Sum), cut)
    return sp.N(expr, 30)


@pytest.mark.parametrize("rhs, term", [("exp(x)", "exp(x)"), ("Abs(xdot)", "Abs(xdot)"),
                                       ("1/x", "1/x"), ("x*sin(xdot)", "sin(xdot)")])
def test_unsupported_terms_are_named(rhs, term):
    """Unsupported terms raise UnsupportedTermError naming the term."""
    with pytest.raises(UnsupportedTermError, match=term.replace("(", r"\(").replace(")", r"\)")):
        derive(custom_model(rhs), 1)


def test_order_and_autonomy_errors():
    """order < 1, order 3 with sin(k x), and a driven slider are refused with clear errors."""
    with pytest.raises(OrderError):
        derive("vdp", 0)
    with pytest.raises(OrderError):
        derive("sedf", 3)
    with pytest.raises(NonAutonomousError):
        derive(get_model("sedf", {"v": "0.1"}), 1)
    with pytest.raises(ModelError, match="omega0"):
        custom_model("x", omega0=-2)
