"""The compiled stepper's crossing of a section ``x = xsec`` (``to_section`` of
``numerics/flow/_dop853_stepper.py``, forward and backward in time), against independent
references:

- the damped linear oscillator ``x'' + 2 zeta x' + x = 0`` in closed form,
  ``x(t) = e^(-zeta t) (cos w t + (zeta/w) sin w t)``, ``x'(t) = -(e^(-zeta t)/w) sin w t``,
  ``w = sqrt(1 - zeta^2)`` from ``(1, 0)`` (backward: the same with ``t -> -t``), the
  crossing time a root of the closed form (Brent); property-based over the section and
  the damping;
- the SEDF (paper eq. 3) written here, ``x'' + mu (beta x^2 - 1) x' + Delta sin(2 pi x) +
  x = 0``: the stable manifold of the saddle near ``-2.61`` followed backward to the
  section of :func:`numerics.bifurcation.connections.section_gap`, against scipy's
  ``solve_ivp`` (DOP853 with event location) at rtol 1e-13.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from kbm import custom_model
from numerics.flow import compile_model, jit_available
from numerics.flow.template import template_flow

pytestmark = pytest.mark.skipif(not jit_available(), reason="numba not installed")

#: x'' + x = mu F with mu = 1, F = -2 zeta x'
DAMPED = custom_model("-2*zeta*xdot")


def _damped_closed_form(zeta: float, sign: float, xsec: float):
    """``(t, x')`` of the first crossing of ``x = xsec`` from ``(1, 0)``, forward
    (``sign = 1``) or backward (``-1``) in time, from the closed form."""
    w = math.sqrt(1 - zeta * zeta)

    def x(t):
        s = sign * t
        return math.exp(-zeta * s) * (math.cos(w * s) + zeta / w * math.sin(w * s))

    def v(t):
        s = sign * t
        return -math.exp(-zeta * s) / w * math.sin(w * s)
    # x falls monotonically from 1 while w t < pi, either way in time (x' = -(e^(-zeta s)/w)
    # sin w s has the sign of -s there)
    t_hi = math.pi / w
    grid = np.linspace(0.0, t_hi, 2001)
    vals = [x(t) - xsec for t in grid]
    k = next(i for i in range(1, len(grid)) if vals[i - 1] * vals[i] <= 0)
    t = brentq(lambda s: x(s) - xsec, grid[k - 1], grid[k], xtol=1e-15, rtol=1e-15)
    return t, v(t)


@settings(max_examples=25)
@given(zeta=st.floats(0.0, 0.3), xsec=st.floats(-0.2, 0.9),
       sign=st.sampled_from([1.0, -1.0]))
def test_section_crossing_of_the_damped_oscillator_equals_the_closed_form(zeta, xsec, sign):
    """The first crossing of ``x = xsec`` from ``(1, 0)``: the time and ``x'`` equal the
    closed form of the damped linear oscillator to 1e-11 (rtol 1e-12)."""
    cm = compile_model(DAMPED, {"mu": 1, "zeta": zeta})
    fl = template_flow(cm.template)
    x, v, t, status = fl.to_section([1.0, 0.0], sign, xsec, 50.0, cm.pvec, 1e-12, 1e-13)
    t_ref, v_ref = _damped_closed_form(zeta, sign, xsec)
    assert status == 0
    assert abs(x - xsec) <= 1e-13
    assert abs(t - t_ref) <= 1e-11 and abs(v - v_ref) <= 1e-11


def test_no_crossing_within_t_max_is_status_1():
    """The oscillator from ``(1, 0)`` stays within ``|x| <= 1``: no crossing of ``x = 2``."""
    cm = compile_model(DAMPED, {"mu": 1, "zeta": 0.1})
    fl = template_flow(cm.template)
    assert fl.to_section([1.0, 0.0], 1.0, 2.0, 20.0, cm.pvec, 1e-12, 1e-13)[3] == 1


def _sedf_rhs(delta, beta, mu, sign):
    return lambda t, y: [sign * y[1], sign * (-mu * (beta * y[0] ** 2 - 1) * y[1]
                                               - delta * math.sin(2 * math.pi * y[0]) - y[0])]


@pytest.mark.parametrize("delta, beta", [(4.0, 0.5), (3.2, 1.0), (5.0, 0.8)])
def test_sedf_stable_manifold_backward_to_the_section_against_scipy(delta, beta):
    """The stable manifold of the saddle near ``-2.61`` (arriving from the right, started
    ``1e-7`` along its eigenvector) followed backward to ``x = x_t + 0.05`` (the section of
    :func:`numerics.bifurcation.connections.section_gap`): ``x'`` there equals scipy's event
    location on the SEDF written here (rtol 1e-13) to 1e-11."""
    mu = 0.1
    xt = brentq(lambda s: s + delta * math.sin(2 * math.pi * s), -2.71, -2.51, xtol=1e-15)
    fx = -1 - 2 * math.pi * delta * math.cos(2 * math.pi * xt)
    fv = -mu * (beta * xt ** 2 - 1)
    ls = (fv - math.sqrt(fv ** 2 + 4 * fx)) / 2
    ys = [xt + 1e-7, 1e-7 * ls]
    xsec = xt + 0.05

    def event(t, y):
        return y[0] - xsec
    event.terminal = True
    ref = solve_ivp(_sedf_rhs(delta, beta, mu, -1), (0, 100), ys, method="DOP853",
                    rtol=1e-13, atol=1e-15, events=event)
    cm = compile_model("sedf", {"mu": mu, "lam": 1, "Delta": delta, "beta": beta})
    fl = template_flow(cm.template)
    x, v, t, status = fl.to_section(ys, -1.0, xsec, 200.0, cm.pvec, 1e-12, 1e-13)
    assert status == 0 and abs(x - xsec) <= 1e-13
    assert abs(v - ref.y_events[0][0][1]) <= 1e-11
    # the time from the start, where |x'| ~ 1e-7, moves by ~1e-8 with the absolute
    # tolerance (7.5e-9 from atol 1e-13 to 1e-17 at (4, 0.5)); the state does not
    assert abs(t - ref.t_events[0][0]) <= 3e-8
