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

from kbm.model.builtins import custom_model
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


@pytest.mark.parametrize("params, vary, at, span, x_turn", [
    # the SEDF (paper eq. 3) at its homoclinic end: the saddles at x = +-1.581
    ({"mu": 0.1, "beta": 1, "lam": 1}, "Delta", 3.2486, (-2.0976, 2.0976), 2.0976),
    # the side-well cycle of beta = 1.3 (Delta = 1.5): one saddle inside its span
    ({"mu": 0.1, "lam": 1, "Delta": 1.5}, "beta", 1.3, (-0.9, -0.3), -0.3),
    # the double well x'' = x - x^3 + eps(...) x': the saddle at 0
    ({"mu": 1, "eps": 0.02, "beta": 1.0}, "alpha", -0.8, (-1.4, 1.4), 1.4),
])
def test_saddles_from_the_compiled_force_equal_the_portraits(params, vary, at, span, x_turn):
    """numerics.cycles.homoclinic.saddles_passed: the saddles and their unstable eigenvalues
    from the compiled force (zeros and quadrature) against the conservative phase portrait
    (symbolic split and potential)."""
    import numpy as np

    import numerics.shooting.planar as arc
    from kbm.parameters.bound import bind
    from numerics.cycles.homoclinic import saddles_passed

    model = "sedf" if "lam" in params else MODEL
    prob = arc.PlanarProblem(model, params, vary, "auto", 1e-10, at)
    prob.choose(np.array([max(abs(span[0]), abs(span[1])), 7.0, at]))
    force = prob.force(at)
    assert force is not None
    bound = bind(model, {**params, vary: at})
    fast = saddles_passed(bound, *span, x_turn, force=force)
    ref = saddles_passed(bound, *span, x_turn)
    assert len(fast[0]) == len(ref[0]) >= 1
    assert np.allclose(fast[0], ref[0], atol=1e-12)
    assert np.allclose(fast[1], ref[1], rtol=1e-10)
