"""The stationary Kramers solve folded by the symmetry (x, v) -> (-x, -v)
(numerics/fokker_planck/_parity.py).

References: the whole (unfolded) collocation operator, whose restriction to the even
subspace the folded one must be (hypothesis, random coefficients of the parity of their
order); the Boltzmann density exp(-G(x)/kT) of a linear damping -gamma x', by adaptive
quadrature (Risken, The Fokker-Planck Equation, eq. 10.1: the Maxwell-Boltzmann
distribution is the stationary solution when the friction is constant).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.integrate import quad

from kbm.model.conservative import split_conservative
from numerics.fokker_planck._bases import cheb_centred
from numerics.fokker_planck._orthonormal import orthonormal_terms
from numerics.fokker_planck._parity import (fold_terms, fold_weights, parity_maps,
                                            reflection_symmetric, unfold)
from numerics.fokker_planck._stationary_solve import orthonormal_stationary


def _apply(terms, c):
    out = np.zeros_like(c)
    for H, X in terms:
        out += (H @ c) @ X.T if np.ndim(X) == 2 else (H @ c) * X
    return out


@settings(max_examples=20, deadline=None)
@given(st.floats(0.05, 0.5), st.floats(0.5, 4.0), st.integers(4, 12), st.integers(5, 20),
       st.integers(0, 2**31 - 1))
def test_folded_operator_is_the_restriction(mu, Delta, nh, half, seed):
    """For coefficients of the parity of their order, c_n(-x) = (-1)^n c_n(x), the folded
    terms applied to the values at x >= 0 equal the whole operator's rows at x >= 0 (SEDF,
    random mu and Delta, the saddle-centred points), to rounding."""
    split = split_conservative("sedf", {"mu": mu, "Delta": Delta, "beta": 1, "lam": 1})
    nc = 2 * half
    xs, Dx = cheb_centred(nc, 6.0, 0.95, (-1.5, 1.5), (0.2, 0.2), 0.3)
    assert reflection_symmetric(split, xs)
    terms = orthonormal_terms(split, mu / 2, 0.3, xs, Dx, nh)
    c = unfold(np.random.default_rng(seed).standard_normal((nh, nc // 2 + 1)), nc + 1)
    whole = _apply(terms, c)[:, :nc // 2 + 1]
    folded = _apply(fold_terms(terms, nc + 1), c[:, :nc // 2 + 1])
    assert np.max(np.abs(folded - whole)) <= 1e-11 * max(1.0, np.max(np.abs(whole)))
    w = np.random.default_rng(seed + 1).random(nc + 1)
    w = w + w[::-1]
    assert fold_weights(w).sum() == pytest.approx(w.sum(), rel=1e-14)


@settings(max_examples=20, deadline=None)
@given(nc=st.integers(2, 40), seed=st.integers(0, 2**31 - 1), keep_zero=st.booleans())
def test_parity_maps_extend_even_and_odd_functions(nc, seed, keep_zero):
    """The folded unknowns extend to the whole symmetric grid as an even function (even
    Hermite orders) and an odd one (odd orders, zero at ``x = 0``): ``F`` reproduces
    ``f(x) +- f(-x)`` sampled on the points kept, with ``x = 0`` kept for the odd orders
    (``keep_zero``, the stationary solve's fold) or not (the escape's)."""
    from numerics.fokker_planck._bases import cheb

    x, _ = cheb(nc, 1.0)
    assert np.allclose(x, -x[::-1], atol=1e-15)
    f = np.random.default_rng(seed).standard_normal(x.size)
    for (idx, F), sign in zip(parity_maps(x.size, True, keep_zero), (1.0, -1.0)):
        sym = f + sign * f[::-1]
        assert np.all(x[idx] > (-1e-15 if sign > 0 or keep_zero else 1e-15))
        np.testing.assert_allclose(F @ sym[idx], sym, atol=1e-14)


def test_asymmetric_models_are_not_folded():
    """A tilt breaks g(-x) = -g(x): no folding (and a point set that is not symmetric)."""
    split = split_conservative("sedf", {"mu": 0.1, "Delta": 3, "beta": 1, "lam": 1})
    xs, _ = cheb_centred(40, 6.0, 0.95, (1.5,), (0.2,), 0.3)
    assert not reflection_symmetric(split, xs)


@settings(max_examples=4, deadline=None)
@given(st.floats(1.0, 3.0), st.floats(0.3, 0.8))
def test_linear_damping_folded_is_boltzmann(Delta, kT):
    """The CDC (friction -mu x', constant): the folded orthonormal solve's <x^2> equals the
    Boltzmann value int x^2 exp(-G/kT) / int exp(-G/kT) to 1e-8, and the unfolded solve of
    the same sizes to 1e-10."""
    mu = 0.2
    params = {"mu": mu, "Delta": Delta, "lam": 1.3}
    split = split_conservative("cdc", params)
    G = split.numpy_functions()[2]
    D = mu * kT
    folded = orthonormal_stationary(split, D, math.sqrt(kT), 7.0, 8, 320, G, 1.0, fold=True)
    whole = orthonormal_stationary(split, D, math.sqrt(kT), 7.0, 8, 320, G, 1.0, fold=False)
    z = quad(lambda x: math.exp(-float(G(np.array(x))) / kT), -7, 7, limit=400, epsabs=0,
             epsrel=1e-13)[0]
    x2 = quad(lambda x: x * x * math.exp(-float(G(np.array(x))) / kT), -7, 7, limit=400,
              epsabs=0, epsrel=1e-13)[0] / z
    assert folded.x2 == pytest.approx(x2, rel=1e-8)
    assert folded.v2 == pytest.approx(kT, rel=1e-8)
    assert folded.x2 == pytest.approx(whole.x2, rel=1e-10)
