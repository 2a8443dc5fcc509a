"""One model type (issues 23, 35): every model is an instance of
kbm.model.coupled.CoupledOscillators with the number of degrees of freedom and the forcing as
properties (the one-degree-of-freedom and forced built-ins are its cases N = 1), and every
instance binds its values through kbm.parameters.bound.bind.

References: the definitions themselves (N = len(F), forced = a forcing angle), the
general form of a case N = 1 written out by hand (x -> x1), and the coupled numerics' own
reading of the values (numerics.flow.coupled_flow.bind_coupled), whose floats the bound form
must give.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from kbm.parameters.bound import bind
from kbm.model.coupled_builtins import COUPLED_MODELS, get_coupled_model
from kbm.model.coupled import CoupledOscillators
from kbm.errors import ModelError, ParameterError
from kbm.model.forced_builtins import FORCED_MODELS, get_forced_model
from kbm.model.builtins import MODELS, custom_model, get_model
from kbm.symbols import x, xdot

X1, V1 = sp.symbols("x1 xdot1")
from numerics.flow.coupled_flow import bind_coupled


@pytest.mark.parametrize("name", sorted(MODELS))
def test_one_degree_of_freedom_members(name):
    m = get_model(name)
    assert isinstance(m, CoupledOscillators) and (m.dof, m.forced) == (1, False)
    assert isinstance(m, CoupledOscillators) and get_coupled_model(name) == m
    assert m.rhs == (m.F.subs({x: X1, xdot: V1}, simultaneous=True),)


@pytest.mark.parametrize("name", sorted(FORCED_MODELS))
def test_forced_members(name):
    m = get_forced_model(name)
    assert isinstance(m, CoupledOscillators) and (m.dof, m.forced) == (1, True)
    assert m.hards == ((m.hard,) if m.hard != 0 else ())  # the general names of its data
    assert m.nu0 == m.omega0 * m.resonance.ratio and m.nu_detuning == "sigma"


@pytest.mark.parametrize("name", sorted(COUPLED_MODELS))
def test_coupled_members(name):
    m = get_coupled_model(name)
    assert isinstance(m, CoupledOscillators)
    assert m.dof == len(m.F) and m.forced == (m.nu0 is not None)


VALUES = {"coupled-vdp": {"mu": 0.1, "c": 0.3, "sigma": 0.5},
          "duffing-1-3": {"mu": 0.02, "sigma": 1, "h": 2},
          "quadratic-1-2": {"mu": 0.02, "zeta1": 0.5, "zeta2": 0.5, "alpha1": 1, "alpha2": 1,
                            "sigma1": 0, "sigma2": 1, "h": 2},
          "sedf-dimer": {"mu": 0.1, "Delta": 1.5},
          "sedf-chain": {"mu": 0.1, "Delta": 3, "kappa": 0.5}}


@pytest.mark.parametrize("name", sorted(VALUES))
def test_the_bound_form_of_a_coupled_member(name):
    b = bind(name, VALUES[name])
    assert b.model == get_coupled_model(name)
    _, floats = bind_coupled(name, VALUES[name])
    assert {k: float(v) for k, v in b.values.items()} == floats
    assert b.missing() == []


def test_the_bound_form_of_the_n1_case_equals_the_oscillators():
    for name, vals in (("vdp", {"mu": "0.1"}), ("duffing", {"mu": 0.2}),
                       ("rayleigh", {"mu": 0.3})):
        one = bind(name, vals)
        _, floats = bind_coupled(get_model(name), vals)
        assert {k: float(v) for k, v in one.values.items()} == floats


def test_bad_values_of_a_coupled_member():
    with pytest.raises(ParameterError, match="unknown parameter .q. for coupled-vdp.*its parameters are mu, c, sigma"):
        bind("coupled-vdp", {"mu": 0.1, "q": 1})
    with pytest.raises(ParameterError, match="either delta or Delta"):
        bind("sedf-dimer", {"mu": 0.1, "Delta": 1.5, "delta": 15})


def test_derive_takes_every_member():
    """kbm.derive of a coupled member is the general engine's expansion; of an oscillator,
    the one-degree-of-freedom engine's (unchanged)."""
    import kbm
    from kbm.expansion.coupled import derive_coupled

    a = kbm.derive("coupled-vdp", 2)
    b = derive_coupled("coupled-vdp", 2)
    assert a.A == b.A and a.B == b.B and a.gammas == b.gammas
    assert kbm.derive(get_coupled_model("duffing-1-3"), 1).model.dof == 2
    assert type(kbm.derive("vdp", 2)).__name__ == "KBMResult"


# -- N = 1: one type, no conversion -----------------------------------------------------
@settings(max_examples=25, deadline=None)
@given(st.lists(st.tuples(st.integers(-3, 3), st.integers(0, 3), st.integers(0, 2)),
                min_size=1, max_size=4))
def test_a_case_equals_the_system_written_in_the_general_form(terms):
    """A random polynomial F as the case N = 1 (custom_model) and as the general type in
    x1, xdot1 by hand: the same right-hand side, equations of motion and parameters."""
    F = sum((c * x**i * xdot**j for c, i, j in terms), sp.Integer(0))
    if not F.free_symbols:  # a constant F is no model (custom_model refuses it)
        return
    m = custom_model(F)
    general = CoupledOscillators("g", (F.subs({x: X1, xdot: V1}, simultaneous=True),), (1,))
    assert m.rhs == general.rhs and m.accelerations() == general.accelerations()
    assert m.parameters == general.parameters and m.F == F


def test_every_engine_takes_either_form():
    """A cycle of one degree of freedom by either shooting (two codes: numerics.cycles and
    numerics.shooting.coupled_orbit) of the one instance: the paper's SEDF (eq. 3) at rest."""
    from numerics import limit_cycle
    from numerics.shooting.coupled_orbit import coupled_cycle

    sedf = get_model("sedf")
    p = {"mu": 0.1, "Delta": 1.5, "beta": 1, "lam": 1}
    one = limit_cycle(sedf, p)
    assert abs(coupled_cycle(sedf, p).period - one.period) < 1e-9  # the other shooting
    with pytest.raises(ModelError, match="2 degrees of freedom.*coupled_cycle"):
        limit_cycle(get_coupled_model("coupled-vdp"), {"mu": 0.1})


def test_the_forced_engine_takes_either_form():
    from numerics.flow.forced_system import ForcedSystem

    m = get_forced_model("duffing-forced")
    vals = {"mu": 0.1, "alpha": 1, "h": 2, "zeta": 0.5}
    one = ForcedSystem(m, vals)
    assert one.model is m  # no conversion
    assert isinstance(one.flow([0.2, -0.1], 0.3), np.ndarray)
    with pytest.raises(ModelError, match="2 degrees of freedom"):
        ForcedSystem(get_coupled_model("duffing-1-3"), {"mu": 0.1})
