"""The escape rate of nonlinearly damped models in orthonormal Hermite functions
(numerics/fokker_planck/_orthonormal.py; issue 36: "the escape rate at any damping, to 6
or more digits").

References, none produced by the solver under test:

* the Hermite functions' recurrences against Gauss-Hermite quadrature (exact for the
  polynomial integrands);
* the Galerkin projection's bound: in ``L^2(dv)`` the friction ``-d/dv(a v P)`` contributes
  ``-a/2`` to the symmetric part and the diffusion a negative part, so the truncated
  velocity operator's numerical range lies below ``-a/2`` whatever the truncation (in
  Risken's pair ``He_n exp(-u^2/2)``, ``He_n`` the same operator has the eigenvalues
  ``-n gamma``, growing with ``n`` where ``gamma < 0``: the cause of the old ladder's
  failure);
* a second discretisation: plain Chebyshev-Gauss-Lobatto points (not crowded), another
  velocity scale and other truncations, which must give the same rate;
* simulated transitions to the next wells' bottoms (fixed seed), counted after the
  trajectories started at the bottom have relaxed into the well's quasi-stationary state
  (from there the waiting time is exponential with mean ``1/r``; Hanggi, Talkner and
  Borkovec, Rev. Mod. Phys. 62 (1990) 251, sec. II.C).

The SEDF at rest (paper eq. 3 with v = 0): ``x'' + mu (beta x^2 - 1) x' + Delta sin(2 pi
x) + x = 0``, Delta = 3, D/mu = 0.5, its damping negative in the whole well and at the
next wells' bottoms (|x| < 1).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import brentq

from kbm.model.conservative import split_conservative
from kbm.model.builtins import custom_model
from numerics.fokker_planck import kramers_escape
from numerics.fokker_planck._bases import cheb, hermite_matrices
from numerics.fokker_planck._orthonormal import (orthonormal_matrices, orthonormal_slowest,
                                                 velocity_scale)
from numerics.fokker_planck._problem import escape_problem
from numerics.fokker_planck._sink_pairs import tanh_sink

SEDF = {"Delta": 3, "beta": 1, "lam": 1}


def _saddles(split):
    g = split.numpy_functions()[0]
    xs = brentq(lambda z: float(g(np.array(z))), 0.3, 0.8, xtol=1e-15)
    return (-xs, xs)


def _orthonormal_functions(n, xi):
    out = np.zeros((n,) + np.shape(xi))
    out[0] = math.pi ** -0.25 * np.exp(-xi**2 / 2)
    if n > 1:
        out[1] = math.sqrt(2) * xi * out[0]
    for k in range(1, n - 1):
        out[k + 1] = math.sqrt(2 / (k + 1)) * xi * out[k] - math.sqrt(k / (k + 1)) * out[k - 1]
    return out


def test_orthonormal_recurrences_against_quadrature():
    """``<h_m, xi h_n>`` and ``<h_m, h_n'>`` by 80-point Gauss-Hermite quadrature (exact for
    these polynomial-times-``exp(-xi^2)`` integrands) equal the tridiagonal matrices; the
    functions are orthonormal."""
    n = 24
    t, w = np.polynomial.hermite.hermgauss(80)
    h = _orthonormal_functions(n + 1, t) * np.exp(t**2 / 2)  # h_k exp(+xi^2/2)
    gram = (h[:n] * w) @ h[:n].T
    np.testing.assert_allclose(gram, np.eye(n), atol=1e-12)
    X, Dxi = orthonormal_matrices(n + 1)
    xh = (h[:n] * w) @ (t * h[:n]).T
    # h_n' = (sqrt(2n) h_{n-1} - xi h_n)... from the definition: d/dxi [H_n e^{-xi^2/2}]
    dh = np.zeros_like(h)
    for k in range(n + 1):
        dh[k] = (math.sqrt(2 * k) * h[k - 1] if k else 0.0) - t * h[k]
    dxh = (h[:n] * w) @ dh[:n].T
    np.testing.assert_allclose(xh, X.toarray()[:n, :n], atol=1e-12)
    np.testing.assert_allclose(dxh, Dxi.toarray()[:n, :n], atol=1e-12)


@settings(max_examples=25, deadline=None)
@given(a=st.floats(0.01, 2.0), D=st.floats(0.01, 1.0), s=st.floats(0.1, 3.0),
       n=st.integers(4, 200))
def test_truncated_velocity_operator_is_bounded_above(a, D, s, n):
    """Galerkin in ``L^2(dv)``: ``-d/dv(a v P) + D P''`` projected on ``h_0 .. h_{n-1}`` has a
    symmetric part ``<= -a/2`` for an anti-damping ``a > 0`` (no order grows), while in
    Risken's pair the same operator's top order grows at ``(n - 1) a``."""
    X, Dq = orthonormal_matrices(n + 3)
    op = (-(Dq @ X) * a + (Dq @ Dq) * (D / s**2)).toarray()[:n, :n]
    top = np.linalg.eigvalsh(0.5 * (op + op.T))[-1]
    assert top <= -a / 2 + 1e-9 * (1 + a + D / s**2 * n)
    U, Du = hermite_matrices(n, 3)
    old = (-(Du @ U) * a + (Du @ Du) * (D / s**2)).toarray()[:n, :n]
    assert old[n - 1, n - 1] == pytest.approx((n - 1) * a)


def _independent_rate(model, params, D, fac, nh, nc):
    """The rate on plain Chebyshev points at ``fac`` times the default velocity scale."""
    split = split_conservative(model, params)
    saddles = _saddles(split)
    _, wells, half, kappa0, width = escape_problem(split, D, saddles)
    s, _ = velocity_scale(split, D, saddles)
    return orthonormal_slowest(split, D, fac * s, lambda n: cheb(n, half), nh, nc,
                               lambda xs: tanh_sink(xs, wells, kappa0, width)), saddles


@pytest.mark.slow  # 4-7 s; the default run keeps its siblings (five-minute rule)
def test_sedf_escape_converges_against_a_second_discretisation():
    """SEDF mu = 0.3, D = 0.15: the default ladder's rate (stated truncation, scale and
    Chebyshev errors <= 1e-8 of it) equals the rate on plain Chebyshev points (192
    intervals) at 0.7 times the velocity scale within its stated errors plus 1e-9 (both with
    the first sink: ``sink_tol=inf``; the sink ladders' limit is tested below)."""
    params = dict(SEDF, mu=0.3)
    ref, saddles = _independent_rate("sedf", params, 0.15, 0.7, 90, 192)
    fp = kramers_escape("sedf", params, 0.15, saddles, sink_tol=math.inf)  # the first sink
    numerical = fp.truncation_error + fp.chebyshev_error
    assert numerical <= 1e-8 * fp.rate
    assert fp.scale_error <= fp.truncation_error
    assert abs(fp.rate - ref) <= numerical + 1e-9 * ref
    assert fp.sink_error <= 1e-5 * fp.rate


@pytest.mark.slow
@pytest.mark.parametrize("model, params, D", [
    ("sedf", dict(SEDF, mu=0.1), 0.05),
    ("sedf", dict(SEDF, mu=0.03), 0.015),
    ("sedf", dict(SEDF, mu=0.1, beta=0.5), 0.05),
    (custom_model("(1 - xdot**2/3)*xdot - delta*sin(2*pi*x)"), {"mu": 0.1, "delta": 30}, 0.05),
])
def test_nonlinear_escape_six_digits(model, params, D):
    """Three SEDFs and a Rayleigh damping in the same potential (velocity powers to 3): the
    rate with stated numerical errors <= 1e-7 of it, equal to a second discretisation
    (plain points, 256 intervals, 0.7 times the scale, 128 functions) within those errors
    plus 2e-9; the old ladder failed here (SEDF mu = 0.1: 1448 functions 3e-5 apart).  Both
    with the first sink (``sink_tol=inf``)."""
    ref, saddles = _independent_rate(model, params, D, 0.7, 128, 256)
    fp = kramers_escape(model, params, D, saddles, sink_tol=math.inf)  # the first sink
    numerical = fp.truncation_error + fp.chebyshev_error
    assert numerical <= 1e-7 * fp.rate
    assert abs(fp.rate - ref) <= numerical + 2e-9 * ref


@pytest.mark.slow
def test_sedf_escape_against_simulated_transitions():
    """SEDF mu = 0.3, D = 0.15: 8000 trajectories from the bottom (seed 0, the command's
    step), the transitions to the next wells' bottoms counted after t0 = 10 (about three
    lifetimes: the survivors have relaxed into the quasi-stationary state, whose waiting
    time is exponential with mean 1/r), within three standard errors of the FP rate."""
    from numerics.escape.transitions import simulated_transitions
    from numerics.noise.langevin import langevin_system, natural_step

    params = dict(SEDF, mu=0.3)
    split = split_conservative("sedf", params)
    saddles = _saddles(split)
    fp = kramers_escape("sedf", params, 0.15, saddles)
    system = langevin_system(split.model, {**{k: float(v) for k, v in split.params.items()},
                                           "mu": float(split.mu)}, 0.15)
    t_end, t0 = 40.0, 10.0
    sim = simulated_transitions(split, 0.15, saddles, kT=None, trajectories=8000,
                                t_end=t_end, dt=natural_step(system, per_period=40), seed=0,
                                wells=fp.wells, workers=1)
    tau = sim.times
    alive = tau > t0
    k = int(np.sum(alive & (tau < t_end)))
    rate = k / float(np.sum(tau[alive] - t0))
    assert k > 500
    assert abs(rate - fp.rate) < 3 * rate / math.sqrt(k)


@pytest.mark.slow
def test_sedf_sink_ladders_bracket_against_a_finer_solve():
    """SEDF mu = 0.3, D = 0.15 (the two sinks 3.5e-6 of the rate apart): the sink ladders of
    linear damping run (numerics/fokker_planck/_sink.py): the rising one rises, the falling
    one falls, the rate is the midpoint of their top rungs with half their gap as the sink
    error (within 1e-6 of the rate, where the first sink stated 3.5e-6), and the top rungs
    solved again on 1.75 times the intervals with sqrt 2 more Hermite functions (another
    discretisation of the same sinks) move the midpoint by less than the stated Chebyshev
    and truncation errors together plus 1e-9 of the rate."""
    from numerics.fokker_planck._bases import cheb_centred
    from numerics.fokker_planck._sink import WEIGHT, sink_rung
    from numerics.fokker_planck.escape import ALPHA, SADDLES

    params = dict(SEDF, mu=0.3)
    split = split_conservative("sedf", params)
    saddles = _saddles(split)
    fp = kramers_escape("sedf", params, 0.15, saddles)
    n = len(fp.sink_ladder) // 2
    low, high = fp.sink_ladder[:n], fp.sink_ladder[n:]
    assert n >= 2
    assert all(b > a for a, b in zip(low, low[1:]))
    assert all(b < a for a, b in zip(high, high[1:]))
    assert low[-1] <= fp.rate <= high[-1]
    assert fp.sink_error == pytest.approx((high[-1] - low[-1]) / 2)
    assert fp.sink_error <= 1e-6 * fp.rate
    _, wells, half, kappa0, width = escape_problem(split, 0.15, saddles)
    top = n - 1
    n_c, n_h = 2 * round(0.875 * (fp.chebyshev - 1)), 2 * round(fp.hermite / math.sqrt(2))
    rates = []
    for offset in fp.sink_offsets[top]:
        c, kap, w = sink_rung(wells, kappa0, width, top, offset)

        def pts(m, c=c, w=w):
            return cheb_centred(m, half, ALPHA, tuple(saddles) + c,
                                (-saddles[0] / 2, saddles[1] / 2, 2.5 * w, 2.5 * w),
                                (SADDLES, SADDLES, WEIGHT, WEIGHT))

        rates.append(orthonormal_slowest(split, 0.15, fp.velocity_scale, pts, n_h, n_c,
                                         lambda xs, c=c, kap=kap, w=w: tanh_sink(xs, c, kap, w)))
    stated = fp.chebyshev_error + fp.truncation_error
    assert abs(sum(rates) / 2 - fp.rate) <= stated + 1e-9 * fp.rate


def test_van_der_pol_stationary_moments_to_eight_digits():
    """vdp mu = 0.3, D = 0.15 (the stationary Kramers solve, orthonormal Hermite
    functions): the virial theorem ``<x^2> = <x'^2>`` (exact for ``g = x`` since
    ``<x (1 - x^2) x'>`` is the mean of a time derivative) to 1e-8, and ``<x^2>``,
    ``<a^2>`` equal to a second discretisation (Risken's pair at its own scale, 256
    functions x 132 intervals) to 1e-8; on the intervals that resolve ``exp(-G/sigma^2)``
    alone the pair's ``<x^2>`` was 1.1e-6 low."""
    from numerics.fokker_planck import stationary_kramers

    sol = stationary_kramers("vdp", {"mu": 0.3}, 0.15)
    assert sol.v2 == pytest.approx(sol.x2, rel=1e-8)
    ref = stationary_kramers("vdp", {"mu": 0.3}, 0.15, n_hermite=256, n_cheb=132,
                             basis="risken")
    assert sol.x2 == pytest.approx(ref.x2, rel=1e-8)
    assert sol.a2 == pytest.approx(ref.a2, rel=1e-8)
