"""Irrational constants and shifted potentials in the exact coupled expansion
(kbm.model.constants, issue 23: a Frenkel-Kontorova chain of self-excited sliders).

- A constant that is not rational (sqrt(2), pi, cos(phi)) is an independent generator of
  the ring: the expansion with it equals the expansion with a symbol in its place, the
  value substituted afterwards (exact, order 2).
- A slider on a shifted potential, sin(k x_i + phi_i), equals the jets (kbm.backend.jets:
  F's Taylor series on an FFT grid, no Bessel function) at random points, and its
  correction u_{i,1} the FFT quadrature of tests/_coupled_references.py.
- A forcing with a phase, h cos(theta + phi), equals its two quadratures.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from _coupled_references import cut_sums, rates_function, u_by_fft
from hypothesis import given, settings
from hypothesis import strategies as st

from kbm.model.coupled_builtins import coupled_custom
from kbm.expansion.coupled import derive_coupled
from kbm.backend.jets import jet_expansion
from kbm.errors import ModelError


def test_irrational_constants_equal_the_symbols_put_in_afterwards():
    """Van der Pol and Duffing terms with the coefficients sqrt(2), pi, cos(phi),
    in 1:3 internal resonance, at order 2."""
    c, p, q = sp.symbols("c p q")
    with_symbols = coupled_custom(["-c*x1**3 + p*xdot1*(1 - x1**2) + q*x1**2*x2",
                                   "-x2**3 + q*x1**3"], "1,3").with_internal(["1:3"])
    with_values = coupled_custom(["-sqrt(2)*x1**3 + pi*xdot1*(1 - x1**2) + cos(phi)*x1**2*x2",
                                  "-x2**3 + cos(phi)*x1**3"], "1,3").with_internal(["1:3"])
    put = {c: sp.sqrt(2), p: sp.pi, q: sp.cos(sp.Symbol("phi"))}
    r1, r2 = derive_coupled(with_symbols, 2), derive_coupled(with_values, 2)
    for rows1, rows2 in ((r1.A, r2.A), (r1.B, r2.B), (r1.u, r2.u)):
        for row1, row2 in zip(rows1, rows2):
            for e1, e2 in zip(row1[1:], row2[1:]):
                assert sp.expand(e1.xreplace(put) - e2) == 0


def test_floats_stay_refused():
    m = coupled_custom(["-0.1*x1**3", "-x2**3"], "1,3").with_internal(["1:3"])
    with pytest.raises(ModelError, match="exact numbers.*0.1 as 1/10"):
        derive_coupled(m, 1)


FK = coupled_custom(
    ["(1 - beta*x1**2)*xdot1 - delta*sin(k*x1 + phi) - kappa*(x1 - x2)",
     "(1 - beta*x2**2)*xdot2 - delta*sin(k*x2 + 2*phi) - kappa*(x2 - x1) "
     "- kappa*(x2 - x3)",
     "(1 - beta*x3**2)*xdot3 - delta*cos(k*x3 - phi) - kappa*(x3 - x2)"],
    "1,1,1").with_internal(["1:1@1,2", "1:1@2,3"])
FK_VALUES = {"beta": 0.8, "delta": 1.1, "k": 2.6, "phi": 0.9, "kappa": 0.4}
FK_RATES = rates_function(derive_coupled(FK, 1), FK_VALUES)


@settings(max_examples=4, deadline=None)
@given(a=st.lists(st.floats(0.3, 2.5), min_size=3, max_size=3),
       g=st.lists(st.floats(-3.1, 3.1), min_size=2, max_size=2))
def test_shifted_potential_chain_equals_the_jets(a, g):
    """Three sliders on the substrate at phases phi, 2 phi and (cos) -phi: a Frenkel-
    Kontorova chain of self-excited sliders, its first-order slow flow."""
    jet = jet_expansion(FK, FK_VALUES, 1, a, g)
    numeric = [*[row[0] for row in jet.A], *[row[0] for row in jet.B]]
    assert np.allclose(FK_RATES(*a, *g), numeric, rtol=0, atol=1e-11)


def test_shifted_potential_u1_equals_fft_quadrature():
    r = derive_coupled(FK, 1)
    a = [1.3, 0.8, 1.9]
    sub = {sp.Symbol(k): v for k, v in FK_VALUES.items()}
    sub.update(dict(zip(sp.symbols("a1:4"), a)))
    angles = sp.symbols("psi1:4")
    for i in range(3):
        exact = sp.lambdify(angles, cut_sums(r.u[i][1]).subs(sub), ["numpy", "scipy"])
        quad = u_by_fft(FK, FK_VALUES, a, i, nodes=48)
        for p in ((0.3, 2.0, -1.0), (1.7, -0.4, 2.5)):
            assert abs(exact(*p) - quad(p)) < 1e-11


def test_a_forcing_phase_equals_its_two_quadratures():
    """h cos(theta + phi) = h cos(phi) cos(theta) - h sin(phi) sin(theta): the expansion
    with the phase equals the one with two forcing amplitudes h1, h2 put in afterwards
    (a 1:2 internal resonance, forced at 1:1, order 2)."""
    rhs2 = "-x2**3 - 2*zeta*xdot2 + c*x1**2"
    with_phase = coupled_custom(["-2*zeta*xdot1 - x1**3 + h*cos(theta + phi) + c*x1*x2",
                                 rhs2], "1,2", nu0=1).with_internal(["1:2", "1:1@1,F"])
    two = coupled_custom(["-2*zeta*xdot1 - x1**3 + h1*cos(theta) - h2*sin(theta) + c*x1*x2",
                          rhs2], "1,2", nu0=1).with_internal(["1:2", "1:1@1,F"])
    h, phi = sp.symbols("h phi")
    put = {sp.Symbol("h1"): h * sp.cos(phi), sp.Symbol("h2"): h * sp.sin(phi)}
    r1, r2 = derive_coupled(with_phase, 2), derive_coupled(two, 2)
    for rows1, rows2 in ((r1.A, r2.A), (r1.B, r2.B), (r1.u, r2.u)):
        for row1, row2 in zip(rows1, rows2):
            for e1, e2 in zip(row1[1:], row2[1:]):
                assert sp.expand(e2.xreplace(put) - e1) == 0
