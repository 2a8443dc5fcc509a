"""Steady states of the forced slow flow (kbm.slowflow.steady) against closed forms.

Duffing primary resonance at first order (Nayfeh & Mook 4.1.1):
sigma = 3 alpha a^2/8 +- sqrt(h^2/(4 a^2) - zeta^2) (omega0 = 1), the backbone
sigma = 3 alpha a^2/8, the jump points where d sigma/da = 0 on that curve, and the middle
branch a saddle.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.optimize import brentq

from kbm.errors import ParameterError
from kbm.expansion.forced import derive_forced
from kbm.slowflow.steady import backbone, fixed_points, response_curve

Z, AL, H = 0.1, 1.0, 0.5


@pytest.fixture(scope="module")
def sf1():
    return derive_forced("duffing-forced", 2).slow_flow({"mu": 0.05, "zeta": Z, "alpha": AL,
                                                          "h": H}, order=1)


def _nm(av, sign):
    return 3 * AL * av**2 / 8 + sign * np.sqrt(H**2 / (4 * av**2) - Z**2)


@given(st.floats(-0.8, 3.0))
def test_fixed_points_on_the_nayfeh_mook_curve(s):
    sf = derive_forced("duffing-forced", 1).slow_flow({"mu": 0.05, "zeta": Z, "alpha": AL,
                                                        "h": H})
    fps = fixed_points(sf, s, (1e-3, 4))
    assert len(fps) in (1, 3)
    for f in fps:
        assert min(abs(_nm(f.amplitude, 1) - s), abs(_nm(f.amplitude, -1) - s)) < 1e-9
    if len(fps) == 3:  # lower and upper stable, middle a saddle (one positive eigenvalue)
        assert [f.stable for f in fps] == [True, False, True]
        assert sorted(e.real for e in fps[1].eigenvalues)[1] > 0


def test_folds_where_dsigma_da_vanishes(sf1):
    rc = response_curve(sf1, (-1.0, 3.0), (1e-3, 4))
    assert len(rc.branches) == 1 and len(rc.folds) == 2
    # closed form: both folds are critical points of sigma_+(a) (which tends to +oo as
    # a -> 0 and joins sigma_- at the peak a = h/(2 zeta)): a minimum (the jump up) and a
    # maximum just below the peak (the jump down)
    d = 1e-7

    def slope_plus(av):
        return (_nm(av + d, 1) - _nm(av - d, 1)) / (2 * d)

    a_top = H / (2 * Z)
    a_low = brentq(slope_plus, 0.3, 1.5, xtol=1e-13)
    a_up = brentq(slope_plus, 1.5, a_top - 1e-6, xtol=1e-13)
    lo, hi = rc.folds
    assert abs(lo.sigma - _nm(a_low, 1)) < 1e-8 and abs(lo.amplitude - a_low) < 1e-5
    assert abs(hi.sigma - _nm(a_up, 1)) < 1e-8 and abs(hi.amplitude - a_up) < 1e-5
    # both stable and unstable points, and unstable exactly between the folds
    b = rc.branches[0]
    assert b.stable.any() and (~b.stable).any()
    mid = b.sigma[~b.stable]
    assert mid.min() > lo.sigma - 1e-6 and mid.max() < hi.sigma + 1e-6


def test_backbone_first_order(sf1):
    av = np.array([0.3, 1.0, 2.0])
    assert np.allclose(backbone(sf1, av), 3 * AL * av**2 / 8, rtol=1e-12)


def test_points_contract(sf1):
    rc = response_curve(sf1, (-1.0, 3.0), (1e-3, 4), n_points=100)
    pts = rc.points()
    assert set(pts[0]) == {"sigma", "amplitude", "stable"}
    assert all(-1.0 - 1e-9 <= p["sigma"] <= 3.0 + 1e-9 for p in pts)
    assert rc.trivial == ()  # external forcing: a = 0 is not a steady state


def test_bad_ranges(sf1):
    with pytest.raises(ParameterError, match="increasing"):
        response_curve(sf1, (1.0, 0.0))
    with pytest.raises(ParameterError, match="0 < a_min < a_max"):
        fixed_points(sf1, 0.0, (0.0, 1.0))
    with pytest.raises(ParameterError, match="mu"):
        derive_forced("duffing-forced", 1).slow_flow({"zeta": 1})
    with pytest.raises(ParameterError, match="needs values of"):
        derive_forced("duffing-forced", 1).slow_flow({"mu": 0.1})


def test_parametric_response_has_trivial_branch():
    """Parametric Duffing: the nontrivial branch bifurcates from a = 0 at the tongue edges,
    where the trivial state's stability changes."""
    sf = derive_forced("parametric", 1).slow_flow({"mu": 0.05, "zeta": 0.05, "alpha": 1,
                                                    "h": 1})
    rc = response_curve(sf, (-1.0, 1.5), (1e-3, 3), n_points=200)
    triv = np.array([(s, st == "stable") for s, st in rc.trivial])
    edge = np.sqrt(1 / 4 - 4 * 0.05**2)
    inside = np.abs(triv[:, 0]) < edge - 1e-2
    outside = np.abs(triv[:, 0]) > edge + 1e-2
    assert not triv[inside, 1].any() and triv[outside, 1].all()
    assert rc.branches and min(b.amplitude.min() for b in rc.branches) < 0.05


@given(st.floats(-1.0, 3.0), st.floats(0.05, 1.0), st.floats(0.02, 0.3))
def test_all_fixed_points_found(s, h, z):
    """Every steady state of the first-order Duffing slow flow: the positive roots r = a^2
    of the cubic r [zeta^2 + (sigma - 3 r/8)^2] = h^2/4 (numpy.roots), none missed."""
    sf = derive_forced("duffing-forced", 1).slow_flow({"mu": 0.05, "zeta": z, "alpha": 1,
                                                        "h": h})
    r = np.roots([9 / 64, -3 * s / 4, s**2 + z**2, -h**2 / 4])
    ref = sorted(np.sqrt(x.real) for x in r if abs(x.imag) < 1e-12 and x.real > 0)
    if len(ref) > 1 and min(np.diff(ref)) < 1e-3:
        return  # a near-double root (at a fold): the count is ill-conditioned there
    got = [f.amplitude for f in fixed_points(sf, s, (1e-3, 6), n_a=300)]
    assert len(got) == len(ref) and np.allclose(got, ref, rtol=1e-9), (got, ref)


def test_vdp_locked_states_form_a_closed_curve():
    """Forced van der Pol (h = 0.4): the large-amplitude steady states form a closed curve
    (traced once, recognised modulo 2 pi in phi) whose folds are the locking boundary
    (the edges of the stable range found by bisection, numerics.locking.entrainment)."""
    from numerics.locking.entrainment import predicted_boundary

    sf = derive_forced("vdp-forced", 1).slow_flow({"mu": 0.1, "h": 0.4})
    rc = response_curve(sf, (-0.5, 0.5), (1e-3, 3), n_points=200)
    closed = [b for b in rc.branches if b.reason == "closed curve"]
    assert len(closed) == 1 and len(rc.folds) == 2
    b = closed[0]
    assert abs(b.sigma[0] - b.sigma[-1]) < 0.02 and abs(b.amplitude[0] - b.amplitude[-1]) < 0.02
    edge = predicted_boundary(sf, 1.0).sigma
    assert abs(rc.folds[1].sigma - edge) < 1e-6 and abs(rc.folds[0].sigma + edge) < 1e-6


@pytest.mark.parametrize("name, vals, sig, order", [
    ("duffing-forced", {"mu": 0.05, "zeta": 0.1, "alpha": 1, "h": 0.5}, 1.0, 2),
    ("duffing-forced", {"mu": 0.05, "zeta": 0.1, "alpha": 1, "h": 0.5}, 1.0, 3),
    ("duffing-forced", {"mu": 0.1, "zeta": 0.05, "alpha": -1, "h": 0.3}, -0.7, 2),
    ("vdp-forced", {"mu": 0.1, "h": 0.4}, 0.05, 2),
    ("parametric", {"mu": 0.05, "zeta": 0.05, "alpha": 1, "h": 1}, 0.8, 3),
])
def test_scan_finds_every_fixed_point_of_the_resultant(name, vals, sig, order):
    """The grid scan against elimination by resultants (exact rational arithmetic, every
    root of a polynomial in a): the same fixed points inside the amplitude window."""
    from kbm.slowflow.resultant import fixed_points_resultant

    sf = derive_forced(name, order).slow_flow(vals)
    exact = [f for f in fixed_points_resultant(sf, sig) if f.amplitude < 4]
    scan = fixed_points(sf, sig, (1e-3, 4))
    assert len(exact) >= 2 and len(scan) == len(exact)
    for f, g in zip(scan, exact):
        assert abs(f.amplitude - g.amplitude) < 1e-9 and f.stable == g.stable
