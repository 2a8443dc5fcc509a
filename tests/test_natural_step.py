"""The default time step without the compiled kernels (numerics/noise/langevin.py,
``natural_step``; issue 36: ``kbm escape --no-simulation`` loaded numba's cache, about
0.8 s, for one finite difference of the acceleration).

Checks:

- the CDC's step is the closed form of its docstring, ``min(2 pi/(w P), (4 mu tol/w^4)^(1/3))``
  with ``w^2 = Omega^2 + 2 pi Delta/lam`` (the curvature of ``Omega^2 x^2/2 - (Delta
  lam/2 pi) cos(2 pi x/lam)`` at the bottom), at low and high friction;
- the uncompiled acceleration (:func:`numerics.noise.codegen.python_accel`) gives the
  compiled kernel's values at the finite difference's points, so the step is the one the
  simulations use (every built-in model);
- computing it imports no numba (a fresh interpreter).
"""

from __future__ import annotations

import math
import subprocess
import sys

import pytest

from numerics.noise.codegen import python_accel
from numerics.noise.langevin import HEATING_TOLERANCE, langevin_system, natural_step

CDC = {"Delta": 3, "lam": 1, "Omega": 1}


@pytest.mark.parametrize("mu, per_period", [(0.01, 50), (1.0, 40), (5.0, 40)])
def test_cdc_step_is_the_closed_form(mu, per_period):
    """The heating rule below mu ~ 0.1, the period rule above (docstring of natural_step)."""
    w = math.sqrt(1 + 2 * math.pi * 3)
    expected = min(2 * math.pi / w / per_period, (4 * mu * HEATING_TOLERANCE / w**4) ** (1 / 3))
    got = natural_step(langevin_system("cdc", {**CDC, "mu": mu}, 0.35 * mu), per_period=per_period)
    assert got == pytest.approx(expected, rel=1e-8)


@pytest.mark.parametrize("model, params", [
    ("cdc", CDC), ("sedf", {**CDC, "beta": 1}), ("sedf_comoving", {**CDC, "beta": 1}),
    ("vdp", {}), ("duffing", {}), ("linear_stiffness", {"kappa": 0.7}),
    ("linear_damping", {"zeta": 0.3})])
def test_python_accel_is_the_compiled_one_at_the_difference_points(model, params):
    system = langevin_system(model, {**params, "mu": 0.3}, 0.1)
    accel, p = python_accel(system.symbolic, system.names), system._p()
    for x in (1e-6, -1e-6, 0.0, 0.4):
        assert accel(0.0, x, 0.0, p) == system.kernels.accel(0.0, x, 0.0, p)


def test_natural_step_imports_no_numba():
    code = ("import sys\nfrom numerics.noise.langevin import langevin_system, natural_step\n"
            "natural_step(langevin_system('cdc', {'Delta': 3, 'lam': 1, 'mu': 1}, 0.35))\n"
            "print('numba' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    assert out.stdout.strip() == "False"
