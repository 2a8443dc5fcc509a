"""Periodic orbits and locking of coupled oscillators (numerics.shooting, numerics.locking)
against independent references.

- Liouville's formula: det of the monodromy = exp of the divergence integral;
- N = 1 of the coupled shooting = the one-degree-of-freedom shooting of numerics.cycles;
- shooting against scipy's solve_ivp: the return time of x1's maximum over 30 periods;
- the Floquet multipliers against exp(mu lambda T) from the eigenvalues lambda of the
  averaged slow flow's Jacobian at its fixed point (averaging theorem, Bogoliubov &
  Mitropolsky 1961, ch. 5), and the anti-phase cycle's amplitude 2 sqrt(1 - 2c);
- the edges of the 1:1 locking region of coupled-vdp: averaged at order n against the true
  fold of the locked cycle, with errors falling like mu**n (n = 1, 2, 3);
- amplitude death: the eigenvalues of the exact linearisation against the first-order
  averaged one, (mu/2) [[1 - c, c], [c, 1 - c + 2 i sigma]].
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp
from scipy.optimize import fsolve

from kbm.model.coupled import amplitudes
from kbm.expansion.coupled import derive_coupled
from kbm.model.coupled_builtins import get_coupled_model
from kbm.errors import ParameterError
from numerics import limit_cycle
from numerics.shooting.coupled_orbit import coupled_cycle
from numerics.flow.coupled_flow import coupled_flow
from numerics.locking.mutual import amplitude_death, averaged_edges
from numerics.locking.fold import true_edges

P = {"mu": 0.02, "c": 0.3, "sigma": 0.1}


@pytest.fixture(scope="module")
def locked():
    return coupled_cycle("coupled-vdp", P)


def test_liouville(locked):
    det, expdiv = locked.liouville
    assert det == pytest.approx(expdiv, rel=1e-8)
    assert abs(locked.floquet_multipliers[0] - 1) < 1e-8
    assert len(locked.floquet_multipliers) == 4


def test_one_degree_of_freedom_is_the_one_dof_shooting():
    c = coupled_cycle("vdp", {"mu": 0.1})
    ref = limit_cycle("vdp", {"mu": 0.1})
    assert c.period == pytest.approx(ref.period, rel=1e-10)
    assert c.amplitudes[0] == pytest.approx(ref.amplitude_first_harmonic, rel=1e-8)
    assert abs(c.floquet_multipliers[1]) == pytest.approx(abs(ref.floquet_multipliers[1]),
                                                          rel=1e-7)


def test_period_against_scipy_return_times(locked):
    model = get_coupled_model("coupled-vdp")
    fl = coupled_flow(model, P)

    def rhs(t, y):
        return fl.rhs(y)

    def max_x1(t, y):
        return y[2]
    max_x1.direction = -1
    sol = solve_ivp(rhs, (0, 30.5 * locked.period), locked.state, method="DOP853",
                    rtol=1e-11, atol=1e-12, events=max_x1)
    times = sol.t_events[0]
    times = times[times > 0.5 * locked.period]
    assert len(times) == 30
    assert np.mean(np.diff(times)) == pytest.approx(locked.period, rel=1e-9)
    # and the orbit closes: the state at the 30th maximum is the start
    assert np.max(np.abs(sol.y_events[0][-1] - locked.state)) < 1e-7


def _averaged(order, values, guess):
    r = derive_coupled("coupled-vdp", order, {k: sp.nsimplify(v) for k, v in values.items()
                                              if k != "mu"})
    rates = r.slow_flow()
    state = [*amplitudes(2), sp.Symbol("gamma1")]
    f = sp.lambdify([state], [e.subs("mu", values["mu"]) for e in rates])
    J = sp.lambdify([state], sp.Matrix(rates).jacobian(state).subs("mu", values["mu"]))
    y = fsolve(lambda y: f(y), guess, xtol=1e-13)
    return y, np.linalg.eigvals(np.array(J(y), dtype=float))


def test_multipliers_from_the_averaged_jacobian(locked):
    for order, tol in ((1, 3e-5), (2, 1e-5)):
        y, ev = _averaged(order, P, [2, 2, 0.3])
        pred = np.sort(np.abs(np.exp(ev * locked.period)))
        true = np.sort(np.abs(locked.floquet_multipliers[1:]))
        assert np.allclose(pred, true, rtol=tol), (order, pred, true)
        assert locked.amplitudes == pytest.approx(y[:2], rel=5 * tol)
    assert locked.phases[1] == pytest.approx(y[2], abs=1e-3)
    assert locked.stable


def test_anti_phase_cycle_is_unstable():
    """Dissipative coupling: the anti-phase cycle, a = 2 sqrt(1 - 2c) at first order, exists
    for c < 1/2 and is unstable (a multiplier outside the unit circle)."""
    p = {"mu": 0.02, "c": 0.3, "sigma": 0}
    a = 2 * math.sqrt(1 - 2 * 0.3)
    anti = coupled_cycle("coupled-vdp", p, start=[a, -a, 0, 0], transient=0,
                         period=2 * math.pi)
    assert abs(anti.phases[1]) == pytest.approx(math.pi, abs=1e-9)
    assert anti.amplitudes[0] == pytest.approx(a, rel=2 * p["mu"] ** 2 + 1e-6)
    assert not anti.stable
    assert max(abs(anti.floquet_multipliers[1:])) > 1


@pytest.mark.slow  # 3-4 s; kept out of the default run (five-minute rule)
def test_locking_edges_converge_like_mu_to_the_order():
    """Averaged order n against the true edge at mu and mu/2: the error falls by 2**n."""
    errs = {}
    for mu in (0.1, 0.05):
        p = {"mu": mu, "c": 0.3}
        true = true_edges("coupled-vdp", p, tol=1e-9, guess={-1: -0.3, 1: 0.3})
        assert true[1].error < 1e-9
        for n in (1, 2, 3):
            avg = averaged_edges("coupled-vdp", p, n)
            errs[(n, mu)] = [abs(a.sigma - t.sigma) for a, t in zip(avg, true)]
    for n in (1, 2, 3):
        for side in (0, 1):
            ratio = errs[(n, 0.1)][side] / errs[(n, 0.05)][side]
            assert 2**n * 0.85 < ratio < 2**n * 1.15, (n, side, ratio)


def test_amplitude_death_against_the_averaged_linearisation():
    mu = 0.01
    for c, sigma, dead in ((0.3, 0.0, False), (2.0, 5.0, True), (2.0, 1.0, False)):
        out = amplitude_death("coupled-vdp", {"mu": mu, "c": c, "sigma": sigma})
        M = 0.5 * np.array([[1 - c, c], [c, 1 - c + 2j * sigma]])
        avg = np.sort(mu * np.linalg.eigvals(M).real)
        true = np.sort(np.unique(np.round([e[0] for e in out["eigenvalues"]], 12)))
        assert out["dead"] is dead
        assert np.allclose(true, avg, atol=5 * mu**2), (c, sigma, true, avg)


def test_bad_input():
    with pytest.raises(ParameterError, match="give a value to mu"):
        coupled_cycle("coupled-vdp", {"c": 0.3})
    with pytest.raises(ParameterError, match="unknown parameter .beta. for coupled-vdp"):
        coupled_cycle("coupled-vdp", {"mu": 0.1, "beta": 1})


def test_sedf_dimer_synchronisation():
    """Two SEDF sliders (paper eq. 3, v = 0) coupled by a spring mu kappa: the in-phase cycle
    is the single slider's (the spring is not stretched), the anti-phase cycle the single
    slider's with the stiffness 2 kappa added (x2 = -x1 and the potential is odd), both
    against the one-degree-of-freedom shooting; the in-phase one is stable, the anti-phase
    one unstable (mu = 0.1, Delta = 1.5, lam = 1, beta = 1, kappa = 0.5)."""
    from kbm.model.builtins import custom_model

    p = {"mu": 0.1, "Delta": 1.5, "lam": 1, "beta": 1, "kappa": 0.5}
    inphase = coupled_cycle("sedf-dimer", p, start=[1, 1, 0, 0])
    anti = coupled_cycle("sedf-dimer", p, start=[1, -1, 0, 0])
    single = limit_cycle("sedf", {"mu": 0.1, "Delta": 1.5, "lam": 1, "beta": 1})
    stiff = limit_cycle(custom_model("-(beta*x**2 - 1)*xdot - delta*sin(k*x) - 2*kappa*x"),
                        {"mu": 0.1, "beta": 1, "delta": 15, "k": 2 * math.pi, "kappa": 0.5})
    assert inphase.period == pytest.approx(single.period, rel=1e-10)
    assert anti.period == pytest.approx(stiff.period, rel=1e-10)
    assert abs(inphase.phases[1]) < 1e-9 and abs(abs(anti.phases[1]) - math.pi) < 1e-9
    assert inphase.stable and not anti.stable
    with pytest.raises(ParameterError, match="give either delta or Delta"):
        coupled_cycle("sedf-dimer", {**p, "delta": 15})


def test_sedf_chain_names():
    from kbm.model.coupled_builtins import get_coupled_model
    from kbm.errors import ModelError

    assert get_coupled_model("sedf-chain").dof == 4
    assert get_coupled_model("sedf-chain-16").dof == 16
    with pytest.raises(ModelError, match="2 to 256"):
        get_coupled_model("sedf-chain-1")


def test_an_equilibrium_is_not_a_cycle():
    """Shot from far (no transient), Newton lands on an equilibrium of the dimer: refused
    with the numbers (the motion's range, the multiplier nearest 1)."""
    from numerics.errors import ConvergenceError

    p = {"mu": 0.1, "Delta": 1.5, "lam": 1, "beta": 1, "kappa": 0.5}
    with pytest.raises(ConvergenceError, match="equilibrium, not a cycle"):
        coupled_cycle("sedf-dimer", p, start=[1, -1, 0, 0], transient=0)
