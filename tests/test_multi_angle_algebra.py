"""The multi-angle Fourier algebra (kbm.algebra.multi_angle) against pointwise evaluation.

Products and differences of series in ``(psi, theta)`` and in three angles equal the
products and differences of their values at a point (the product-to-sum formulas), the
angle and amplitude derivatives equal sympy's derivatives of the expressions, and every
stored harmonic is canonical (its first nonzero index positive).  The two-angle case is the
algebra of the forced engine (:func:`kbm.expansion.forced.derive_forced`)."""

from __future__ import annotations

import math

import pytest
import sympy as sp
from hypothesis import given
from hypothesis import strategies as st

from kbm.algebra.laurent import LaurentRing
from kbm.algebra.multi_angle import MultiAngle, canonical
from kbm.symbols import a, psi

theta, chi = sp.Symbol("theta"), sp.Symbol("chi")
RING = LaurentRing([a])
ANGLES = {2: (psi, theta), 3: (psi, theta, chi)}
POINT = {a: 0.7, psi: 0.3, theta: -1.1, chi: 0.45}

_idx = st.integers(-3, 3)
_harm = st.tuples(st.tuples(_idx, _idx, _idx), st.integers(-4, 4), st.integers(0, 2),
                  st.sampled_from(["cos", "sin"]))
_series = st.lists(_harm, min_size=1, max_size=4)


def _build(terms, n: int) -> MultiAngle:
    out = MultiAngle(RING, n)
    for h, c, e, kind in terms:
        out = out + MultiAngle.harmonic(RING, h[:n], RING.const(c).shift(0, e), kind)
    return out


def _value(f: MultiAngle) -> float:
    return float(f.as_expr(ANGLES[f.n]).subs(POINT))


@pytest.mark.parametrize("n", [2, pytest.param(3, marks=pytest.mark.slow)])
@given(f=_series, g=_series)
def test_product_and_sum_pointwise(n, f, g):
    F, G = _build(f, n), _build(g, n)
    v = _value(F), _value(G)
    assert math.isclose(_value(F * G), v[0] * v[1], rel_tol=1e-12, abs_tol=1e-12)
    assert math.isclose(_value(F - G), v[0] - v[1], rel_tol=1e-12, abs_tol=1e-12)


@pytest.mark.parametrize("n", [2, 3])
@given(f=_series)
def test_derivatives_and_canonical_form(n, f):
    F = _build(f, n)
    e = F.as_expr(ANGLES[n])
    for which, var in enumerate(ANGLES[n]):
        d = F.d_angle(which).as_expr(ANGLES[n])
        assert sp.simplify(sp.expand_trig(d - sp.diff(e, var))) == 0
    assert sp.simplify(F.diff(0).as_expr(ANGLES[n]) - sp.diff(e, a)) == 0
    assert all(canonical(h) == (h, 1) for h in F.harmonics())


def test_canonical():
    assert canonical((-1, 2)) == ((1, -2), -1)
    assert canonical((0, -3)) == ((0, 3), -1)
    assert canonical((2, -1)) == ((2, -1), 1)
    assert canonical((0, 0, -1)) == ((0, 0, 1), -1)
