"""First-order averaging of coupled systems with any smooth F (kbm.backend.coupled, issue
23) against independent references.

- The exact engine (kbm.expansion.coupled.derive_coupled, exact multi-angle Fourier algebra) on the
  polynomial built-ins: 1:1 (coupled-vdp), 1:3 forced (duffing-1-3), 1:2 forced with a
  declared detuning (quadratic-1-2), and a non-resonant pair: the grid average equals it to
  rounding.
- A Bessel closed form for a coupling the exact engine cannot take, -c sin(x1 - x2) between
  two oscillators in 1:1 (x1 - x2 = R cos(psi1 + delta), R e^{i delta} = a1 - a2 e^{i gamma};
  sin(R cos phi) = 2 sum (-1)^k J_{2k+1}(R) cos((2k+1) phi), Jacobi-Anger): A_1 =
  c a2 sin(gamma) J_1(R)/R, B_1 = c (a1 - a2 cos gamma) J_1(R)/(R a1), and the same with 1
  and 2 exchanged (gamma -> -gamma); J_1(R)/R -> 1/2 as R -> 0.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings, strategies as st
from scipy.special import j1

from kbm.model.coupled_builtins import coupled_custom
from kbm.expansion.coupled import derive_coupled
from kbm.backend.coupled import numeric_average
from kbm.model.variables import amplitudes
from kbm.errors import ModelError, ParameterError

CASES = [("coupled-vdp", {"c": 0.3, "sigma": 0.7}),
         ("duffing-1-3", {"zeta1": 0.1, "zeta2": 0.2, "alpha1": 1, "alpha2": 0.5, "k": 1.5,
                          "h": 2, "sigma": 0.3}),
         ("quadratic-1-2", {"zeta1": 0.5, "zeta2": 0.25, "alpha1": 1, "alpha2": 2, "h": 3,
                            "sigma1": 0.4, "sigma2": 0.5})]
NONRES = coupled_custom(["(1 - x1**2)*xdot1 + c*x2**2", "(1 - x2**2)*xdot2 - c*x1*xdot1"],
                        "1,3/2")


@pytest.mark.parametrize("name, vals", CASES + [(NONRES, {"c": 0.7})])
@settings(max_examples=15, deadline=None)
@given(data=st.data())
def test_equals_the_exact_engine_at_first_order(name, vals, data):
    r = derive_coupled(name, 1)
    na = numeric_average(name, vals)
    gam = [g for g, _ in r.gammas]
    a = [data.draw(st.floats(0.2, 2.5)) for _ in range(2)]
    g = [data.draw(st.floats(-math.pi, math.pi)) for _ in gam]
    A, B, tail = na.rates(a, g)
    sub = {**{sp.Symbol(k): v for k, v in vals.items()}, **dict(zip(amplitudes(2), a)),
           **dict(zip(gam, g))}
    for i in range(2):
        assert A[i] == pytest.approx(float(r.A[i][1].subs(sub)), abs=1e-12)
        assert B[i] == pytest.approx(float(r.B[i][1].subs(sub)), abs=1e-12)
    assert tail < 1e-12


def _sin_coupled():
    return coupled_custom(["-c*sin(x1 - x2)", "-c*sin(x2 - x1)"], "1,1").with_internal(["1:1"])


@settings(max_examples=20, deadline=None)
@given(a1=st.floats(0.1, 4.0), a2=st.floats(0.1, 4.0), gamma=st.floats(-3.1, 3.1))
def test_sine_coupling_against_the_bessel_closed_form(a1, a2, gamma):
    """The grid's error is bounded by its stated tail (the largest coefficient on the outer
    shell, ~J_15(R)): rounding where the grid resolves F, 1e-10 at R = 4."""
    c = 0.8
    A, B, tail = numeric_average(_sin_coupled(), {"c": c}).rates([a1, a2], [gamma])
    z = a1 - a2 * complex(math.cos(gamma), math.sin(gamma))
    R = abs(z)
    f = j1(R) / R if R > 1e-8 else 0.5
    tol = 1e-12 + 10 * tail
    assert tail < 1e-6
    assert A[0] == pytest.approx(c * a2 * math.sin(gamma) * f, abs=tol)
    assert B[0] == pytest.approx(c * (a1 - a2 * math.cos(gamma)) * f / a1, abs=tol)
    assert A[1] == pytest.approx(-c * a1 * math.sin(gamma) * f, abs=tol)
    assert B[1] == pytest.approx(c * (a2 - a1 * math.cos(gamma)) * f / a2, abs=tol)


def test_conservative_coupling_keeps_the_energy_exchange_balanced():
    """sin(x1 - x2) is conservative: omega1 a1 A1 + omega2 a2 A2 = 0 (the averaged energy
    a1^2 + a2^2 is conserved at first order), at any amplitudes and phase."""
    na = numeric_average(_sin_coupled(), {"c": 0.5})
    rng = np.random.default_rng(3)
    for _ in range(10):
        a = rng.uniform(0.2, 3.0, 2)
        A, _, _ = na.rates(a, [rng.uniform(-3, 3)])
        assert a[0] * A[0] + a[1] * A[1] == pytest.approx(0, abs=1e-13)


def test_slow_flow_of_a_locked_pair():
    """The 1:1 slow flow of coupled-vdp: at sigma = 0 the in-phase state a1 = a2 = 2,
    gamma = 0 is a fixed point (the single van der Pol cycle)."""
    na = numeric_average("coupled-vdp", {"c": 0.3, "sigma": 0.0})
    assert np.max(np.abs(na.slow_flow(0.1, [2.0, 2.0], [0.0]))) < 1e-14


def test_bad_input():
    with pytest.raises(ParameterError, match="positive amplitudes"):
        numeric_average("coupled-vdp", {"c": 0.3, "sigma": 0}).rates([1.0, -1.0], [0.0])
    with pytest.raises(ParameterError, match="slow phases"):
        numeric_average("coupled-vdp", {"c": 0.3, "sigma": 0}).rates([1.0, 1.0], [])
    with pytest.raises(ParameterError, match="give values for c"):
        numeric_average(_sin_coupled(), {}).rates([1.0, 1.0], [0.0])
    with pytest.raises(ParameterError, match="even integer"):
        numeric_average("coupled-vdp", {"c": 0.3, "sigma": 0}, nodes=7)
    with pytest.raises(ParameterError, match="exceed the limit"):
        numeric_average("sedf-chain", {"mu": 0.1}, nodes=64)
    with pytest.raises(ParameterError, match="detunings sigma1"):
        numeric_average("quadratic-1-2", {"zeta1": 0.5})
    with pytest.raises(ModelError, match="depends on t"):
        numeric_average("sedf-dimer", {"v": 0.5})


def _cli(capsys, *argv):
    from numerics.cli import main

    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_kbm_derive_numeric_at_a_point(capsys):
    import json

    argv = ["derive", "--rhs", "-c*sin(x1 - x2)", "--rhs", "-c*sin(x2 - x1)", "--omega0", "1,1",
            "--internal", "1:1", "-p", "c=0.8", "--order", "1", "--numeric"]
    code, out, err = _cli(capsys, *argv, "--at", "a1=1,a2=3,gamma1=0.5", "--json")
    assert code == 0, err
    d = json.loads(out)
    A, B, _ = numeric_average(_sin_coupled(), {"c": 0.8}).rates([1, 3], [0.5])
    assert [row[1] for row in d["A"]] == list(A) and [row[1] for row in d["B"]] == list(B)
    assert d["gammas"] == [["gamma1", "psi2 - psi1"]]
    for extra, words in ((["--at", "a1=1"], "missing a2, gamma1"), ([], "give the point"),
                         (["--at", "a1=1,a2=x,gamma1=0"], "NAME=VALUE")):
        code, out, err = _cli(capsys, *argv, *extra)
        assert code == 2 and words in err and len(err.strip().splitlines()) == 1, err


def test_locking_of_sine_coupled_van_der_pol_oscillators():
    """Two van der Pol oscillators coupled through sin(x2 - x1) (the exact engine cannot take
    it): the order-1 locking edges from the numeric backend's slow flow (the same in sigma
    for every mu) against the true edges (where the locked cycle of the full system ceases
    to exist, numerics.locking.fold.true_edges): the error falls like mu."""
    from numerics.locking.mutual import averaged_edges
    from numerics.locking.fold import true_edges

    m = coupled_custom(["(1 - x1**2)*xdot1 + c*sin(x2 - x1)",
                        "(1 - x2**2)*xdot2 + c*sin(x1 - x2) - 2*sigma*x2"],
                       "1,1").with_internal(["1:1"])
    av = averaged_edges(m, {"mu": 0.05, "c": 0.3}, 1, "sigma", 2.0)
    assert av[0].sigma == pytest.approx(-av[1].sigma, abs=1e-10)  # symmetric at order 1
    err = {}
    for mu in (0.05, 0.025):
        tr = true_edges(m, {"mu": mu, "c": 0.3}, "sigma", 2.0, 1e-7,
                        {e.side: e.sigma for e in av})
        err[mu] = [abs(a.sigma - t.sigma) for a, t in zip(av, tr)]
    for side in (0, 1):
        assert 1.8 < err[0.05][side] / err[0.025][side] < 2.2, err
    assert max(err[0.025]) < 1e-3


def test_an_undeclared_resonance_is_refused_as_by_the_exact_engine():
    """The first order is the first order of the one recursion on the sampled algebra
    (kbm.backend.jets.first_order): a harmonic of F at an exact internal resonance that
    was not declared (1:1, (x1 - x2)**3 holds psi2 - psi1) has a vanishing divisor, and the
    numeric average refuses it as derive_coupled does (Bogoliubov & Mitropolsky 1961,
    ch. 5: the resonant combination must be kept as a slow phase); declared, it averages."""
    from kbm.expansion.resonance import UndeclaredResonanceError

    m = coupled_custom(["-c*(x1 - x2)**3", "-c*(x2 - x1)**3"], "1,1")
    with pytest.raises(UndeclaredResonanceError):
        derive_coupled(m, 1)
    with pytest.raises(UndeclaredResonanceError, match="declare"):
        numeric_average(m, {"c": 0.8}).rates([1.0, 0.5], [])
    A, B, _ = numeric_average(m.with_internal(["1:1"]), {"c": 0.8}).rates([1.0, 0.5], [0.3])
    r = derive_coupled(m.with_internal(["1:1"]), 1)
    sub = {sp.Symbol("c"): 0.8, **dict(zip(amplitudes(2), [1.0, 0.5])),
           r.gammas[0][0]: 0.3}
    assert A[0] == pytest.approx(float(r.A[0][1].subs(sub)), abs=1e-12)
    assert B[1] == pytest.approx(float(r.B[1][1].subs(sub)), abs=1e-12)
