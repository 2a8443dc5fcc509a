"""``Oscillator.dissipative_force``: the part of ``mu F`` that vanishes at ``x' = 0``, for
every built-in, against the damping typed here from its equation of motion.

``x'' + Omega^2 x = mu F + drive``: the dissipative force is what multiplies ``x'`` in
``mu F``:

* van der Pol ``x'' - mu (1 - x^2) x' + x = 0`` (van der Pol 1926): ``mu (1 - x^2) x'``;
* Rayleigh ``x'' - mu (1 - x'^2/3) x' + x = 0`` (Rayleigh 1883): ``mu (1 - x'^2/3) x'``;
* linear damping ``x'' + 2 mu zeta x' + x = 0``: ``-2 mu zeta x'``;
* Duffing and the stiffness perturbation: none (conservative);
* the SEDF, D'Acunto's eq. (3): ``-mu (beta x^2 - 1) x'``;
* the CDC, eq. (12): ``-mu x'``;
* the SEDF with the excitation attached to the stage, pulled at ``v``:
  ``-mu (beta (x - v t)^2 - 1) x'`` (at ``v = 0`` the SEDF's).
"""

from __future__ import annotations

import pytest
import sympy as sp

from kbm.model.builtins import get_model, model_names
from kbm.symbols import mu, t, x, xdot

beta, zeta, v = sp.symbols("beta zeta v")

BY_HAND = {
    "vdp": mu * (1 - x**2) * xdot,
    "rayleigh": mu * (1 - xdot**2 / 3) * xdot,
    "linear_damping": -2 * mu * zeta * xdot,
    "duffing": sp.Integer(0),
    "linear_stiffness": sp.Integer(0),
    "sedf": -mu * (beta * x**2 - 1) * xdot,
    "cdc": -mu * xdot,
    "sedf_comoving": -mu * (beta * x**2 - 1) * xdot,
}


def test_every_built_in_is_covered():
    assert set(BY_HAND) == set(model_names())


@pytest.mark.parametrize("name", sorted(BY_HAND))
def test_dissipative_force_is_the_damping_of_the_equation_of_motion(name):
    """The built-in's damping as typed from its equation (module docstring)."""
    assert sp.expand(get_model(name).dissipative_force() - BY_HAND[name]) == 0


@pytest.mark.parametrize("name, pulled", [
    ("sedf", -mu * (beta * x**2 - 1) * xdot),            # eq. (3): excitation at x
    ("cdc", -mu * xdot),                                 # eq. (12)
    ("sedf_comoving", -mu * (beta * (x - v * t)**2 - 1) * xdot),
])
def test_pulled_sliders_keep_their_damping_and_the_comoving_one_moves_with_the_stage(name,
                                                                                    pulled):
    """Pulled at ``v`` (the spring ``Omega^2 (x - v t)``, a drive, not a damping): eq. (3)
    and eq. (12) keep their damping; the comoving SEDF's is evaluated at ``x - v t``."""
    m = get_model(name).with_stage_velocity(v)
    assert sp.expand(m.dissipative_force() - pulled) == 0
    assert m.dissipative_force().subs(xdot, 0) == 0


@pytest.mark.parametrize("name", ["sedf", "sedf_comoving", "vdp"])
def test_dissipation_parts_split_minus_dissipative_force_times_velocity(name):
    """Paper eqs. (10)-(11): ``-D x' = beta Gamma_+ - Gamma_-`` with ``D`` the damping
    typed by hand, each part of one sign."""
    m = get_model(name).with_stage_velocity(v) if name != "vdp" else get_model(name)
    hand = BY_HAND[name].subs(x, x - v * t) if name == "sedf_comoving" else BY_HAND[name]
    plus, minus, factor = m.dissipation_parts()
    assert sp.expand(factor * plus - minus + hand * xdot) == 0
    assert factor == (1 if name == "vdp" else beta)
