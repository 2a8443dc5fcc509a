"""The coupled KBM recursion (kbm.expansion.coupled) against independent references.

- N = 1 is the one-degree-of-freedom recursion of kbm.expansion.one_dof (a different algebra and
  code path), exactly, to order 5;
- the first order is the numeric average of F_i sin(psi_i), F_i cos(psi_i) over the
  resonant torus (FFT quadrature, Bogoliubov & Mitropolsky 1961, ch. 5);
- a linear coupling expands exactly: the in-phase normal mode's frequency is
  sqrt(1 - mu kappa) to every order;
- Nayfeh & Mook (1979) sec. 6.5: the first-order modulation equations of quadratic
  coupling in 1:2 internal resonance;
- conservative right-hand sides: reversibility keeps sin(gamma) out of B and cos(gamma)
  out of A at every order, the amplitudes do not move without a resonance, and the
  energy sum_i omega_i^2 a_i^2 is conserved by the first-order flow (hypothesis).
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from kbm import derive
from kbm.model.coupled import CoupledOscillators, amplitudes, positions, velocities
from kbm.expansion.resonance import InternalResonance, UndeclaredResonanceError
from kbm.expansion.coupled import derive_coupled
from kbm.model.coupled_builtins import get_coupled_model
from kbm.errors import ModelError, OrderError, ParameterError, UnsupportedTermError
from kbm.symbols import mu

a1, a2 = amplitudes(2)
g1 = sp.Symbol("gamma1")


@pytest.mark.parametrize("name", ["vdp", "duffing", "rayleigh", "linear_damping"])
def test_one_degree_of_freedom_is_the_one_dof_recursion(name):
    """N = 1 of the coupled recursion equals kbm.derive's A_n, B_n exactly (order 5)."""
    r = derive_coupled(name, 5)
    o = derive(name, 5)
    a = sp.Symbol("a")
    for n in range(1, 6):
        assert sp.expand(r.A[0][n] - o.A[n].subs(a, a1)) == 0
        assert sp.expand(r.B[0][n] - o.B[n].subs(a, a1)) == 0


@pytest.mark.parametrize("name, order", [("vdp", 20), ("duffing", 30)])
def test_one_degree_of_freedom_to_high_orders(name, order):
    """N = 1 above the coupled limit of 8, to kbm.derive's own limit: the same A_n, B_n."""
    r = derive_coupled(name, order)
    o = derive(name, order)
    a = sp.Symbol("a")
    for n in range(1, order + 1):
        assert sp.expand(r.A[0][n] - o.A[n].subs(a, a1)) == 0
        assert sp.expand(r.B[0][n] - o.B[n].subs(a, a1)) == 0


def test_order_limits_depend_on_the_degrees_of_freedom():
    from kbm.expansion.coupled import MAX_ORDER, MAX_ORDER_ONE
    from kbm.errors import CostError

    with pytest.raises(OrderError, match=f"from 1 to {MAX_ORDER_ONE} for 1 degree of"):
        derive_coupled("vdp", MAX_ORDER_ONE + 1)
    with pytest.raises(OrderError, match=f"from 1 to {MAX_ORDER} for 2 degrees of"):
        derive_coupled("coupled-vdp", MAX_ORDER + 1)
    # a high degree: refused by the size estimate before any work, as kbm.derive refuses it
    heavy = CoupledOscillators("heavy", ("(x1 + 1)**40*xdot1",), (1,))
    with pytest.raises(CostError, match="budget"):
        derive_coupled(heavy, 30)


def _torus_average(model, values, amps, gamma, i, n_s=256):
    """-<F_i sin psi_i>/omega_i and -<F_i cos psi_i>/(omega_i a_i) by quadrature over the
    torus of the declared resonance p psi_2 - q psi_1 = gamma (or both angles)."""
    w = [float(v) for v in model.omega0]
    xs, vs = positions(2), velocities(2)
    f = sp.lambdify([*xs, *vs], model.F[i].subs(values), "numpy")
    s = 2 * np.pi * np.arange(n_s) / n_s
    if model.internal:
        r = model.internal[0]
        psi = [r.p * s, r.q * s + gamma / r.p]
    else:
        S1, S2 = np.meshgrid(s, s)
        psi = [S1.ravel(), S2.ravel()]
    x = [amps[k] * np.cos(psi[k]) for k in range(2)]
    v = [-w[k] * amps[k] * np.sin(psi[k]) for k in range(2)]
    F = f(*x, *v) * np.ones_like(psi[0])
    A = -np.mean(F * np.sin(psi[i])) / w[i]
    B = -np.mean(F * np.cos(psi[i])) / (w[i] * amps[i])
    return A, B


VALUES = {
    "coupled-vdp": {"c": sp.Rational(3, 10), "sigma": sp.Rational(1, 7)},
    "duffing-1-3": {"zeta1": sp.Rational(1, 20), "zeta2": sp.Rational(1, 30), "alpha1": 1,
                    "alpha2": sp.Rational(1, 2), "k": sp.Rational(3, 5), "h": 0},
    "quadratic-1-2": {"zeta1": sp.Rational(1, 10), "zeta2": sp.Rational(1, 5),
                      "alpha1": sp.Rational(3, 2), "alpha2": sp.Rational(2, 3), "h": 0},
}


@pytest.mark.parametrize("name", sorted(VALUES))
@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(amp1=st.floats(0.2, 3.0), amp2=st.floats(0.2, 3.0), gamma=st.floats(-3.1, 3.1))
def test_first_order_is_the_torus_average(name, amp1, amp2, gamma):
    """A_{i,1}, B_{i,1} of the built-ins against FFT quadrature of the averaging integrals."""
    model = get_coupled_model(name)
    vals = {sp.Symbol(k): v for k, v in VALUES[name].items()}
    res = derive_coupled(name, 1, VALUES[name])
    point = {a1: amp1, a2: amp2, g1: gamma, sp.Symbol("sigma1"): 0}
    for i in range(2):
        A, B = _torus_average(model, vals, (amp1, amp2), gamma, i)
        assert float(res.A[i][1].subs(point)) == pytest.approx(A, abs=1e-12)
        assert float(res.B[i][1].subs(point)) == pytest.approx(B, abs=1e-12)


def test_non_resonant_first_order_is_the_full_torus_average():
    """Frequencies 1 and 5/2 (no resonance met at order 1 of a cubic F)."""
    m = CoupledOscillators("nr", ("(1 - x1**2)*xdot1 - x1*x2**2", "-xdot2/5 - x2**3 + x1**2*x2"),
                           (1, sp.Rational(5, 2)))
    res = derive_coupled(m, 1)
    assert res.gammas == ()
    for amp1, amp2 in [(0.7, 1.3), (2.0, 0.4)]:
        for i in range(2):
            A, B = _torus_average(m, {}, (amp1, amp2), 0.0, i)
            assert float(res.A[i][1].subs({a1: amp1, a2: amp2})) == pytest.approx(A, abs=1e-12)
            assert float(res.B[i][1].subs({a1: amp1, a2: amp2})) == pytest.approx(B, abs=1e-12)


def test_linear_coupling_expands_exactly():
    """x1'' + x1 = mu kappa x2, x2'' + x2 = mu kappa x1: the in-phase normal mode (a1 = a2,
    gamma = 0) turns at sqrt(1 - mu kappa), the anti-phase one (gamma = pi) at
    sqrt(1 + mu kappa), to every order (order 6)."""
    m = CoupledOscillators("lin", ("-kappa*x2", "-kappa*x1"), (1, 1), internal=("1:1",))
    N = 6
    res = derive_coupled(m, N)
    kappa = sp.Symbol("kappa")
    for gamma, sign in ((0, 1), (sp.pi, -1)):
        pt = {a2: a1, g1: gamma}
        freq = sp.expand(sum(mu**n * res.B[0][n].subs(pt) for n in range(N + 1)))
        exact = sp.series(sp.sqrt(1 + sign * mu * kappa), mu, 0, N + 1).removeO()
        assert sp.expand(freq - exact) == 0
        for i in range(2):
            assert all(sp.simplify(res.A[i][n].subs(pt)) == 0 for n in range(1, N + 1))


def test_quadratic_1_2_is_nayfeh_mook_6_5():
    """Nayfeh & Mook (1979) sec. 6.5 (h = 0): a1' = -mu1 a1 - alpha1/(4 w1) a1 a2 sin gamma,
    a2' = -mu2 a2 + alpha2/(4 w2) a1^2 sin gamma, a1 b1' = alpha1/(4 w1) a1 a2 cos gamma,
    a2 b2' = alpha2/(4 w2) a1^2 cos gamma (their beta_i = psi_i - omega_i t), gamma = psi2 - 2 psi1."""
    res = derive_coupled("quadratic-1-2", 1, {"h": 0})  # free oscillations
    z1, z2, al1, al2, s1 = sp.symbols("zeta1 zeta2 alpha1 alpha2 sigma1")
    w1, w2 = 1, 2
    assert res.gammas[0][1] == sp.Symbol("psi2") - 2 * sp.Symbol("psi1")
    expect_A = [-z1 * a1 - al1 / (4 * w1) * a1 * a2 * sp.sin(g1),
                -z2 * a2 + al2 / (4 * w2) * a1**2 * sp.sin(g1)]
    # B_2 holds the detuning: psi2' = 2 + mu sigma1 + ... (omega2 = 2 omega1 + mu sigma1)
    expect_B = [al1 / (4 * w1) * a2 * sp.cos(g1),
                al2 / (4 * w2) * a1**2 / a2 * sp.cos(g1) + s1]
    for i in range(2):
        assert sp.expand(res.A[i][1] - expect_A[i]) == 0
        assert sp.expand(res.B[i][1] - expect_B[i]) == 0


_coef = st.integers(-3, 3)


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(c=st.lists(_coef, min_size=6, max_size=6), resonant=st.booleans())
def test_conservative_forces_reversibility(c, resonant):
    """F_i = -dV/dx_i (no velocity): A_{i,n} holds only sines of gamma and B_{i,n} only
    cosines at every order (time reversal); without a resonance A = 0 to order 3; at order
    1 the energy sum omega_i^2 a_i^2 is conserved (the coupling only exchanges it)."""
    x1, x2 = positions(2)
    V = (c[0] * x1**4 + c[1] * x1**3 * x2 + c[2] * x1**2 * x2**2 + c[3] * x2**4
         + c[4] * x1**2 * x2 + c[5] * x1 * x2**2) / 4
    w = (1, 3) if resonant else (1, sp.Rational(17, 10))
    m = CoupledOscillators("V", (-sp.diff(V, x1), -sp.diff(V, x2)), w,
                           internal=("1:3",) if resonant else ())
    res = derive_coupled(m, 3 if not resonant else 2)
    for i in range(2):
        for n in range(1, res.order + 1):
            A = sp.expand(res.A[i][n])
            B = sp.expand(res.B[i][n])
            assert not A.has(sp.cos), (i, n, A)
            assert not B.has(sp.sin), (i, n, B)
            if not resonant:
                assert A == 0
    energy = sp.expand(sum(wi**2 * ai * res.A[i][1] for i, (wi, ai) in enumerate(zip(w, (a1, a2)))))
    assert energy == 0


def test_declared_detuning_is_the_detuning_in_F():
    """omega_2 = 1 + mu sigma declared with the resonance equals -2 sigma x2 written in F at
    first order (exactly: the declared one adds -sigma^2 x2 at the second)."""
    written = derive_coupled("coupled-vdp", 1)
    m = CoupledOscillators("declared", ("(1 - x1**2)*xdot1 + c*(xdot2 - xdot1)",
                                        "(1 - x2**2)*xdot2 + c*(xdot1 - xdot2)"), (1, 1),
                           internal=(InternalResonance(1, 2, 1, 1, "sigma"),))
    declared = derive_coupled(m, 1)
    for i in range(2):
        assert sp.expand(written.A[i][1] - declared.A[i][1]) == 0
        assert sp.expand(written.B[i][1] - declared.B[i][1]) == 0


# -- bad input: errors of the package that say what to change ---------------------------
def test_undeclared_resonances_are_named():
    m = CoupledOscillators("m", ("-x1**2*x2", "-x1**3"), (1, 3))
    # the library names its argument; kbm derive says --internal 1:3 (test_cli_messages)
    with pytest.raises(UndeclaredResonanceError, match=r"internal=\['1:3'\]"):
        derive_coupled(m, 1)
    near = CoupledOscillators("m", ("-x1**2*x2", "-x1**3"), (1, "2.95"))
    with pytest.raises(UndeclaredResonanceError, match=r"within .* internal=\['1:3'\]"):
        derive_coupled(near, 1)
    one = CoupledOscillators("m", ("(1 - x1**2)*xdot1 + x2", "(1 - x2**2)*xdot2 + x1"), (1, 1))
    with pytest.raises(UndeclaredResonanceError, match=r"internal=\['1:1'\]"):
        derive_coupled(one, 1)
    # declared, it goes through
    assert derive_coupled(one, 1, internal=["1:1"]).gammas


def test_bad_models_and_orders():
    with pytest.raises(ModelError, match="2 right-hand sides but 3 frequencies"):
        CoupledOscillators("m", ("x1", "x2"), (1, 2, 3))
    with pytest.raises(ModelError, match="positive rational"):
        CoupledOscillators("m", ("x1", "x2"), (1, -2))
    with pytest.raises(ModelError, match="not a state variable"):
        CoupledOscillators("m", ("x3", "x2"), (1, 2))
    with pytest.raises(ModelError, match="not in the declared ratio 1:3"):
        CoupledOscillators("m", ("x1", "x2"), (1, 2), internal=("1:3",))
    with pytest.raises(ModelError, match="cannot read the internal resonance"):
        CoupledOscillators("m", ("x1", "x2"), (1, 3), internal=("1/3",))
    with pytest.raises(ModelError, match="reserved"):
        CoupledOscillators("m", ("a1*x1", "x2"), (1, 2))
    with pytest.raises(ModelError, match="small parameter mu"):
        CoupledOscillators("m", ("mu*x1", "x2"), (1, 2))
    with pytest.raises(OrderError):
        derive_coupled("coupled-vdp", 0)
    with pytest.raises(UnsupportedTermError, match="polynomials in the state"):
        derive_coupled(CoupledOscillators("m", ("tanh(x1)", "x2**3"), (1, sp.Rational(5, 2))), 1)
    big = CoupledOscillators("big", tuple(f"-x{i}**3" for i in range(1, 8)),
                             tuple(range(1, 8)))
    with pytest.raises(ModelError, match="above the limit"):
        derive_coupled(big, 1)
    with pytest.raises(ParameterError, match="unknown parameter .nope. for coupled-vdp"):
        derive_coupled("coupled-vdp", 1, {"nope": 1})
    with pytest.raises(ModelError, match="unknown model 'nope'"):
        get_coupled_model("nope")
