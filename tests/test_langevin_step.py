"""The default step of the Langevin integrator without the compiled kernels
(:func:`numerics.noise.langevin.natural_step`, :func:`numerics.noise.codegen.python_accel`).

References: the compiled module's own ``accel`` (numba; a second evaluation of the same
printed operations), which the interpreted one must equal bit for bit at every model and
state drawn (hypothesis), and the step rule written out here from its docstring (the
fastest linear period over ``per_period`` and ``(4 mu tol/w^4)^(1/3)``).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from numerics.noise import codegen, langevin
from numerics.noise.langevin import HEATING_TOLERANCE, langevin_system, natural_step

#: every built-in model at rest, at parameters with a stable origin
CASES = [
    ("vdp", {"mu": 0.3}), ("duffing", {"mu": 0.2}), ("rayleigh", {"mu": 0.1}),
    ("linear_damping", {"mu": 1.0, "zeta": 0.5}), ("linear_stiffness", {"mu": 0.1, "kappa": 2}),
    ("sedf", {"mu": 0.1, "Delta": 3, "beta": 1, "lam": 1, "Omega": 1}),
    ("cdc", {"mu": 1.0, "Delta": 3, "lam": 1, "Omega": 1}),
    ("cdc", {"mu": 0.02, "Delta": 3, "lam": 1.3, "Omega": 1, "v": 0.2}),
    ("sedf_comoving", {"mu": 0.1, "Delta": 2, "beta": 1, "lam": 1, "Omega": 1, "v": 0.1}),
]


@pytest.mark.parametrize("name,params", CASES)
@settings(max_examples=60, deadline=None)
@given(t=st.floats(0, 50), x=st.floats(-3, 3), v=st.floats(-3, 3))
def test_interpreted_accel_equals_the_compiled_one(name, params, t, x, v):
    """The interpreted acceleration is the compiled kernel's, bit for bit (the same printed
    operations; numba without fast-math; integer powers by numba's squaring: with
    CPython's ``pow`` the Duffing term ``x**3`` was one ulp off at x = 2.678)."""
    system = langevin_system(name, params, 0.05)
    p = system._p()
    fast = codegen.python_accel(system.symbolic, system.names)
    assert fast(t, x, v, p) == system.kernels.accel(t, x, v, p)


@pytest.mark.parametrize("name,params", CASES)
def test_natural_step_is_the_rule_on_the_compiled_kernel(name, params):
    """The step equals the rule evaluated on the compiled ``accel`` (the value before the
    kernels were left out), bit for bit."""
    system = langevin_system(name, params, 0.05)
    p, k, eps = system._p(), system.kernels, 1e-6
    stiff = -(k.accel(0.0, eps, 0.0, p) - k.accel(0.0, -eps, 0.0, p)) / (2 * eps)
    w = max(system.omega0, math.sqrt(max(stiff, 0.0)))
    h = 2 * math.pi / w / 40
    mu = abs(system.bound.mu or 0.0)
    if mu > 0:
        h = min(h, (4 * mu * HEATING_TOLERANCE / w**4) ** (1 / 3))
    assert natural_step(system, per_period=40) == h


def test_escape_without_simulation_loads_no_kernels(monkeypatch):
    """``kbm escape --no-simulation`` fills ``dt`` without compiling or loading the
    simulation kernels (the step of the rule, as with them)."""
    from numerics.escape.report import escape_report

    def refuse(*a, **k):
        raise AssertionError("the compiled kernels were loaded")

    params = {"mu": 1, "Delta": 3, "D": 0.35}
    expected = natural_step(langevin_system("cdc", {"mu": 1, "Delta": 3, "lam": 1,
                                                    "Omega": 1}, 0.35), per_period=40)
    monkeypatch.setattr(langevin, "_compiled", refuse)
    monkeypatch.setattr(codegen, "_compiled", refuse)
    out = escape_report("cdc", params, simulate=False)
    assert out["dt"] == expected
    assert np.isfinite(out["rate_averaged"])
