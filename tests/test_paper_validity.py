"""The SEDF validity map of KBM orders 1 and 2 (numerics.paper.validity), on a small grid."""

from __future__ import annotations

import pytest

from numerics.paper.validity import validity_map

from _maps import point_at


@pytest.fixture(scope="module")
def vmap():
    return validity_map([0.02, 0.1], [0.01, 1.0, 1.5], [1.0], workers=2, progress=False)


def test_small_delta_within_one_percent(vmap):
    """Paper eq. (3) with Delta = 0.01: both KBM orders are within 1 % of the true cycle,
    order 2 at least five times closer than order 1."""
    for mu in (0.02, 0.1):
        p = point_at(vmap, mu, 0.01)
        assert p.success
        assert p.error(2) < p.error(1) / 5 < 1e-3
    assert {(p.params["mu"], p.params["Delta"]) for p in vmap.within(0.01, 2)} == {
        (0.02, 0.01), (0.1, 0.01)}


def test_paper_parameters_outside(vmap):
    """At the paper's mu = 0.1, Delta = 1.5 (beta = 1) neither order is within 1 %, and the
    second order is worse than the first (asymptotic series outside its range)."""
    p = point_at(vmap, 0.1, 1.5)
    assert p.success
    assert 0.01 < p.error(1) < p.error(2)


def test_error_depends_on_delta_not_ratio(vmap):
    """The expansion is a double series in mu and Delta (terms mu^(n-m) Delta^m): at fixed
    Delta = 1 the error hardly changes between Delta/mu = 50 and Delta/mu = 10."""
    for N in (1, 2):
        e1, e2 = point_at(vmap, 0.02, 1.0).error(N), point_at(vmap, 0.1, 1.0).error(N)
        assert abs(e1 - e2) < 0.05 * e1
