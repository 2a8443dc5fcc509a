"""The equilibria of :class:`numerics.bifurcation.autonomous.OneDof` (the zeros of
``f(x, 0)``, found from sign changes on a grid): the grid evaluated as one array must give
the roots that the point-by-point scalar evaluation gives, to the bit, and each root must
solve the SEDF's equilibrium equation ``x + Delta sin(2 pi x) = 0`` (paper eq. 3 at rest,
``lam = 1``; closed form of the residual)."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import brentq

from numerics.bifurcation.autonomous import OneDof

SEDF = ("sedf", {"mu": "0.1", "lam": "1"}, ("Delta", "beta"))


def _scalar_scan(kit: OneDof, a: float, b: float, L: float, n: int = 4001):
    """The zeros of ``f(x, 0)`` from ``f`` evaluated point by point (the scalar
    function), Brent in each sign change: the second method."""
    pv = kit.compiled(a, b).pvec
    f = kit._d[(0, 0)]
    xs = np.linspace(-L, L, n)
    vals = [f(x, 0.0, *pv) for x in xs]
    out = []
    for k in range(n - 1):
        if vals[k] == 0 or vals[k] * vals[k + 1] < 0:
            x = xs[k] if vals[k] == 0 else brentq(lambda s: f(s, 0.0, *pv), xs[k], xs[k + 1],
                                                   xtol=1e-14, rtol=1e-15)
            out.append(float(x))
    return out


@settings(max_examples=20)
@given(delta=st.floats(0.2, 6.0), beta=st.floats(0.3, 1.6))
def test_equilibria_on_the_array_grid_equal_the_scalar_scan(delta, beta):
    kit = OneDof(*SEDF, (delta, beta))
    eq = kit.equilibria(delta, beta, 4.0)
    assert [x for x, _ in eq] == _scalar_scan(kit, delta, beta, 4.0)
    for x, kind in eq:
        assert abs(x + delta * math.sin(2 * math.pi * x)) <= 1e-12
        # a saddle where f_x = -1 - 2 pi Delta cos(2 pi x) > 0
        assert (kind == "saddle") == (-1 - 2 * math.pi * delta * math.cos(2 * math.pi * x) > 0)
    assert any(x == 0.0 for x, _ in eq)  # the origin, an exact zero on the grid
