"""Saddle connections by shooting the manifolds (numerics.cycles.manifolds) against
Mel'nikov's first-order prediction.

x'' = x - x^3 + eps (alpha + beta x^2) x' (written x'' + x = mu F with mu = 1 and
F = 2x - x^3 + eps (alpha + beta x^2) x') has at eps = 0 the homoclinic loop
x0 = sqrt(2) sech t of the saddle at 0.  Mel'nikov's function (Guckenheimer & Holmes 1983,
sec. 4.5) M = int v0^2 (alpha + beta x0^2) dt = 4 alpha/3 + 16 beta/15 vanishes at
alpha = -4 beta/5: the loop persists at alpha_h(eps) = -4 beta/5 + O(eps^2) (time reversal,
t -> -t with eps -> -eps, maps the loop to itself, so alpha_h is even in eps).
"""

from __future__ import annotations

import pytest

from kbm.models import custom_model
from numerics.cycles.manifolds import connection_gap, saddle_connection
from numerics.errors import ConvergenceError

MODEL = custom_model("2*x - x**3 + eps*(alpha + beta*x**2)*xdot")


def test_homoclinic_loop_against_melnikov():
    beta = 1.0
    errors = []
    for eps in (0.04, 0.02, 0.01):
        c = saddle_connection(MODEL, {"mu": 1, "eps": eps, "beta": beta}, "alpha",
                              (-1.2, -0.4), 0.0, 0.0, 1, 1)
        errors.append(c.parameter + 0.8 * beta)
        assert c.error < 1e-9 and c.saddles == (0.0, 0.0)
    assert abs(errors[-1]) < 1e-5
    for big, small in zip(errors, errors[1:]):
        assert 3.6 < big / small < 4.4  # O(eps^2): halving eps quarters the error


def test_no_connection_is_said():
    with pytest.raises(ConvergenceError, match="no saddle connection"):
        saddle_connection(MODEL, {"mu": 1, "eps": 0.01, "beta": 1.0}, "alpha", (0.5, 1.0),
                          0.0, 0.0, 1, 1)
    # the gap changes sign across the connection
    lo = connection_gap(MODEL, {"mu": 1, "eps": 0.01, "beta": 1.0, "alpha": -1.0}, 0, 0, 1, 1)
    hi = connection_gap(MODEL, {"mu": 1, "eps": 0.01, "beta": 1.0, "alpha": -0.6}, 0, 0, 1, 1)
    assert lo[0] * hi[0] < 0
