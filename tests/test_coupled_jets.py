"""The coupled numeric backend beyond the first order (kbm.backend.jets, issue 23) against
independent references.

- The exact engine (kbm.expansion.coupled.derive_coupled: exact multi-angle Fourier series with
  Laurent coefficients, its amplitude derivatives symbolic) on the polynomial built-ins at
  orders 1 to 3: coupled-vdp (1:1), duffing-1-3 (1:3 and forced; Nayfeh & Mook sec. 6.6),
  quadratic-1-2 (1:2 with a declared detuning, forced; N&M sec. 6.5), a non-resonant pair.
- The one-degree-of-freedom pointwise engine (kbm.derive_values: the Jacobi-Anger/Bessel
  harmonics of sin(k x), paper eq. 3's SEDF) at orders 1 to 4, as the case N = 1.
- A coupling the exact engine cannot take, c sin(x2 - x1), against the exact engine on its
  Taylor polynomial (degree 7), within the bound of the Taylor remainder.
- The first-order FFT average of kbm.backend.coupled (a second method at order 1).
- Invariants: a conservative F never changes the amplitude, at any order (hypothesis).
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings, strategies as st

from kbm.model.coupled_builtins import coupled_custom
from kbm.expansion.coupled import derive_coupled
from kbm.model.coupled_builtins import get_coupled_model
from kbm.backend.jets import MAX_ORDER_JETS, jet_expansion
from kbm.model.coupled import CoupledOscillators
from kbm.backend.coupled import numeric_average
from kbm.expansion.resonance import UndeclaredResonanceError
from kbm.model.variables import amplitudes
from kbm.errors import ModelError, OrderError, ParameterError
from kbm.model.builtins import get_model
from kbm.backend.pointwise import derive_values

#: frequencies 1 and 7/2: the nearest resonance 7 omega1 = 2 omega2 needs harmonics of
#: degree 9, beyond those of a cubic F to order 3 (2 n + 1 = 7)
NONRES = coupled_custom(["(1 - x1**2)*xdot1 + c*x2**2", "(1 - x2**2)*xdot2 - c*x1*xdot1"],
                        "1,7/2")
CASES = {
    "coupled-vdp": ({"c": 0.3, "sigma": 0.7}, 3),
    "duffing-1-3": ({"zeta1": 0.1, "zeta2": 0.2, "alpha1": 1, "alpha2": 0.5, "k": 1.5,
                     "h": 2, "sigma": 0.3}, 2),
    "quadratic-1-2": ({"zeta1": 0.5, "zeta2": 0.25, "alpha1": 1, "alpha2": 2, "h": 3,
                       "sigma1": 0.4, "sigma2": 0.5}, 2),
    "nonresonant": ({"c": 0.7}, 3),
}


def _model(name):
    return NONRES if name == "nonresonant" else get_coupled_model(name)


@lru_cache(maxsize=None)
def _exact(name: str, order: int):
    """The exact rates as functions ``(a1, a2, gammas..., parameters...) -> float``."""
    r = derive_coupled(_model(name), order)
    vals, _ = CASES[name]
    gam = [g for g, _ in r.gammas]
    args = [*amplitudes(2), *gam, *[sp.Symbol(k) for k in vals]]
    fA = [[sp.lambdify(args, r.A[i][n]) for n in range(1, order + 1)] for i in range(2)]
    fB = [[sp.lambdify(args, r.B[i][n]) for n in range(1, order + 1)] for i in range(2)]
    return fA, fB, len(gam)


@pytest.mark.parametrize("name", list(CASES))
@settings(max_examples=4, deadline=None)
@given(data=st.data())
def test_equals_the_exact_engine_to_order_3(name, data):
    """Every A_{i,n}, B_{i,n} at a random point, to rounding (the jets' amplitude
    derivatives are exact, the grid holds every harmonic of a polynomial F)."""
    vals, order = CASES[name]
    fA, fB, ng = _exact(name, order)
    a = [data.draw(st.floats(0.2, 2.0)) for _ in range(2)]
    g = [data.draw(st.floats(-math.pi, math.pi)) for _ in range(ng)]
    ex = jet_expansion(_model(name), vals, order, a, g)
    args = [*a, *g, *vals.values()]
    for i in range(2):
        for n in range(order):
            scale = 1 + max(a) ** (2 * n + 3)
            assert ex.A[i][n] == pytest.approx(float(fA[i][n](*args)), abs=1e-12 * scale)
            assert ex.B[i][n] == pytest.approx(float(fB[i][n](*args)), abs=1e-12 * scale)
    assert ex.tail < 1e-10  # the shell holds rounding only


def test_the_forced_1_3_system_at_order_3():
    """duffing-1-3 forced (three angles on the grid) at order 3 at one point."""
    vals = CASES["duffing-1-3"][0]
    r = derive_coupled("duffing-1-3", 3)
    a, g = (1.1, 0.7), (0.3, 0.7)
    ex = jet_expansion(get_coupled_model("duffing-1-3"), vals, 3, a, g)
    sub = {**{sp.Symbol(k): v for k, v in vals.items()}, **dict(zip(amplitudes(2), a)),
           **dict(zip([s for s, _ in r.gammas], g))}
    for i in range(2):
        for n in (1, 2, 3):
            assert ex.A[i][n - 1] == pytest.approx(float(r.A[i][n].subs(sub)), abs=1e-13)
            assert ex.B[i][n - 1] == pytest.approx(float(r.B[i][n].subs(sub)), abs=1e-13)


@settings(max_examples=10, deadline=None)
@given(a=st.floats(0.2, 2.0), delta=st.floats(0.1, 1.5), k=st.floats(0.5, 3.0),
       beta=st.floats(0.2, 2.0))
def test_one_degree_of_freedom_equals_the_bessel_engine(a, delta, k, beta):
    """N = 1: the SEDF (paper eq. 3, F = (1 - beta x^2) x' - delta sin(k x)) at orders 1 to
    4 against kbm.derive_values (Jacobi-Anger harmonics: J_n(k a))."""
    p = {"beta": beta, "delta": delta, "k": k}
    ref = derive_values("sedf", 4, [a], p)
    model = get_model("sedf")  # the case N = 1 of the one type, as it is
    ex = jet_expansion(model, p, 4, [a], [], nodes=64)
    for n in range(1, 5):
        scale = 1 + (delta * k + a**2) ** n
        assert ex.A[0][n - 1] == pytest.approx(ref.A[n][0], abs=1e-12 * scale)
        assert ex.B[0][n - 1] == pytest.approx(ref.B[n][0], abs=1e-12 * scale)


def test_a_smooth_coupling_equals_the_exact_engine_on_its_taylor_polynomial():
    """Two van der Pol oscillators coupled by c sin(x2 - x1) in 1:1, at order 2, against the
    exact engine on sin u ~ u - u^3/6 + u^5/120 - u^7/5040 (|u| <= a1 + a2 = 0.35: the
    remainder is below 0.35^9/9! = 2.2e-10 times c)."""
    c = 0.3
    smooth = coupled_custom(["(1 - x1**2)*xdot1 + c*sin(x2 - x1)",
                             "(1 - x2**2)*xdot2 - c*sin(x2 - x1)"]).with_internal(["1:1"])
    taylor = "((x2 - x1) - (x2 - x1)**3/6 + (x2 - x1)**5/120 - (x2 - x1)**7/5040)"
    poly = coupled_custom([f"(1 - x1**2)*xdot1 + c*{taylor}",
                           f"(1 - x2**2)*xdot2 - c*{taylor}"]).with_internal(["1:1"])
    r = derive_coupled(poly, 2)
    a, g = (0.2, 0.15), (0.9,)
    ex = jet_expansion(smooth, {"c": c}, 2, a, g)
    sub = {sp.Symbol("c"): c, **dict(zip(amplitudes(2), a)), r.gammas[0][0]: g[0]}
    bound = 10 * c * 0.35**9 / math.factorial(9)
    for i in range(2):
        for n in (1, 2):
            assert ex.A[i][n - 1] == pytest.approx(float(r.A[i][n].subs(sub)), abs=bound)
            assert ex.B[i][n - 1] == pytest.approx(float(r.B[i][n].subs(sub)),
                                                   abs=bound / a[i])
    # order 1 by the FFT average of kbm.backend.coupled (a second method)
    A1, B1, _ = numeric_average(smooth, {"c": c}).rates(a, g)
    assert np.allclose(A1, [ex.A[0][0], ex.A[1][0]], atol=1e-15)
    assert np.allclose(B1, [ex.B[0][0], ex.B[1][0]], atol=1e-15)


@settings(max_examples=8, deadline=None)
@given(a1=st.floats(0.2, 1.5), a2=st.floats(0.2, 1.5), gamma=st.floats(-3, 3),
       c=st.floats(0.05, 1.0))
def test_slow_flow_of_order_2_sums_the_orders(a1, a2, gamma, c):
    """NumericAverage.slow_flow at order 2 is mu A_1 + mu^2 A_2 (and the gamma rate the
    same combination of the B's), the order-1 part from the FFT average."""
    model = get_coupled_model("coupled-vdp")
    na = numeric_average(model, {"c": c, "sigma": 0.2})
    mu = 0.05
    ex = na.expansion([a1, a2], [gamma], 2)
    flow = na.slow_flow(mu, [a1, a2], [gamma], order=2)
    for i in range(2):
        assert flow[i] == pytest.approx(mu * ex.A[i][0] + mu**2 * ex.A[i][1], abs=1e-15)
    (g,) = na.gammas
    rate = sum(g[i] * (mu * ex.B[i][0] + mu**2 * ex.B[i][1]) for i in range(2))
    assert flow[2] == pytest.approx(rate, abs=1e-15)


@settings(max_examples=8, deadline=None)
@given(a=st.floats(0.2, 2.0), delta=st.floats(0.1, 2.0), k=st.floats(0.5, 3.0),
       b=st.floats(-1.0, 1.0))
def test_a_conservative_force_never_changes_the_amplitude(a, delta, k, b):
    """F = -delta sin(k x) - b x^3 (a force with a potential): A_n = 0 at every order."""
    model = coupled_custom(["-delta*sin(k*x1) - b*x1**3"])
    ex = jet_expansion(model, {"delta": delta, "k": k, "b": b}, 4, [a], [], nodes=64)
    for n in range(4):
        assert abs(ex.A[0][n]) < 1e-12 * (1 + (delta * k + abs(b) * a**2) ** (n + 1))


def test_bad_input_gets_one_line_errors():
    vdp = get_coupled_model("coupled-vdp")
    vals = {"c": 0.3, "sigma": 0.1}
    with pytest.raises(OrderError, match=f"from 1 to {MAX_ORDER_JETS}"):
        jet_expansion(vdp, vals, MAX_ORDER_JETS + 1, [1, 1], [0])
    with pytest.raises(ParameterError, match="positive amplitudes"):
        jet_expansion(vdp, vals, 2, [1, -1], [0])
    with pytest.raises(ParameterError, match="slow phases"):
        jet_expansion(vdp, vals, 2, [1, 1], [])
    with pytest.raises(ParameterError, match="give values for c"):
        jet_expansion(vdp, {"sigma": 0.1}, 2, [1, 1], [0])
    # 1:3 frequencies with a cubic coupling, the resonance not declared: named
    undeclared = coupled_custom(["-x1**3 - x1**2*x2", "-x2**3 - x1**3"], "1,3")
    with pytest.raises(UndeclaredResonanceError, match=r"internal=\['1:3'\]"):
        jet_expansion(undeclared, {}, 2, [1, 1], [])
    # a forcing frequency in F puts mu into F
    forced_nu = CoupledOscillators("f", ("-x1**3 + cos(theta)*nu",), (1,), nu0=1,
                                   nu_detuning="sigma")
    with pytest.raises(ModelError, match="forcing frequency nu"):
        jet_expansion(forced_nu, {"sigma": 0.1}, 2, [1], [])


def test_kbm_derive_numeric_at_order_3(capsys):
    """``kbm derive --numeric --at ... --order 3``: the JSON rows ``[null, A_1, A_2, A_3]``
    are jet_expansion's; an order above the limit is a one-line error."""
    import json

    from numerics.cli import main

    argv = ["derive", "--rhs", "(1 - x1**2)*xdot1 + c*sin(x2 - x1)",
            "--rhs", "(1 - x2**2)*xdot2 - c*sin(x2 - x1)", "--internal", "1:1", "-p", "c=0.3",
            "--numeric", "--at", "a1=0.4,a2=0.3,gamma1=0.9"]
    assert main([*argv, "--order", "3", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    model = coupled_custom(["(1 - x1**2)*xdot1 + c*sin(x2 - x1)",
                            "(1 - x2**2)*xdot2 - c*sin(x2 - x1)"]).with_internal(["1:1"])
    ex = jet_expansion(model, {"c": 0.3}, 3, [0.4, 0.3], [0.9])
    assert d["order"] == 3
    assert [row[1:] for row in d["A"]] == [list(r) for r in ex.A]
    assert [row[1:] for row in d["B"]] == [list(r) for r in ex.B]
    assert main([*argv, "--order", str(MAX_ORDER_JETS + 1)]) == 2
    err = capsys.readouterr().err
    assert f"--order 1 to {MAX_ORDER_JETS}" in err and len(err.strip().splitlines()) == 1


def test_locking_edges_at_order_2_for_a_sine_coupling():
    """Two van der Pol oscillators coupled through sin(x2 - x1), detuned by sigma: the edges
    of 1:1 locking from the order-2 slow flow (numeric backend on jets, the exact engine
    cannot take sin) against the true edges (numerics.locking.fold.true_edges: where the
    locked cycle of the full system ceases to exist).  Order 1's error falls like mu (its
    edges do not depend on mu); order 2's like mu^2, and is 50 times smaller at mu = 0.05."""
    from numerics.locking.mutual import averaged_edges
    from numerics.locking.fold import true_edges

    m = coupled_custom(["(1 - x1**2)*xdot1 + c*sin(x2 - x1)",
                        "(1 - x2**2)*xdot2 + c*sin(x1 - x2) - 2*sigma*x2"],
                       "1,1").with_internal(["1:1"])
    err1, err2 = {}, {}
    for mu in (0.05, 0.025):
        av1 = averaged_edges(m, {"mu": mu, "c": 0.3}, 1, "sigma", 2.0)
        av2 = averaged_edges(m, {"mu": mu, "c": 0.3}, 2, "sigma", 2.0)
        tr = true_edges(m, {"mu": mu, "c": 0.3}, "sigma", 2.0, 1e-9,
                        {e.side: e.sigma for e in av2})
        err1[mu] = [abs(a.sigma - t.sigma) for a, t in zip(av1, tr)]
        err2[mu] = [abs(a.sigma - t.sigma) for a, t in zip(av2, tr)]
    for side in (0, 1):
        assert 1.8 < err1[0.05][side] / err1[0.025][side] < 2.2, err1
        assert 3.0 < err2[0.05][side] / err2[0.025][side] < 5.5, err2
        assert err2[0.05][side] < err1[0.05][side] / 50, (err1, err2)


def test_the_grid_is_refined_until_the_outer_coefficients_are_small():
    """c sin(x2 - x1) at amplitudes where |x2 - x1| reaches 3.6: on 32 points per angle the
    u_n's outer coefficients are 1e-9 of the largest (J_15(3.6)); the adaptive grid doubles
    to 64 and agrees with a fixed grid of 128 to rounding.  An unreachable tolerance ends
    in a ResolutionError with the numbers."""
    from kbm.errors import ResolutionError

    m = coupled_custom(["(1 - x1**2)*xdot1 + c*sin(x2 - x1)",
                        "(1 - x2**2)*xdot2 - c*sin(x2 - x1)"]).with_internal(["1:1"])
    point = ([2.0, 1.8], [2.5])
    coarse = jet_expansion(m, {"c": 0.3}, 3, *point, adapt=False)
    assert coarse.nodes == 32 and coarse.tail > 1e-10
    adaptive = jet_expansion(m, {"c": 0.3}, 3, *point)
    assert adaptive.nodes > 32 and adaptive.tail <= 1e-10
    fine = jet_expansion(m, {"c": 0.3}, 3, *point, nodes=128, adapt=False)
    assert np.allclose(adaptive.A, fine.A, atol=1e-14) and np.allclose(adaptive.B, fine.B,
                                                                        atol=1e-14)
    one = coupled_custom(["-delta*sin(k*x1)"])
    with pytest.raises(ResolutionError, match="outer Fourier coefficients"):
        jet_expansion(one, {"delta": 1.0, "k": 2.0}, 2, [1.0], [], tol=1e-300)
    with pytest.raises(ParameterError, match="even integer"):
        jet_expansion(one, {"delta": 1.0, "k": 2.0}, 2, [1.0], [], nodes=9)
