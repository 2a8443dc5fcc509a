"""Both sinks of a sink-ladder rung from one factorisation
(:mod:`numerics.fokker_planck._sink_pairs`): the transposed sweeps against a dense solve
with the transposed matrix, the slope of the slowest decay rate (first-order perturbation
of a simple eigenvalue by its left and right modes; Kato, *Perturbation Theory for
Linear Operators*, II.2) against the central difference of two solves, and the paired
ladders on closed-form rungs (straight lines in the offset, ``_sink``'s model) against
those lines.  The slow tests of ``tests/test_fokker_planck_sink.py`` check the paired top
rungs of the CDC against both sinks solved independently (``_independent_top``)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings, strategies as st

from kbm.model.conservative import split_conservative
from numerics.fokker_planck._bases import cheb_centred
from numerics.fokker_planck._folded import FoldedRungs, FoldedTermBlocks
from numerics.fokker_planck._folded_orders import FoldedOrderLU
from numerics.fokker_planck._orthonormal import orthonormal_terms
from numerics.fokker_planck._sink import absorbing_limit, sink_grading, sink_rung
from numerics.fokker_planck._sink_pairs import PAIRED, tanh_sink, tanh_sink_slope
from numerics.fokker_planck.escape import ALPHA
from numerics.fokker_planck._problem import escape_problem

KT = 0.35
SADDLE = 0.5281669331486846  # the CDC's at Delta = 3, lam = 1


def _rung(mu, j, offset, grid_offset):
    """The CDC's rung ``j``: the sink at ``offset``, the points crowded at the centres of
    ``grid_offset`` (as :func:`numerics.fokker_planck.escape.kramers_escape`'s rungs)."""
    split = split_conservative("cdc", {"mu": mu, "Delta": 3, "Omega": 1, "lam": 1})
    D = KT * mu
    _, wells, half, kappa0, width = escape_problem(split, D, (-SADDLE, SADDLE))
    centres, kap, w = sink_rung(wells, kappa0, width, j, offset)
    grid = sink_rung(wells, kappa0, width, j, grid_offset)[0]
    grading = sink_grading(j)

    def points(m):
        return cheb_centred(m, half, ALPHA, (-SADDLE, SADDLE) + grid * len(grading),
                            (SADDLE / 2, SADDLE / 2) + tuple(f * w for f, _ in grading
                                                             for _ in (0, 1)),
                            (0.0, 0.0) + tuple(q for _, q in grading for _ in (0, 1)))

    return split, D, points, centres, kap, w


@pytest.mark.parametrize("sharp", [1, 8])
def test_transposed_solve_is_the_dense_transpose(sharp):
    """``FoldedOrderLU.solve_transposed`` solves ``A^T x = b`` as a dense solve with the
    transposed folded matrix does (1e-12), at every truncation, with the first sink and a
    rung's sharper one."""
    split, D, points, centres, kap, w = _rung(0.2, 0, 1.0, 1.0)
    xs, Dx = points(24)
    A = FoldedTermBlocks(orthonormal_terms(split, D, 0.6 * math.sqrt(KT), xs, Dx, 16),
                         xs.size, tanh_sink(xs, centres, kap * sharp ** 2, w / sharp))
    lu = FoldedOrderLU(A, 16)
    rng = np.random.default_rng(6)
    for n in (3, 8, 16):
        rhs = rng.standard_normal(n * A.mm)
        dense = np.linalg.solve(A.block(0, n, 0, n).T, rhs)
        got = lu.solve_transposed(rhs, n)
        assert np.max(np.abs(got - dense)) <= 1e-12 * np.max(np.abs(dense))


@pytest.mark.parametrize("mu,j", [(5.0, 2), (20.0, 4)])
def test_slope_is_the_central_difference(mu, j):
    """``FoldedRungs.slope`` (``y^T dA x / y^T K x``) with :func:`tanh_sink_slope` is the
    central difference ``(r(o + h) - r(o - h))/2h`` of the rates with the sink moved by
    ``+-h`` widths on the same points (``h`` = 0.01: its error ``h^2 r'''/6`` is below
    1e-6 of the slope) to 1e-6, and it is negative (a sink moved out absorbs less)."""
    o, h, nh, nc = 1.5, 0.01, 48, 96
    split, D, points, centres, kap, w = _rung(mu, j, o, o)
    s = 0.6 * math.sqrt(KT)
    solver = FoldedRungs(nh, by_order=True)
    solver(split, D, s, points, nh, nc, lambda xs: tanh_sink(xs, centres, kap, w))
    slope = solver.slope(lambda xs: tanh_sink_slope(xs, centres, kap, w))
    rates = []
    for d in (h, -h):
        c = _rung(mu, j, o + d, o)[3]
        rates.append(FoldedRungs(nh, by_order=True)(split, D, s, points, nh, nc,
                                                    lambda xs, c=c: tanh_sink(xs, c, kap, w)))
    assert slope < 0
    assert slope == pytest.approx((rates[0] - rates[1]) / (2 * h), rel=1e-6)


@settings(max_examples=20, deadline=None)
@given(r=st.floats(0.01, 1.0), a=st.floats(1e-2, 1e-1), o0=st.floats(0.6, 1.2),
       k=st.floats(0.05, 0.15), bh=st.floats(1e-4, 1e-2), lh=st.floats(15.0, 30.0))
def test_paired_ladders_on_closed_form_rungs(r, a, o0, k, bh, lh):
    """``absorbing_limit(adaptive=True, paired=True)`` on closed-form rungs, straight lines
    ``r - a w_j (o - o0 - k j)`` plus a Hermite error ``bh r exp(-n/lh)``, with their exact
    slope ``-a w_j``: from :data:`PAIRED` on every rung is solved at the midpoint of its
    two offsets only, the gap between its two rates is the lines' (the Hermite error is
    common to both), and the rate lies within the stated errors of ``r``.  ``a >= 0.01 r``
    as in ``test_adaptive_rungs_state_their_errors`` (below, the ladders' placement fails
    on the Hermite errors)."""
    assume(a >= 0.01 * r)
    solved = []

    def rung(j, o, nc, nh, slope=False):
        solved.append((j, o))
        rate = r - a * 2.0**-j * (o - o0 - k * j) + bh * r * math.exp(-nh / lh)
        return (rate, lambda: -a * 2.0**-j) if slope else rate

    out = dict(rate=r, sink_error=1.0, chebyshev_error=0.0, truncation_error=0.0,
               hermite=64, chebyshev=129)
    res = absorbing_limit(out, rung, adaptive=True, paired=True)
    offsets, n = res["sink_offsets"], len(res["sink_offsets"])
    assert n > PAIRED + 1  # the ladders climbed past the first paired rung
    for j, o in solved:
        if j >= PAIRED:
            assert o == pytest.approx(sum(offsets[j]) / 2, abs=1e-15)
    for j in range(PAIRED, n):
        gap = res["sink_ladder"][n + j] - res["sink_ladder"][j]
        assert gap == pytest.approx(a * 2.0**-j * (offsets[j][0] - offsets[j][1]),
                                    abs=1e-12 * r)
    nh = res["hermite"]
    assert abs(res["rate"] - r) <= (res["sink_error"] + res["truncation_error"]
                                    + bh * r * math.exp(-nh / lh) + 1e-13 * r)
