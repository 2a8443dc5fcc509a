"""Energy predictions over a map (numerics.energy.maps): the mu-independent portrait and
roots computed once per column and the warm-started position scheme give the same cycles
as predict_cycles point by point."""

from __future__ import annotations

import numpy as np
import pytest

from numerics.energy import predict_cycles
from numerics.energy.maps import map_predictions, predict_along_mu

KEYS = ("period", "amplitude_max", "amplitude_first_harmonic", "floquet_multiplier")


def _close(a, b, rtol):
    assert len(a.cycles) == len(b.cycles)
    assert a.params == pytest.approx(b.params, rel=1e-14)
    for x, y in zip(a.cycles, b.cycles):
        assert (x.annulus, x.stable, x.order) == (y.annulus, y.stable, y.order)
        for k in KEYS:
            assert getattr(x, k) == pytest.approx(getattr(y, k), rel=rtol), k


@pytest.mark.parametrize("Delta, beta", [(0.3, 1.0), (1.5, 0.25), (3.0, 1.0)])
def test_column_equals_predict_cycles(Delta, beta):
    """SEDF columns mu = 0.3 .. 0.005 at fixed Delta, beta: every order-2 cycle of
    predict_along_mu (tol 1e-9) equals predict_cycles' (tol 1e-11) to 1e-8 relative in
    period, max x, first harmonic and multiplier, with the same stability and annulus;
    at Delta = 3, beta = 1 the first mu have no order-2 cycle in both (the curve cannot
    pass the saddle)."""
    mus = [0.3, 0.2, 0.1, 0.03, 0.005]
    params = {"Delta": Delta, "beta": beta, "lam": 1}
    col = predict_along_mu("sedf", params, mus, order=2)
    for m, p in zip(mus, col):
        ref = predict_cycles("sedf", {**params, "mu": m}, order=2)
        _close(p, ref, 1e-8)
        assert bool(p.reason) == bool(ref.reason)


def test_first_order_rescaled_with_mu():
    """Order 1: the energy-balance roots computed once are the same at every mu, and the
    multiplier exp(mu dGamma/dE) and the period sensitivity are rescaled per mu exactly as
    predict_cycles computes them (1e-12)."""
    params = {"Delta": 1.5, "beta": 1.0, "lam": 1}
    mus = [0.2, 0.02]
    for m, p in zip(mus, predict_along_mu("sedf", params, mus, order=1)):
        ref = predict_cycles("sedf", {**params, "mu": m}, order=1)
        _close(p, ref, 1e-12)
        for x, y in zip(p.cycles, ref.cycles):
            assert x.period_sensitivity == pytest.approx(y.period_sensitivity, rel=1e-9)


def test_map_over_two_workers_is_ordered():
    """map_predictions over Delta on two processes returns out[i_Delta][i_mu], the same
    as one process."""
    args = ("sedf", {"beta": 1.0, "lam": 1}, [0.1, 0.05], "Delta", [0.01, 1.5])
    two = map_predictions(*args, workers=2)
    one = map_predictions(*args, workers=1)
    for c2, c1 in zip(two, one):
        for a, b in zip(c2, c1):
            _close(a, b, 1e-14)
    assert [p.params["delta"] for p in two[1]] == pytest.approx([15.0, 30.0])
    assert np.isclose(two[0][0].cycles[0].amplitude_max, 2.0, atol=1e-3)
