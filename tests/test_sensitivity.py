"""The parameter sensitivity integrated with the state (numerics.flow.sensitivity), which the
continuation of cycles uses for ``dR/dp`` in place of a central difference.

References, none produced by the code under test:

- the linear oscillator ``x'' + c x' + x = 0`` (``F = -c xdot``, mu = 1): the closed form
  ``x(t; c)`` from ``x(0) = x0, x'(0) = 0``, differentiated in ``c`` by sympy;
- the SEDF (paper eq. 3, mu = 0.1, beta = 1, lam = 1) in the physical ``Delta`` (the flow
  moves ``delta = Delta/mu``): central differences of the plain flow in ``Delta``;
- the branch of cycles in ``Delta``: each point's period against the cycle shot from
  scratch at that ``Delta`` (:func:`numerics.limit_cycle`).
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings, strategies as st

from kbm import custom_model
from numerics.flow import CompiledLine, Method, extended_state, flow
from numerics.flow.sensitivity import flow_with_sensitivity, sensitivity_flow, sensitivity_state

pytest.importorskip("numba")

LINEAR = custom_model("-c*xdot", name="linear-damping-c")


def _closed_form_rate(c: float, x0: float, t_end: float) -> tuple[float, float]:
    """``(dx/dc, dx'/dc)`` at ``t_end`` from the closed form of the underdamped solution."""
    C, t = sp.symbols("C t", positive=True)
    wd = sp.sqrt(1 - C**2 / 4)
    x = x0 * sp.exp(-C * t / 2) * (sp.cos(wd * t) + C / (2 * wd) * sp.sin(wd * t))
    dx = sp.diff(x, C)
    dv = sp.diff(sp.diff(x, t), C)
    at = {C: sp.Rational(repr(c)), t: sp.Rational(repr(t_end))}
    return float(dx.subs(at).evalf(30)), float(dv.subs(at).evalf(30))


@settings(max_examples=15, deadline=None)
@given(c=st.floats(0.05, 1.5), x0=st.floats(0.2, 3.0), t_end=st.floats(0.5, 12.0))
def test_linear_damping_rate_equals_the_closed_form(c, x0, t_end):
    line = CompiledLine(LINEAR, {"mu": 1}, "c", c)
    cm = line(c)
    assert sensitivity_flow(cm.template) is not None
    y = flow_with_sensitivity(cm, line.rates(c), sensitivity_state(x0), t_end, 1, 1e-12,
                              1e-12)[-1]
    dx, dv = _closed_form_rate(c, x0, t_end)
    assert y[7] == pytest.approx(dx, rel=1e-8, abs=1e-10 * x0)
    assert y[8] == pytest.approx(dv, rel=1e-8, abs=1e-10 * x0)


@pytest.mark.parametrize("Delta", [0.7, 2.5, 3.2])
def test_sedf_rate_in_the_physical_delta_equals_central_differences(Delta):
    """Through ``delta = Delta/mu``: the rate ``d delta/d Delta = 1/mu`` enters the
    inhomogeneity; the difference quotient of the plain extended flow is the reference."""
    params = {"mu": 0.1, "beta": 1, "lam": 1}
    line = CompiledLine("sedf", params, "Delta", Delta)
    x0, T = 1.9, 7.3
    y = flow_with_sensitivity(line(Delta), line.rates(Delta), sensitivity_state(x0), T, 1,
                              1e-12, 1e-12)[-1]
    h = 1e-5
    plus = flow(line(Delta + h), extended_state(x0), T, 1, Method.COMPILED, 1e-12, 1e-12)[-1]
    minus = flow(line(Delta - h), extended_state(x0), T, 1, Method.COMPILED, 1e-12, 1e-12)[-1]
    fd = (plus[:2] - minus[:2]) / (2 * h)
    assert np.allclose(y[7:9], fd, rtol=1e-6, atol=1e-7 * np.max(np.abs(fd)))
    # the first seven states are the plain extended flow's (at the integrator's tolerance)
    plain = flow(line(Delta), extended_state(x0), T, 1, Method.COMPILED, 1e-12, 1e-12)[-1]
    assert np.allclose(y[:7], plain[:7], rtol=1e-9, atol=1e-10)


def test_rates_of_the_scaled_names():
    """``d p_k/d vary`` in the template's order: ``delta = Delta/mu`` moves at ``1/mu`` in
    ``Delta`` and at ``-Delta/mu^2`` in ``mu``; a stage velocity has none."""
    a = CompiledLine("sedf", {"mu": 0.1, "beta": 1, "lam": 1}, "Delta", 1.0)
    names = a.template.names
    r = dict(zip(names, a.rates(2.0)))
    assert r["delta"] == pytest.approx(10.0) and r["mu"] == 0 and r["beta"] == 0
    b = CompiledLine("sedf", {"Delta": 2, "beta": 1, "lam": 1}, "mu", 0.1)
    r = dict(zip(names, b.rates(0.1)))
    assert r["mu"] == 1.0 and r["delta"] == pytest.approx(-2 / 0.1**2)
    assert CompiledLine("sedf", {"mu": 0.1, "beta": 1, "lam": 1, "Delta": 1}, "v",
                        0.01).rates(0.02) is None


def test_branch_points_are_the_cycles_shot_from_scratch():
    """The continuation with the sensitivity (one integration per Newton iteration) and
    the corrector's acceptance at the correction it computes: the SEDF branch in Delta
    (rtol 1e-10) agrees with limit_cycle shot at rtol 1e-12 at every fifth point to 1e-10
    (accepting corrections ten times larger gave 1.5e-9)."""
    from numerics import limit_cycle
    from numerics.cycles.continuation import continue_cycles

    params = {"mu": 0.1, "beta": 1, "lam": 1}
    br = continue_cycles("sedf", {**params, "Delta": 0.5}, "Delta", (0.5, 2.5), max_points=60)
    assert len(br.points) > 10
    # about three integrations per point (a central difference took two more per iteration)
    assert br.evaluations < 5 * len(br.points)
    for p in br.points[::5]:
        c = limit_cycle("sedf", {**params, "Delta": p.parameter}, rtol=1e-12, atol=1e-12)
        assert p.period == pytest.approx(c.period, rel=1e-10)


def test_acceleration_jacobian_of_van_der_pol_and_its_refusal():
    """The one Jacobian of the variational equations (template, nine-state flow, adjoint
    Floquet, fold system): Van der Pol ``x'' = -x + mu (1 - x^2) x'`` has, by hand,
    ``d/dx = -1 - 2 mu x x'`` and ``d/dx' = mu (1 - x^2)``; ``sign(x')`` has none."""
    from kbm.errors import ModelError
    from kbm.symbols import mu, x, xdot
    from numerics.flow.template import acceleration_jacobian

    acc = -x + mu * (1 - x**2) * xdot
    jx, jv = acceleration_jacobian(acc, "vdp")
    assert sp.expand(jx - (-1 - 2 * mu * x * xdot)) == 0
    assert sp.expand(jv - mu * (1 - x**2)) == 0
    with pytest.raises(ModelError, match="'coulomb'.*x'.*tanh"):
        acceleration_jacobian(-x - mu * sp.sign(xdot), "coulomb")
