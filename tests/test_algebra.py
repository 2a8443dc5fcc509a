"""The private algebra wing kbm.algebra: the FourierAlgebra contract and its two algebras.

- the Protocol names exactly what the recursion asks (recorded through a proxy while
  derive() runs), and both adapters satisfy it;
- Laurent polynomials and PolyFourier series against sympy (exact, hypothesis);
- the Jacobi-Anger families against sympy's Bessel functions, and the lattice lines
  against brute force;
- the lazy series: Tail is x - x_0, powers by squaring equal repeated products.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, strategies as st

import kbm.algebra.laurent
import kbm.expansion.one_dof
from kbm import custom_model, derive
from kbm.algebra.base import FourierAlgebra, FourierSeries
from kbm.algebra.bessel_fourier import COS, SymAlgebra, SymFourier, jacobi_anger
from kbm.algebra.lattice import egcd, line, line_sum
from kbm.algebra.laurent import Laurent, LaurentRing, Q
from kbm.algebra.lazy_series import Builder, Leaf, Product, Tail
from kbm.algebra.poly_fourier import PolyAlgebra, PolyFourier
from kbm.model.builtins import get_model
from kbm.symbols import a, psi, x, xdot

beta = sp.Symbol("beta")


# ----------------------------------------------------------------------------- the contract
def _protocol_members() -> set[str]:
    names = set(FourierAlgebra.__annotations__)
    names |= {n for n, v in vars(FourierAlgebra).items()
              if callable(v) and not n.startswith("_")}
    return names


class _Recorder:
    """Wraps an algebra and records every attribute the engine reads from it."""

    seen: set[str] = set()

    def __init__(self, inner):
        object.__setattr__(self, "_inner", inner)

    def __getattr__(self, name):
        _Recorder.seen.add(name)
        return getattr(self._inner, name)


def test_protocol_names_exactly_what_derive_asks(monkeypatch):
    """Through a recording proxy, derive() of a polynomial and of a Bessel model reads
    exactly the Protocol's members from the algebra: nothing more, nothing left unused."""
    _Recorder.seen = set()
    monkeypatch.setattr(kbm.expansion.one_dof, "PolyAlgebra", lambda m: _Recorder(PolyAlgebra(m)))
    monkeypatch.setattr(kbm.expansion.one_dof, "SymAlgebra", lambda m: _Recorder(SymAlgebra(m)))
    derive(custom_model("g + (1 - x**2)*xdot"), 3)
    derive(custom_model("g - delta*sin(k*x) + (1 - x**2)*xdot"), 2)
    assert _Recorder.seen == _protocol_members()


@pytest.mark.parametrize("algebra, model", [(PolyAlgebra, "vdp"), (SymAlgebra, "sedf")])
def test_adapters_satisfy_the_protocol(algebra, model):
    alg = algebra(get_model(model))
    assert isinstance(alg, FourierAlgebra)
    assert isinstance(alg.x0(), FourierSeries)
    assert alg.exact is (algebra is PolyAlgebra)


@pytest.mark.parametrize("algebra", [PolyAlgebra, SymAlgebra])
def test_secular_and_solve_meet_their_docstrings(algebra):
    """With omega0 = 1 and R = 3 + 2 cos psi - 5 sin psi + 7 cos 3 psi: A = 5/2, B = -1/a,
    and u = 3 - (7/8) cos 3 psi."""
    alg = algebra(custom_model("-delta*sin(k*x) + (1 - x**2)*xdot"))
    R_expr = 3 + 2 * sp.cos(psi) - 5 * sp.sin(psi) + 7 * sp.cos(3 * psi)
    three = alg.const(sp.Integer(3))
    x0 = alg.x0()                                                 # a cos psi
    cos1 = alg.scale(x0, alg.coef(1 / a))
    sin1 = alg.scale(alg.dpsi(cos1), alg.coef(sp.Integer(-1)))
    cos3 = cos1 * cos1 * cos1                                     # cos^3 = (3 cos + cos 3)/4
    cos3 = alg.scale(cos3, alg.coef(sp.Integer(4))) - alg.scale(cos1, alg.coef(sp.Integer(3)))
    R = three + alg.scale(cos1, alg.coef(sp.Integer(2))) \
        - alg.scale(sin1, alg.coef(sp.Integer(5))) + alg.scale(cos3, alg.coef(sp.Integer(7)))
    assert sp.expand(alg.series_expr(R) - R_expr) == 0
    A, B = alg.secular(R)
    assert sp.simplify(alg.coef_expr(A) - sp.Rational(5, 2)) == 0
    assert sp.simplify(alg.coef_expr(B) + 1 / a) == 0
    u = alg.series_expr(alg.solve(R))
    assert sp.expand(u - 3 + sp.Rational(7, 8) * sp.cos(3 * psi)) == 0


# ----------------------------------------------------------------------------- exact algebra
small = st.integers(min_value=-3, max_value=3)
coeffs = st.lists(st.tuples(small, small, st.integers(-5, 5).filter(bool)), max_size=4)


def _laurent(ring, terms):
    expr = sp.Add(*[c * a**i * beta**j for i, j, c in terms])
    return ring.from_expr(expr), expr


@given(coeffs, coeffs)
def test_laurent_ring_against_sympy(t1, t2):
    ring = LaurentRing([a, beta])
    p, pe = _laurent(ring, t1)
    q, qe = _laurent(ring, t2)
    assert sp.expand((p * q).as_expr() - pe * qe) == 0
    assert sp.expand((p - q).as_expr() - (pe - qe)) == 0
    assert sp.expand(p.diff(0).as_expr() - sp.diff(pe, a)) == 0
    assert sp.expand(p.as_primitive_expr() - pe) == 0
    assert sp.expand(p.scale(Q(2, 3)).as_expr() - sp.Rational(2, 3) * pe) == 0


harmonics = st.dictionaries(st.integers(0, 4), st.integers(-4, 4), max_size=3)


@given(harmonics, harmonics, harmonics, harmonics)
def test_poly_fourier_product_and_calculus_against_sympy(c1, s1, c2, s2):
    ring = LaurentRing([a])

    def series(c, s):
        f = PolyFourier(ring, {m: ring.const(v) * ring.gen(0, m) for m, v in c.items()},
                        {m: ring.const(v) * ring.gen(0, m) for m, v in s.items()})
        e = sp.Add(*[v * a**m * sp.cos(m * psi) for m, v in c.items()],
                   *[v * a**m * sp.sin(m * psi) for m, v in s.items()])
        return f, e

    f, fe = series(c1, s1)
    g, ge = series(c2, s2)
    pts = np.random.default_rng(1).uniform(-2, 2, size=(2, 7))
    for got, want in ((f * g, fe * ge), (f.dpsi(), sp.diff(fe, psi)), (f.da(), sp.diff(fe, a))):
        h = sp.lambdify((a, psi), got.as_expr(psi) - want, "numpy")
        np.testing.assert_allclose(h(*pts), 0, atol=1e-9)


one_gen = st.dictionaries(st.integers(-3, 6), st.fractions(max_denominator=9).filter(bool),
                          max_size=5)


def _one_gen_pair(terms):
    """The same one-generator Laurent polynomial in a dense ring and a sparse one."""
    dense, sparse = LaurentRing([a]), LaurentRing([a])
    sparse.dense = False
    return tuple(Laurent(ring, {ring.monomial([e]): Q(c) for e, c in terms.items()})
                 for ring in (dense, sparse))


@pytest.mark.skipif(not kbm.algebra.laurent.HAVE_DENSE, reason="needs python-flint")
@given(one_gen, one_gen)
def test_dense_laurent_arithmetic_is_the_sparse_one_exactly(t1, t2):
    (p, ps), (q, qs) = _one_gen_pair(t1), _one_gen_pair(t2)
    assert p.ring.dense and not ps.ring.dense
    for got, want in ((p * q, ps * qs), (p + q, ps + qs), (p - q, ps - qs),
                      (p.diff(0), ps.diff(0)), (p.shift(0, -2), ps.shift(0, -2)),
                      (p.scale(Q(-3, 4)), ps.scale(Q(-3, 4)))):
        assert got.terms == want.terms
        assert bool(got) == bool(want)
        assert sp.srepr(got.as_expr()) == sp.srepr(want.as_expr())
        assert sp.srepr(got.as_primitive_expr()) == sp.srepr(want.as_primitive_expr())


@pytest.mark.skipif(not kbm.algebra.laurent.HAVE_DENSE, reason="needs python-flint")
def test_dense_fourier_product_is_the_sparse_one_exactly():
    raw = kbm.expansion.one_dof.run_recursion("vdp", 6)
    for f in raw.u:
        for g in raw.u:
            dense, sparse = f._mul_dense(g), f._mul_sparse(g)
            for d1, d2 in ((dense.cos, sparse.cos), (dense.sin, sparse.sin)):
                assert sorted(d1) == sorted(d2)
                assert all(d1[m].terms == d2[m].terms for m in d1)


# ----------------------------------------------------------------------------- Bessel algebra
def test_jacobi_anger_families_evaluate_like_sin_and_cos():
    """sin(z cos psi), cos(z cos psi) from the families match numpy at z = 1.7."""
    from kbm.output.evaluate import numpy_function

    z, psis = 1.7, np.linspace(0, 2 * np.pi, 9)
    s, c = jacobi_anger(sp.Symbol("z"))
    for fam, exact in ((s, np.sin(z * np.cos(psis))), (c, np.cos(z * np.cos(psis)))):
        f = numpy_function(fam.as_expr(psi), [sp.Symbol("z"), psi])
        np.testing.assert_allclose(f(z, psis), exact, atol=1e-14)


def test_sym_fourier_harmonic_of_a_single_family():
    """The 3rd harmonic of sin(z cos psi) is -2 J_3(z) (the family's n = 1 point)."""
    z = sp.Symbol("z")
    s, _ = jacobi_anger(z)
    c3, s3 = s.harmonic(3)
    assert sp.simplify(c3 + 2 * sp.besselj(3, z)) == 0 and s3 == 0
    assert SymFourier.harmonic_term(COS, 2, z).harmonic(2) == (z, 0)


@given(st.integers(-4, 4), st.integers(-4, 4), st.integers(-6, 6), st.integers(-6, 6))
def test_egcd_and_lattice_line_against_brute_force(p1, p2, q, target):
    g, u, w = egcd(p1, p2)
    assert p1 * u + p2 * w == g >= 0
    n1, n2 = sp.Symbol("n1", integer=True), sp.Symbol("n2", integer=True)
    h = p1 * n1 + p2 * n2 + q
    idx = ((n1, 0), (n2, 1))
    brute = {(i, j) for i, j in itertools.product(range(0, 30), range(1, 30))
             if p1 * i + p2 * j + q == target}
    ln = line(h, idx, target)
    if ln is None:
        assert not brute
    elif ln == "all":
        assert p1 == p2 == 0 and q == target
    else:
        x0, y0, d1, d2, lo, hi = ln
        steps = range(lo if lo is not None else -60, (hi if hi is not None else 60) + 1)
        pts = {(x0 + d1 * s, y0 + d2 * s) for s in steps}
        assert brute <= pts
        assert all(i >= 0 and j >= 1 for i, j in pts)


def test_line_sum_finite_and_infinite():
    n1, n2, k = (sp.Symbol(s, integer=True) for s in ("n1", "n2", "k"))
    c = sp.Rational(1, 2)**n1 * sp.Rational(1, 3)**n2
    # n1 + n2 = 3, n1, n2 >= 0: four points
    finite = line_sum(c, n1 + n2, ((n1, 0), (n2, 0)), 3, k)
    assert finite == sum(sp.Rational(1, 2)**i * sp.Rational(1, 3)**(3 - i) for i in range(4))
    # n1 - n2 = 1: infinitely many points, a Sum over the fresh index k
    inf = line_sum(c, n1 - n2, ((n1, 0), (n2, 0)), 1, k)
    assert isinstance(inf, sp.Sum) and inf.limits[0][0] == k
    assert sp.nsimplify(inf.doit()) == sp.Rational(1, 2) / (1 - sp.Rational(1, 6))


# ----------------------------------------------------------------------------- lazy series
def test_tail_and_powers_of_the_builder():
    """Tail drops the eps^0 coefficient; Builder.power (by squaring, memoised) equals the
    repeated product."""
    alg = PolyAlgebra(get_model("vdp"))
    x0 = alg.x0()
    X = Leaf(alg.zero, x0)
    V = Leaf(alg.zero, alg.scale(alg.dpsi(x0), alg.w0))
    X.append(alg.scale(x0, alg.coef(sp.Integer(3))))
    X.append(alg.const(sp.Integer(5)))
    builder = Builder(alg, X, V)
    tail = Tail(alg.zero, X)
    assert tail.coeff(0).is_zero()
    assert alg.series_expr(tail.coeff(2)) == 5
    assert builder.delta() is builder.delta()
    cube = builder.power("x", X, 3)
    assert builder.power("x", X, 3) is cube
    naive = Product(alg.zero, Product(alg.zero, X, X), X)
    for n in range(3):
        assert sp.expand(alg.series_expr(cube.coeff(n)) - alg.series_expr(naive.coeff(n))) == 0
    node = builder.build(sp.expand((1 - x**2) * xdot))
    want = -a * (1 - a**2 * sp.cos(psi)**2) * sp.sin(psi)
    assert sp.simplify(alg.series_expr(node.coeff(0)) - want) == 0
