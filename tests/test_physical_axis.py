"""The one physical-axis binding (:func:`kbm.parameters.names.physical_axis`) of ``kbm lock`` and
``kbm diagram``, against the closed forms of the built-in maps (paper eqs. 3 and 12):
``delta = Delta/mu`` (inverse ``Delta = mu delta``) and ``k = 2 pi/lam`` (inverse
``lam = 2 pi/k``), and against the elementary inverses of maps that sympy gives no single
closed form for (Brent's method on the bracket): ``q = X^2`` on ``X > 0`` (``X = sqrt q``)
and ``q = X + X^5`` (a quintic: checked by the forward map).

Properties: the mapped range's ends are the closed form's values at the ends; the ends map
back exactly; ``forward(inverse(y)) = y`` to rounding; an error maps by the inverse's
derivative; a map with a pole or a turning point
in the range is flagged not monotone (the callers refuse it).
"""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from kbm.model.builtins import get_model
from kbm.parameters.names import physical_axis

PHYSICAL = dict(get_model("sedf").physical)  # {delta: Delta/mu, k: 2 pi/lam}
MUS = st.sampled_from(["0.01", "0.05", "0.08", "0.1", "0.3", "1"])


def _interval(lo_min: float, lo_max: float):
    return st.tuples(st.floats(lo_min, lo_max), st.floats(1e-3, 10.0)).map(
        lambda t: (t[0], t[0] + t[1]))


@settings(max_examples=100, deadline=None)
@given(mu=MUS, ends=_interval(-5.0, 5.0), w=st.floats(0.0, 1.0))
def test_delta_axis_against_closed_form(mu, ends, w):
    """``--vary Delta=lo:hi`` is ``delta`` over ``[lo/mu, hi/mu]``; a value of delta maps
    back to ``mu delta`` (the closed form, to rounding), and ``forward(inverse(y)) = y``."""
    lo, hi = ends
    m = float(mu)
    ax = physical_axis(PHYSICAL, "Delta", lo, hi, {"mu": mu})
    assert ax.name == "delta" and ax.monotone and ax.rule == "delta = Delta/mu"
    assert ax.span[0] == pytest.approx(lo / m, rel=1e-15, abs=1e-300)
    assert ax.span[1] == pytest.approx(hi / m, rel=1e-15, abs=1e-300)
    assert (ax.to_user(ax.span[0]), ax.to_user(ax.span[1])) == (lo, hi)
    y = ax.span[0] + w * (ax.span[1] - ax.span[0])
    scale = max(abs(ax.span[0]), abs(ax.span[1]))
    assert ax.to_user(y) == pytest.approx(m * y, rel=1e-15, abs=1e-15 * m * scale)
    assert ax.forward(ax.inverse(y)) == pytest.approx(y, rel=4e-16, abs=4e-16 * scale)
    assert ax.error(y, 1e-8) == pytest.approx(m * 1e-8, rel=1e-15)  # |d Delta/d delta| = mu


@settings(max_examples=30, deadline=None)  # 100 took 7 s of the default run
@given(ends=_interval(0.05, 5.0), w=st.floats(0.0, 1.0))
def test_lam_axis_against_closed_form(ends, w):
    """``--vary lam=lo:hi`` (lo > 0) is ``k`` over ``[2 pi/hi, 2 pi/lo]`` (increasing: the
    map decreases); ``lam = 2 pi/k`` back, the ends exactly."""
    lo, hi = ends
    ax = physical_axis(PHYSICAL, "lam", lo, hi, {})
    assert ax.name == "k" and ax.monotone
    assert ax.span == (pytest.approx(2 * math.pi / hi, rel=1e-15),
                       pytest.approx(2 * math.pi / lo, rel=1e-15))
    assert (ax.to_user(ax.span[1]), ax.to_user(ax.span[0])) == (lo, hi)
    y = ax.span[0] + w * (ax.span[1] - ax.span[0])
    assert ax.to_user(y) == pytest.approx(2 * math.pi / y, rel=1e-15)
    assert ax.forward(ax.inverse(y)) == pytest.approx(y, rel=1e-15)
    lam = 2 * math.pi / y  # |d lam/dk| = lam^2/(2 pi)
    assert ax.error(y, 1e-8) == pytest.approx(lam * lam / (2 * math.pi) * 1e-8, rel=1e-14)


@settings(max_examples=20, deadline=None)  # 50 took 4 s of the default run
@given(ends=_interval(0.1, 3.0), w=st.floats(0.0, 1.0))
def test_bracketed_inverse_where_sympy_gives_no_single_closed_form(ends, w):
    """``q = X^2`` (two roots, ``+-sqrt q``) and ``q = X + X^5`` (no closed form):
    the inverse is the root in ``[lo, hi]`` by Brent's method, ``sqrt q`` to 1e-14, and the
    forward map of it the value to 1e-14."""
    lo, hi = ends
    sq = physical_axis({"q": "X**2"}, "X", lo, hi, {})
    y = sq.span[0] + w * (sq.span[1] - sq.span[0])
    assert sq.monotone and sq.span == (pytest.approx(lo * lo, rel=1e-15),
                                       pytest.approx(hi * hi, rel=1e-15))
    assert sq.to_user(y) == pytest.approx(math.sqrt(y), rel=1e-14)
    if sq.span[0] + 1e-6 < y < sq.span[1] - 1e-6:  # the difference quotient of sqrt
        assert sq.error(y, 1e-8) == pytest.approx(1e-8 / (2 * math.sqrt(y)), rel=1e-5)
    qu = physical_axis({"q": "X + X**5"}, "X", lo, hi, {})
    y = qu.span[0] + w * (qu.span[1] - qu.span[0])
    x = qu.to_user(y)
    assert lo <= x <= hi and x + x**5 == pytest.approx(y, rel=1e-14)


def test_bracketed_inverse_at_the_ends_and_outside():
    """``y`` at an end of the span but past it by a rounding (``lo + 1.0 (hi - lo)``, which
    hypothesis found: Brent's bracket had one sign) maps to that end; a value outside the
    span is refused with the range."""
    from kbm.errors import ParameterError

    lo, hi = 1.4845755059342232, 3.484575505934223
    qu = physical_axis({"q": "X + X**5"}, "X", lo, hi, {})
    y = qu.span[0] + 1.0 * (qu.span[1] - qu.span[0])
    assert qu.to_user(y) == pytest.approx(hi, rel=1e-15)
    assert qu.to_user(qu.span[0]) == pytest.approx(lo, rel=1e-15)
    with pytest.raises(ParameterError, match="outside"):
        qu.to_user(1.01 * qu.span[1])


def test_not_monotone_and_identity():
    """A pole (``2 pi/lam`` over lam = -1:1) or a turning point (``X^2`` over -1:1) in the
    range is flagged; a name no map holds is the identity; a missing input is refused."""
    from kbm.errors import ParameterError

    assert not physical_axis(PHYSICAL, "lam", -1.0, 1.0, {}).monotone
    assert not physical_axis(PHYSICAL, "lam", -1.0, 0.3, {}).monotone
    assert not physical_axis({"q": "X**2"}, "X", -1.0, 1.0, {}).monotone
    cube = physical_axis({"q": "X**3"}, "X", -2.0, 3.0, {})  # three roots: Brent, real
    assert cube.slope is None and cube.to_user(-1.0) == pytest.approx(-1.0, rel=1e-14)
    assert cube.to_user(8.0) == pytest.approx(2.0, rel=1e-14)
    beta = physical_axis(PHYSICAL, "beta", 0.5, 1.5, {})
    assert not beta.mapped and beta.span == (0.5, 1.5) and beta.to_user(0.75) == 0.75
    with pytest.raises(ParameterError, match=r"-p mu=VALUE"):
        physical_axis(PHYSICAL, "Delta", 0.1, 1.0, {})
