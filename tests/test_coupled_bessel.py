"""sin(c x_i) and cos(c x_i) in the exact coupled expansion at first order
(kbm.algebra.coupled_bessel, issue 23: the sliders of paper eq. 3 in a chain), against independent
references.

- N = 1: the one-degree-of-freedom Bessel engine kbm.derive (its own Jacobi-Anger series
  with lattice sums, kbm.algebra.bessel_fourier) on the paper's SEDF (eq. 3) and CDC
  (eq. 12) and on products x^p cos(k x), x' sin(k x): the rates equal as expressions,
  u_1 numerically.
- u_{i,1} against FFT quadrature on the torus (the dimer; a forced 1:3 system).
- N = 2, 3: the jets (kbm.backend.jets: F's Taylor series on an FFT grid of the torus,
  no Bessel function anywhere) on the SEDF dimer and chain at random points (hypothesis),
  and on a forced slider with a 1:3 internal resonance.
- The first-order frequency of the dimer's in-phase and anti-phase cycles against
  shooting (numerics.shooting.coupled_orbit): the error falls like mu**2.
- The cut of the Jacobi-Anger series is exact: raising it changes nothing.
- A conservative F (the potential and the springs) leaves sum a_i**2 unchanged at first
  order (one slider: its amplitude).
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import sympy as sp
from _coupled_references import cut_sums, rates_function, u_by_fft
from hypothesis import given, settings
from hypothesis import strategies as st

import kbm
from kbm.algebra import coupled_bessel as bessel_module
from kbm.model.coupled import CoupledOscillators
from kbm.model.coupled_builtins import coupled_custom, get_coupled_model
from kbm.expansion.coupled import derive_coupled
from kbm.backend.jets import jet_expansion
from kbm.errors import ModelError, OrderError, ParameterError, UnsupportedTermError
from kbm.model.builtins import custom_model, get_model

A1 = sp.Symbol("a1")


@pytest.mark.parametrize("F", ["sedf", pytest.param("cdc", marks=pytest.mark.slow),
                               "(1 - x**2)*xdot - delta*x**2*cos(k*x)",
                               "-delta*x*cos(k*x) - 2*zeta*xdot",
                               "(1 - x**2)*xdot - delta*xdot*sin(k*x)",
                               "-delta*x**3*sin(2*k*x) + xdot"])
def test_n1_equals_the_bessel_engine(F):
    """Paper eqs. (3), (12) and products with powers of x and x' (A&S 9.1.44-45)."""
    model = get_model(F) if F in ("sedf", "cdc") else custom_model(F)
    one = kbm.derive(model, 1)
    gen = derive_coupled(model, 1)  # the model is an instance of the one type
    sub = {sp.Symbol("a"): A1, sp.Symbol("Omega"): 1}
    assert sp.simplify(one.A[1].subs(sub) - gen.A[0][1]) == 0
    assert sp.simplify(one.B[1].subs(sub) - gen.B[0][1]) == 0
    # u_1: the one-degree-of-freedom engine's Bessel sums against the cut series plus its
    # sums above the cut, numerically at a few points (the sums' indices differ)
    vals = {sp.Symbol(k): v for k, v in (("delta", 0.8), ("k", 2.1), ("beta", 1.3),
                                        ("zeta", 0.4))}
    psi = sp.Symbol("psi1")
    for a, p in ((0.7, 0.3), (2.2, 1.9), (3.1, -2.4)):
        ref = cut_sums(one.u[1].subs(sub)).subs({**vals, A1: a, sp.Symbol("psi"): p})
        got = cut_sums(gen.u[0][1]).subs({**vals, A1: a, psi: p})
        assert abs(complex(ref.evalf()) - complex(got.evalf())) < 1e-13


DIMER = get_coupled_model("sedf-dimer").at_rest()
CHAIN3 = get_coupled_model("sedf-chain-3").at_rest()
DIMER_RATES = rates_function(derive_coupled(DIMER, 1), {"delta": 1.3, "k": 2 * math.pi,
                                                "beta": 1.0, "kappa": 0.7})
CHAIN_VALUES = {"delta": 0.8, "k": 2 * math.pi / 1.7, "beta": 0.6, "kappa": 1.1}
CHAIN_RATES = rates_function(derive_coupled(CHAIN3, 1), CHAIN_VALUES)


@settings(max_examples=15, deadline=None)
@given(a1=st.floats(0.2, 3.0), a2=st.floats(0.2, 3.0), g=st.floats(-3.1, 3.1))
def test_dimer_equals_the_jets(a1, a2, g):
    """The SEDF dimer (paper eq. 3, two sliders, spring mu kappa) at v = 0."""
    vals = {"delta": 1.3, "k": 2 * math.pi, "beta": 1.0, "kappa": 0.7}
    jet = jet_expansion(DIMER, vals, 1, [a1, a2], [g])
    exact = DIMER_RATES(a1, a2, g)
    numeric = [jet.A[0][0], jet.A[1][0], jet.B[0][0], jet.B[1][0]]
    assert np.allclose(exact, numeric, rtol=0, atol=1e-11)


@settings(max_examples=4, deadline=None)
@given(a=st.lists(st.floats(0.3, 2.5), min_size=3, max_size=3),
       g=st.lists(st.floats(-3.1, 3.1), min_size=2, max_size=2))
def test_chain_of_three_equals_the_jets(a, g):
    jet = jet_expansion(CHAIN3, CHAIN_VALUES, 1, a, g)
    exact = CHAIN_RATES(*a, *g)
    numeric = [*[row[0] for row in jet.A], *[row[0] for row in jet.B]]
    assert np.allclose(exact, numeric, rtol=0, atol=1e-11)


def test_forced_slider_in_internal_resonance_equals_the_jets():
    """A slider forced at 1:1 and coupled to a mode of frequency 3 (1:3): the bound on the
    harmonics takes the forcing angle and the frequency ratio into account."""
    m = coupled_custom(["-delta*sin(k*x1) + (1 - x1**2)*xdot1 + c*x1**2*x2 + h*cos(theta)",
                        "-2*zeta*xdot2 + c*x1**3 - delta*x2*cos(k*x2)"], "1,3", nu0=1)
    m = m.with_internal(["1:3", "1:1@1,F"])
    vals = {"delta": 0.9, "k": 2.3, "c": 0.6, "h": 0.4, "zeta": 0.2, "sigma": 0.3}
    rates = rates_function(derive_coupled(m, 1), vals)
    for a, g in (([1.2, 0.5], [0.3, -1.1]), ([0.4, 1.6], [2.0, 0.7])):
        jet = jet_expansion(m, vals, 1, a, g)
        numeric = [*[row[0] for row in jet.A], *[row[0] for row in jet.B]]
        assert np.allclose(rates(*a, *g), numeric, rtol=0, atol=1e-11)


def test_raising_the_cut_changes_nothing(monkeypatch):
    m = coupled_custom(["-delta*x1**2*sin(k*x1) + c*x2*xdot1", "-delta*cos(k*x2)*x1**3"],
                       "1,3").with_internal(["1:3"])
    base = derive_coupled(m, 1)
    bound = bessel_module.harmonic_bound
    monkeypatch.setattr(bessel_module, "harmonic_bound", lambda *a: bound(*a) + 8)
    more = derive_coupled(m, 1)
    assert (base.A, base.B) == (more.A, more.B)
    monkeypatch.setattr(bessel_module, "harmonic_bound", lambda *a: 1)  # too low: differs
    assert derive_coupled(m, 1).B != base.B


@settings(max_examples=10, deadline=None)
@given(n=st.integers(1, 3), p=st.integers(0, 2), cos=st.booleans())
def test_a_conservative_force_keeps_the_energy(n, p, cos):
    """Potential forces (a force of x_i alone: sin, cos of the position times a power, and
    the symmetric springs of a chain) do no work on average: the first-order rate of the
    energy sum a_i**2/2 (omega_i = 1) vanishes, and with one slider every A_1 does."""
    trig = "cos" if cos else "sin"
    F = []
    for i in range(1, n + 1):
        springs = "".join(f" - kappa*(x{i} - x{j})" for j in (i - 1, i + 1) if 1 <= j <= n)
        F.append(f"-delta*{trig}(k*x{i})*x{i}**{p}{springs}")
    m = coupled_custom(F, ",".join(["1"] * n))
    m = m.with_internal([f"1:1@{i},{i + 1}" for i in range(1, n)])
    r = derive_coupled(m, 1)
    a = sp.symbols(f"a1:{n + 1}")
    assert sp.simplify(sum(ai * row[1] for ai, row in zip(a, r.A))) == 0
    if n == 1:
        assert r.A[0][1] == 0


def test_what_the_bessel_terms_do_not_take():
    dimer = get_coupled_model("sedf-dimer")
    with pytest.raises(OrderError, match="order 1, got order 2.*--numeric"):
        derive_coupled(dimer, 2)
    pair = coupled_custom(["-delta*sin(k*(x1 - x2))", "-delta*sin(k*(x2 - x1))"], "1,1")
    with pytest.raises(UnsupportedTermError, match="one\\s+position"):
        derive_coupled(pair.with_internal(["1:1"]), 1)
    prod = coupled_custom(["-delta*sin(k*x1)*cos(k*x2)", "xdot2"], "1,1")
    with pytest.raises(UnsupportedTermError, match="2 factors sin or cos"):
        derive_coupled(prod.with_internal(["1:1"]), 1)
    vel = coupled_custom(["-delta*sin(k*xdot1)", "xdot2"], "1,2")
    with pytest.raises(UnsupportedTermError, match="one\\s+position"):
        derive_coupled(vel, 1)
    with pytest.raises(ModelError, match="stage that pulls at v = 0.1.*give v=0"):
        derive_coupled(dimer, 1, {"v": "0.1"})
    timed = coupled_custom(["-delta*sin(k*x1 + t)", "xdot2"], "1,2")
    with pytest.raises(ModelError, match="depends on the time t explicitly"):
        derive_coupled(timed, 1)  # no parameter switches it off (k = 0 would not)
    with pytest.raises(UnsupportedTermError, match="float.*0.5 as 1/2"):
        derive_coupled(coupled_custom(["-sin(0.5*x1)", "xdot2"], "1,2"), 1)


def test_the_dimer_on_the_command_line(capsys):
    from numerics.cli import main

    assert main(["derive", "sedf-dimer", "--order", "1", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["A"][0][1] == "a1*(4 - a1**2*beta)/8 + a2*kappa*sin(gamma1)/2" or \
        sp.simplify(kbm.parse(out["A"][0][1])
                    - (A1 * (4 - A1**2 * sp.Symbol("beta")) / 8
                       + sp.Symbol("a2") * sp.Symbol("kappa") * sp.sin(sp.Symbol("gamma1")) / 2)
                    ) == 0
    assert "besselj(1, a1*k)" in out["B"][0][1]
    u = kbm.parse(out["u"][0][1])  # the cut series and the sum above it, read back
    assert u.has(sp.Sum) and "besselj(2*m + 1, a1*k)" in out["u"][0][1]
    assert main(["derive", "sedf-dimer", "--order", "1", "--latex"]) == 0
    tex = capsys.readouterr().out
    assert "J_{1}\\!\\left(a_{1} k\\right)" in tex and "u_{1,1} &=" in tex
    assert "\\sum_{m=1}^{\\infty}" in tex and "x_{2} &= a_{2}\\cos\\psi_{2}" in tex
    # the numeric backend at the default v = 0 (it used to ask for a value of t)
    assert main(["derive", "sedf-dimer", "--numeric", "--order", "2", "-p", "mu=0.1",
                 "-p", "Delta=0.15", "--at", "a1=1,a2=1.2,gamma1=0.3", "--json"]) == 0
    rows = json.loads(capsys.readouterr().out)
    assert rows
    assert main(["derive", "sedf-dimer", "--order", "1", "-p", "v=0.1"]) != 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "give v=0" in err[0]


def _dimer_cycle(mu: float, sign: int):
    from numerics.shooting.coupled_orbit import coupled_cycle

    # in phase (x2 = x1) and anti-phase (x2 = -x1) are invariant: F is odd
    return coupled_cycle("sedf-dimer", {"mu": mu, "delta": 1.0, "kappa": 0.5, "beta": 1,
                                        "lam": 1.0}, start=np.array([2.0, 2.0 * sign, 0, 0]))


def test_dimer_synchronisation_against_shooting():
    """The dimer's locked states at v = 0 (delta = 1, kappa = 1/2, beta = 1, k = 2 pi):
    the first-order slow flow has fixed points at a1 = a2 = 2 with gamma = 0 (in phase)
    and gamma = pi (anti-phase), frequencies 1 + mu delta J_1(2k)/2 and that plus
    mu kappa, and Jacobian eigenvalues lambda.  Shooting gives the true cycles: their
    frequencies agree to O(mu**2) and their Floquet exponents log(m)/(mu T) tend to
    lambda like mu; the in-phase state is the stable one."""
    from scipy.special import jv

    r = derive_coupled(get_coupled_model("sedf-dimer"), 1,
                       {"delta": 1, "kappa": "1/2", "beta": 1})
    rates = sp.Matrix([e.subs({sp.Symbol("mu"): 1, sp.Symbol("k"): 2 * sp.pi})
                       for e in r.slow_flow()])
    y = sp.symbols("a1 a2 gamma1")
    jac = rates.jacobian(y)
    for sign, gamma, shift in ((1, 0, 0.0), (-1, sp.pi, 0.5)):
        point = {y[0]: 2, y[1]: 2, y[2]: gamma}
        assert all(abs(float(e.subs(point))) < 1e-15 for e in rates)  # a fixed point
        flow = r.numpy_slow_flow({"k": 2 * math.pi})  # scipy's Bessel functions
        assert np.allclose(flow([2.0, 2.0, float(gamma)], 0.01), 0, atol=1e-15)
        assert np.allclose(flow([1.5, 2.5, 0.3], 0.01),
                           [0.01 * float(e.subs({y[0]: 1.5, y[1]: 2.5, y[2]: 0.3}))
                            for e in rates], rtol=1e-13, atol=0)
        lam = np.sort_complex(np.linalg.eigvals(np.array(jac.subs(point).evalf(),
                                                         dtype=float)))
        freq_err, exp_err = [], []
        for mu in (0.02, 0.01):
            c = _dimer_cycle(mu, sign)
            pred = 1 + mu * (jv(1, 4 * math.pi) / 2 + shift)
            freq_err.append(abs(c.frequency - pred))
            m = np.asarray(c.floquet_multipliers[1:], dtype=complex)
            exp_err.append(np.max(np.abs(np.sort_complex(np.log(m) / (c.period * mu)) - lam)))
            assert c.stable == (sign == 1)
        assert 3.5 < freq_err[0] / freq_err[1] < 4.5  # mu**2
        assert 1.6 < exp_err[0] / exp_err[1] < 2.4 and exp_err[1] < 0.01  # mu


@pytest.mark.parametrize("case", ["sedf-dimer", "forced-1-3"])
def test_u1_equals_fft_quadrature(case):
    """u_{i,1} with its sums over the harmonics above the cut equals the harmonics of F_i
    on the torus, by FFT, over their divisors (a second method: no Bessel function)."""
    if case == "sedf-dimer":
        model = DIMER
        vals = {"delta": 1.3, "k": 2 * math.pi, "beta": 1.0, "kappa": 0.7}
        a, points = [1.4, 0.9], [(0.3, 2.0), (1.7, -0.4)]
    else:
        model = coupled_custom(
            ["-delta*sin(k*x1) + (1 - x1**2)*xdot1 + c*x1**2*x2 + h*cos(theta)",
             "-2*zeta*xdot2 + c*x1**3 - delta*x2*cos(k*x2)"], "1,3", nu0=1
        ).with_internal(["1:3", "1:1@1,F"])
        vals = {"delta": 0.9, "k": 2.3, "c": 0.6, "h": 0.4, "zeta": 0.2}
        a, points = [1.2, 1.6], [(0.3, 2.0, -1.0), (1.7, -0.4, 2.5)]
    r = derive_coupled(model, 1)
    angles = [*sp.symbols(f"psi1:{model.dof + 1}")] + ([sp.Symbol("theta")] if model.forced
                                                       else [])
    sub = {sp.Symbol(k): v for k, v in vals.items()}
    sub.update(dict(zip(sp.symbols(f"a1:{model.dof + 1}"), a)))
    for i in range(model.dof):
        exact = sp.lambdify(angles, cut_sums(r.u[i][1]).subs(sub), ["numpy", "scipy"])
        quad = u_by_fft(model, vals, a, i)
        for p in points:
            assert abs(exact(*p) - quad(p)) < 1e-11


def test_the_paper_parameters_of_the_dimer():
    """-p mu, Delta, lam are read as the paper's (eq. 3): delta = Delta/mu, k = 2 pi/lam,
    as for one slider; k stays a symbol when lam is not given (whatever its default)."""
    one = kbm.derive("sedf", 1, {"mu": "0.1", "Delta": "1.5"})
    two = derive_coupled("sedf-dimer", 1, {"mu": "0.1", "Delta": "1.5"})
    sub = {sp.Symbol("a"): A1, sp.Symbol("Omega"): 1}
    springs = sp.Symbol("kappa") / 2 - sp.Symbol("a2") * sp.Symbol("kappa") \
        * sp.cos(sp.Symbol("gamma1")) / (2 * A1)
    assert sp.simplify(one.B[1].subs(sub) + springs - two.B[0][1]) == 0
    assert two.B[0][1].has(sp.besselj(1, A1 * sp.Symbol("k")))
    lam2 = derive_coupled("sedf-dimer", 1, {"lam": 2})
    assert lam2.B[0][1].has(sp.besselj(1, sp.pi * A1))
    with pytest.raises(ParameterError, match="needs a value of mu"):
        derive_coupled("sedf-dimer", 1, {"Delta": "1.5"})



def test_one_slider_above_the_first_order_in_the_general_form():
    """N = 1 is a case of the general form at every order kbm.derive takes: the SEDF (paper
    eq. 3) as CoupledOscillators at order 2 gives kbm.derive's Bessel lattice sums in the
    general form (a1, psi1), which equal the jets (Taylor series on an FFT grid) at a few
    amplitudes; derive_coupled alone stops at order 1 and says where to go."""
    model = CoupledOscillators("sedf", ("(1 - beta*x1**2)*xdot1 - delta*sin(k*x1)",), (1,))
    r = kbm.derive(model, 2)
    assert type(r).__name__ == "CoupledKBMResult" and r.to_json()["A"][0][2]
    vals = {"delta": 1.3, "k": 2.2, "beta": 0.9}
    sub = {sp.Symbol(k): v for k, v in vals.items()}
    for a in (0.6, 1.7, 2.9):
        jet = jet_expansion(model, vals, 2, [a])
        for n in (1, 2):
            exact_a = float(cut_sums(r.A[0][n]).subs({**sub, A1: a}).evalf())
            exact_b = float(cut_sums(r.B[0][n]).subs({**sub, A1: a}).evalf())
            assert abs(exact_a - jet.A[0][n - 1]) < 1e-11
            assert abs(exact_b - jet.B[0][n - 1]) < 1e-11
    with pytest.raises(OrderError, match="kbm.derive\\(model, N\\)"):
        derive_coupled(model, 2)
