"""The two-angle Fourier algebra (kbm.algebra.two_angle) against pointwise evaluation."""

from __future__ import annotations

import math

import sympy as sp
from hypothesis import given
from hypothesis import strategies as st

from kbm.algebra.laurent import LaurentRing
from kbm.algebra.two_angle import TwoAngle, canonical
from kbm.symbols import a, psi

theta = sp.Symbol("theta")
RING = LaurentRing([a])

_harm = st.tuples(st.integers(-3, 3), st.integers(-3, 3), st.integers(-4, 4),
                  st.integers(0, 2), st.sampled_from(["cos", "sin"]))
_series = st.lists(_harm, min_size=1, max_size=4)


def _build(terms) -> TwoAngle:
    out = TwoAngle(RING)
    for m, k, c, e, kind in terms:
        out = out + TwoAngle.harmonic(RING, m, k, RING.const(c).shift(0, e), kind)
    return out


def _value(f: TwoAngle, av: float, p: float, t: float) -> float:
    return float(f.as_expr(psi, theta).subs({a: av, psi: p, theta: t}))


POINT = (0.7, 0.3, -1.1)


@given(_series, _series)
def test_product_and_sum_pointwise(f, g):
    F, G = _build(f), _build(g)
    v = _value(F, *POINT), _value(G, *POINT)
    assert math.isclose(_value(F * G, *POINT), v[0] * v[1], rel_tol=1e-12, abs_tol=1e-12)
    assert math.isclose(_value(F - G, *POINT), v[0] - v[1], rel_tol=1e-12, abs_tol=1e-12)


@given(_series)
def test_derivatives_and_canonical_form(f):
    F = _build(f)
    e = F.as_expr(psi, theta)
    for which, var in ((0, psi), (1, theta)):
        d = F.d_angle(which).as_expr(psi, theta)
        assert sp.simplify(sp.expand_trig(d - sp.diff(e, var))) == 0
    assert sp.simplify(F.da().as_expr(psi, theta) - sp.diff(e, a)) == 0
    assert all(m > 0 or (m == 0 and k >= 0) for m, k in F.harmonics())


def test_canonical():
    assert canonical(-1, 2) == (1, -2, -1)
    assert canonical(0, -3) == (0, 3, -1)
    assert canonical(2, -1) == (2, -1, 1)
