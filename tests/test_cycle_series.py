"""The limit-cycle series on the cycle itself (kbm.slowflow.cycle_series,
kbm.slowflow.numeric_series, kbm.slowflow.resum) against independent references: the KBM averaged
route (kbm.slowflow.series, method='kbm'), a plain Fraction Lindstedt expansion
(tests/reference/lindstedt_fraction.py), Andersen & Geer's published coefficients and radius, and
the true cycles of numerics."""

from __future__ import annotations

from fractions import Fraction

import mpmath
import pytest
import sympy as sp
from hypothesis import given, settings, strategies as st

from kbm import OrderError, ParameterError, custom_model, limit_cycle_series
from kbm.algebra import zfourier
from kbm.algebra.zfourier import ZSeries, arithmetic
from kbm.slowflow.cycle_series import lindstedt_series, polynomial_terms
from kbm.errors import AveragedCycleError
from kbm.slowflow.numeric_series import numeric_cycle_series
from kbm.slowflow.resum import nearest_singularity, pade_resum
from kbm.symbols import x, xdot

from reference.andersen_geer import OMEGA_VDP, RADIUS_MU2
from reference.lindstedt_fraction import vdp_lindstedt_fraction


def _q(c) -> sp.Rational:
    return sp.Rational(c.numerator, c.denominator)


# ----------------------------------------------------------------------------- exact route
def test_vdp_frequency_matches_andersen_geer_published_coefficients():
    """Andersen & Geer (1982): omega* = 1 - e^2/16 + 17e^4/3072 + 35e^6/884736
    - 678899 e^8/5096079360 + ... (tests/reference/andersen_geer.py cites where each came from)."""
    s = limit_cycle_series("vdp", max(OMEGA_VDP))
    for n, c in OMEGA_VDP.items():
        assert s.omega[n] == c, n
    assert all(s.omega[n] == 0 for n in range(1, len(s.omega), 2))


def test_vdp_through_eps24_three_independent_routes():
    """Andersen & Geer computed the series exactly to eps^24: the Lindstedt engine, the KBM
    averaged route and a plain Fraction Lindstedt expansion agree on every coefficient of
    omega* and a* through mu^24."""
    fast = limit_cycle_series("vdp", 24)
    kbm = limit_cycle_series("vdp", 24, method="kbm")
    w, a = vdp_lindstedt_fraction(24)
    assert fast == kbm
    assert list(fast.omega) == [_q(c) for c in w]
    assert list(fast.amplitude) == [_q(c) for c in a]


@pytest.mark.parametrize("rhs, order", [
    ("(1 - x**2)*xdot", 16),                    # van der Pol
    ("xdot - xdot**3/3", 12),                   # Rayleigh
    ("(1 - x**2)*xdot - x**3", 12),             # van der Pol-Duffing
    ("(1 - x**2)*xdot + x**2/2 - x*xdot**2/5", 10),  # asymmetric: even harmonics, odd powers
])
def test_lindstedt_equals_kbm_route(rhs, order):
    """a* (KBM's a is the first-harmonic amplitude: no u_n has a first harmonic) and omega*
    from the recursion on the cycle equal the root of the averaged equations, exactly."""
    model = custom_model(rhs)
    assert limit_cycle_series(model, order) == limit_cycle_series(model, order, method="kbm")


even_v_terms = st.lists(st.tuples(st.integers(0, 3), st.integers(0, 1),
                                  st.fractions(-2, 2, max_denominator=7)),
                        min_size=1, max_size=3)


@settings(max_examples=10)
@given(even_v_terms)
def test_random_polynomial_F_agrees_with_kbm_route(terms):
    """Property: F = (1 - x^2) x' + sum c x^i x'^(2j) (terms even in x' leave A_1 and so
    a0 = 2 unchanged) gives the same exact series by both routes (order 4)."""
    F = (1 - x**2) * xdot + sum(_q(c) * x**i * xdot**(2 * j) for i, j, c in terms)
    model = custom_model(F)
    assert limit_cycle_series(model, 4) == limit_cycle_series(model, 4, method="kbm")


def test_pure_python_fallback_gives_the_flint_numbers(monkeypatch):
    """Without python-flint the same recursion runs on ListPoly over gmpy2.mpq: identical
    coefficients (van der Pol and an asymmetric F, order 20 and 8)."""
    flint_s = limit_cycle_series("vdp", 20)
    asym = custom_model("(1 - x**2)*xdot + x**2/2")
    flint_a = limit_cycle_series(asym, 8)
    monkeypatch.setattr(zfourier, "HAVE_FLINT", False)
    assert arithmetic("exact").backend == "python"
    assert limit_cycle_series("vdp", 20) == flint_s
    assert limit_cycle_series(asym, 8) == flint_a


def test_zseries_product_and_derivative_against_trigonometry():
    """(cos t + 2 sin 2t)(3 - sin t) and d/dt, expanded by sympy's trigonometric algebra."""
    t = sp.Symbol("t")
    for ar in (arithmetic("exact"), arithmetic("exact", use_flint=False), arithmetic("float")):
        q = ar.num
        f = ZSeries.trig(ar, q(Fraction(1)), ar.zero, 1) + ZSeries.trig(ar, ar.zero,
                                                                          q(Fraction(2)), 2)
        g = ZSeries.constant(ar, q(Fraction(3))) - ZSeries.trig(ar, ar.zero, q(Fraction(1)), 1)

        def expr(s):
            return sum(sp.nsimplify(float(C) if ar.name == "float" else _q_any(C)) * sp.cos(k * t)
                       + sp.nsimplify(float(S) if ar.name == "float" else _q_any(S))
                       * sp.sin(k * t) for k, (C, S) in s.trig_coefficients().items())

        fe = sp.cos(t) + 2 * sp.sin(2 * t)
        ge = 3 - sp.sin(t)
        assert sp.simplify(expr(f * g) - fe * ge) == 0
        assert sp.simplify(expr(f.square()) - fe**2) == 0
        assert sp.simplify(expr(f.dtau()) - sp.diff(fe, t)) == 0


def _q_any(c):
    p = getattr(c, "numerator", None)
    return sp.Rational(int(c.p), int(c.q)) if p is None else sp.Rational(int(p), int(c.denominator))


# ----------------------------------------------------------------------------- errors
@pytest.mark.parametrize("call, error, needle", [
    (lambda: limit_cycle_series("vdp", -1), OrderError, ">= 0"),
    (lambda: limit_cycle_series("vdp", 201), OrderError, "limit 200"),
    (lambda: limit_cycle_series("vdp", 30, method="kbm"), OrderError, "limit 29"),
    (lambda: limit_cycle_series("vdp", 2, method="fast"), ParameterError, "lindstedt"),
    (lambda: limit_cycle_series(custom_model("(1 - 3*x**2)*xdot"), 2, method="lindstedt"),
     OrderError, "method='kbm'"),
    (lambda: numeric_cycle_series("vdp", 0), OrderError, ">= 1"),
    (lambda: numeric_cycle_series("vdp", 1001), OrderError, "limit 1000"),
    (lambda: numeric_cycle_series("vdp", 10, digits=2), ParameterError, "from 5 to 1000"),
    (lambda: numeric_cycle_series("vdp", 201, digits=20), OrderError, "limit 200"),
    (lambda: numeric_cycle_series("sedf", 10), OrderError, "polynomial"),
    (lambda: numeric_cycle_series(custom_model("(16 - 32*x**2 + 8*x**4)*xdot"), 4),
     AveragedCycleError, "not hyperbolic"),
])
def test_bad_input_raises_kbm_errors_that_say_what_to_change(call, error, needle):
    with pytest.raises(error, match=None) as e:
        call()
    assert needle in str(e.value)


def test_irrational_first_order_amplitude():
    """F = (1 - 3x^2) x' is van der Pol with x scaled by 1/sqrt(3): a0 = 2/sqrt(3) takes the
    averaged route exactly, and in floating point omega* is van der Pol's, a* = vdp's/sqrt 3."""
    model = custom_model("(1 - 3*x**2)*xdot")
    s = limit_cycle_series(model, 4)
    v = limit_cycle_series("vdp", 4)
    assert s.omega == v.omega
    assert all(sp.simplify(p - q / sp.sqrt(3)) == 0 for p, q in zip(s.amplitude, v.amplitude))
    n = numeric_cycle_series(model, 12)
    nv = numeric_cycle_series("vdp", 12)
    for p, q in zip(n.amplitude, nv.amplitude):
        assert abs(p - q / 3**0.5) <= 1e-14
    assert n.omega == pytest.approx(nv.omega, abs=1e-15)


# ----------------------------------------------------------------------------- floating point
@pytest.mark.parametrize("order", [40, pytest.param(100, marks=pytest.mark.slow)])
def test_float_and_mpmath_coefficients_against_exact(order):
    """Double precision to mu^order keeps ~1e-10 accuracy relative to the coefficients' size
    (the largest of the neighbouring even coefficients: single ones dip by cancellation);
    30 digits to mu^30 ~1e-25.  Order 100 (the exact series alone takes 15 s) is slow."""
    ex = limit_cycle_series("vdp", order)
    fl = numeric_cycle_series("vdp", order)
    for name in ("omega", "amplitude"):
        exact = [float(c) for c in getattr(ex, name)]
        for n in range(0, order + 1, 2):
            size = max(abs(v) for v in exact[max(0, n - 4):n + 5:2])
            assert abs(getattr(fl, name)[n] - exact[n]) <= 1e-10 * size, (name, n)
    mp = numeric_cycle_series("vdp", 30, digits=30)
    with mpmath.workdps(40):
        for n in range(0, 31, 2):
            e = mpmath.mpf(ex.omega[n].p) / ex.omega[n].q
            assert abs(mp.omega[n] - e) <= mpmath.mpf(10)**-25 * abs(e), n
    assert fl.even and mp.even and fl.variable == "mu**2"


def test_asymmetric_series_is_not_even():
    model = custom_model("(1 - x**2)*xdot + x**2/2 - x*xdot**2/5")
    s = numeric_cycle_series(model, 8)
    ex = limit_cycle_series(model, 8)
    assert not s.even
    assert s.amplitude == pytest.approx([float(c) for c in ex.amplitude], rel=1e-12, abs=1e-15)


def test_coefficients_in_the_series_variable():
    """The public coefficients: van der Pol's omega* in mu**2 (Andersen & Geer's even
    coefficients, lowest first); the asymmetric model's amplitude in every power of mu (the
    exact Lindstedt route)."""
    s = numeric_cycle_series("vdp", 8)
    assert s.coefficients() == pytest.approx(
        [float(OMEGA_VDP[n]) for n in range(0, 9, 2)], rel=1e-12)
    model = custom_model("(1 - x**2)*xdot + x**2/2 - x*xdot**2/5")
    assert numeric_cycle_series(model, 6).coefficients("amplitude") == pytest.approx(
        [float(c) for c in limit_cycle_series(model, 6).amplitude], rel=1e-12, abs=1e-15)
    with pytest.raises(ParameterError, match="'omega' or 'amplitude'"):
        s.coefficients("phase")


@pytest.fixture(scope="module")
def vdp_160():
    """The double-precision vdp series to mu^160 (3-4 s), computed once for the radius and
    the Pade tests (a frozen result: the tests only read it)."""
    return numeric_cycle_series("vdp", 160)


def test_radius_of_convergence_matches_andersen_geer(vdp_160):
    """Andersen & Geer (1982): the nearest singularities of omega*(mu^2) are branch points at
    |mu^2| ~= 3.42.  Ratio estimates from mu^160 extrapolated: 3.42 +- 0.01; the nearest
    Pade pole lies on the branch cut just beyond (3.42 .. 3.6), at the same angle."""
    s = vdp_160
    sg = s.singularity()
    assert abs(sg.radius - RADIUS_MU2) < 0.01
    assert 3.42 <= sg.pole_radius < 3.6
    assert abs(sg.pole_angle - sg.angle) < 0.03
    assert sg.variable == "mu**2"


def test_resum_and_radius_on_a_known_function():
    """f(t) = 1/sqrt(1 + t + t^2/4 + ...) with branch points at t = 2 e^{+-2i}: the
    estimate finds R = 2, theta = 2; Pade sums it at t = 10 (outside) to 1e-10."""
    R, th = mpmath.mpf(2), mpmath.mpf(2)
    t0 = R * mpmath.expj(th)

    def f(t):
        return 1 / mpmath.sqrt((1 - t / t0) * (1 - t / mpmath.conj(t0)))

    with mpmath.workdps(40):
        c = [mpmath.re(v) for v in mpmath.taylor(f, 0, 120)]
        sg = nearest_singularity(c)
        assert abs(sg.radius - 2) < 1e-3 and abs(sg.angle - 2) < 1e-3
        r = pade_resum(c, 10)
        assert abs(r.value - mpmath.re(f(10))) < 1e-10


# ----------------------------------------------------------------------------- true cycles
def _true_omega(mu, digits):
    from numerics import limit_cycle

    c = limit_cycle("vdp", {"mu": mu}, digits=digits)
    return 2 * mpmath.pi / c.mp["period"], c.mp["amplitude_first_harmonic"]


@pytest.mark.parametrize("mu, tol", [(1, 1e-13), (2, 1e-11)])
def test_pade_resummed_series_against_true_cycle(mu, tol, vdp_160):
    """Pade in mu^2 of the mu^160 series against 20-digit true cycles (numerics' Taylor
    shooting): omega* and a* to the stated relative tolerance; the partial sum is already
    off at mu = 2 (mu^2 = 4 > 3.42)."""
    s = vdp_160
    w_true, a_true = _true_omega(mu, 20)
    w = s.pade(mu).value
    a = s.pade(mu, "amplitude").value
    assert abs(w - w_true) <= tol * w_true
    assert abs(a - a_true) <= tol * a_true
    if mu == 2:
        assert abs(s.partial_sum(mu) - w_true) > 1  # the partial sum is useless there


@pytest.mark.slow
@pytest.mark.parametrize("mu, tol", [(1, 1e-14), (2, 1e-12), (5, 1e-4)])
def test_pade_mu300_against_30_digit_true_cycles(mu, tol):
    """Order 300 in double precision, Pade in mu^2, against the 30-digit cycles for mu = 1,
    2, 5 (beyond the radius |mu^2| = 3.42 from mu ~ 1.85 on, where the partial sums
    diverge)."""
    s = numeric_cycle_series("vdp", 300)
    w_true, a_true = _true_omega(mu, 30)
    assert abs(s.pade(mu).value - w_true) <= tol * w_true
    assert abs(s.pade(mu, "amplitude").value - a_true) <= tol * a_true


# ----------------------------------------------------------------------------- command line
@pytest.mark.slow  # 4-8 s; kept out of the default run (five-minute rule)
def test_cli_float_mode(capsys):
    """kbm series vdp --float --json: coefficients, the singularity and Pade values."""
    import json

    from numerics.cli import main

    assert main(["series", "vdp", "--order", "80", "--float", "--at", "1", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["variable"] == "mu**2" and len(data["omega"]) == 81
    assert float(data["omega"][2]) == -1 / 16
    assert abs(data["singularity"]["radius"] - RADIUS_MU2) < 0.05
    assert abs(float(data["pade"][0]["omega"]) - 0.942955847441610) < 1e-12


@pytest.mark.parametrize("argv, needle", [
    (["series", "vdp", "--order", "10", "--float", "--digits", "2"], "--digits must"),
    (["series", "vdp", "--order", "2000", "--float"], "limit 1000"),
    (["series", "vdp", "--order", "300"], "--float"),
    (["series", "vdp", "--order", "-1"], ">= 0"),
    (["series", "vdp", "--order", "4", "--digits", "20"], "--float"),
    (["series", "--rhs", "(1 - 3*x**2)*xdot", "--order", "2", "--method", "lindstedt"],
     "--method kbm"),
    (["series", "sedf", "--order", "10", "--float"], "polynomial"),
])
def test_cli_errors_are_one_line(capsys, argv, needle):
    from numerics.cli import main

    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and needle in err[0], err


def test_polynomial_terms_rejects_what_is_not_a_rational_polynomial():
    assert polynomial_terms(sp.sin(x)) is None
    assert polynomial_terms(sp.pi * x) is None
    assert polynomial_terms(x**2 * xdot / 3) == [(2, 1, Fraction(1, 3))]


def test_lindstedt_series_checks_the_root():
    ar = arithmetic("exact")
    with pytest.raises(AveragedCycleError, match="not a root"):
        lindstedt_series(polynomial_terms((1 - x**2) * xdot), Fraction(1), ar.num(Fraction(3)),
                         2, ar)
