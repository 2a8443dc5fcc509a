"""Forced coupled systems: the forcing angle theta = nu t as one more angle of the coupled
recursion.

- N = 1 with forcing is the forced recursion of kbm.expansion.forced, exactly to order 3, for
  every polynomial forced built-in (primary, superharmonic, parametric resonances): both run
  the coupled algebra, derive_coupled through its own hard-forcing shift (_hard_shifted),
  resonance declaration and gamma = q theta - p psi, derive_forced through the model's
  shift and its result in phi; the forced engine's own references (closed forms, Nayfeh &
  Mook) are in tests/test_forced_engine.py and tests/test_forced_mathieu.py;
- the saturation of quadratic coupling in 1:2 internal resonance forced near the higher
  mode (Nayfeh & Mook 1979, sec. 6.5.1): the directly excited mode's amplitude is
  a2 = (2 omega1/alpha1) sqrt(4 zeta1^2 + s^2), s = (nu - 2 omega1)/mu, whatever the
  forcing (closed form, derived in the docstring of test_saturation), while the other mode
  absorbs the energy; against shooting at the period 2 x 2 pi/nu, with the averaged
  errors falling like mu (order 1) and mu^2 (order 2).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp
from scipy.optimize import fsolve

from kbm.model.coupled import amplitudes
from kbm.expansion.coupled import derive_coupled
from kbm.expansion.forced import derive_forced
from kbm.model.forced_builtins import get_forced_model
from numerics.shooting.coupled_orbit import forced_response


@pytest.mark.parametrize("name", ["duffing-forced", "duffing-super", "mathieu", "vdp-forced",
                                  "parametric", "mathieu-2", "mathieu-3",
                                  "duffing-super-hard", "duffing-sub-hard"])
def test_forced_one_dof_is_the_forced_recursion(name):
    """gamma = q theta - p psi of the coupled engine is -p phi of kbm.expansion.forced; with a hard
    forcing (N&M 4.1.2-4.1.3) both shift x by Lambda cos(theta) (Lambda1 here)."""
    fm = get_forced_model(name)
    f = derive_forced(name, 3)
    c = derive_coupled(fm, 3)
    phi, g, a, a1, lam, lam1 = sp.symbols("phi gamma1 a a1 Lambda Lambda1")
    p = fm.resonance.p
    for n in range(1, 4):
        for mine, theirs in ((c.A[0][n], f.A[n - 1]), (c.B[0][n], f.B[n - 1])):
            mine = mine.subs(g, -p * phi).subs({a1: a, lam1: lam})
            diff = sp.expand(sp.expand_trig(mine - theirs))
            assert sp.simplify(diff) == 0, (name, n, diff)


def test_hard_forcing_of_coupled_systems():
    """Two Duffings, the first hard-forced near nu = omega1/3 (superharmonic): N = 2 with
    the second oscillator uncoupled gives the first's rates of the one-degree-of-freedom
    forced engine; a hard forcing at its mode's frequency, or without nu0, is refused."""
    from kbm.model.coupled import CoupledOscillators
    from kbm.errors import ModelError, ParameterError

    two = CoupledOscillators("two", ("-2*zeta*xdot1 - alpha*x1**3",
                                     "-2*zeta*xdot2 - alpha*x2**3"), (1, 2), nu0=sp.Rational(1, 3),
                             nu_detuning="sigma", internal=("3:1@1,F",), hard=("K", 0))
    c = derive_coupled(two, 2)
    f = derive_forced("duffing-super-hard", 2)
    phi, g, a, a1, lam, lam1 = sp.symbols("phi gamma1 a a1 Lambda Lambda1")
    for n in (1, 2):
        mine = c.A[0][n].subs(g, -phi).subs({a1: a, lam1: lam})
        assert sp.simplify(sp.expand(sp.expand_trig(mine - f.A[n - 1]))) == 0
    with pytest.raises(ParameterError, match="resonant at nu = omega1"):
        derive_coupled(CoupledOscillators("r", ("-x1**3",), (1,), nu0=1, hard=("K",)), 1)
    with pytest.raises(ModelError, match="needs the forcing frequency"):
        CoupledOscillators("r", ("-x1**3",), (1,), hard=("K",))


P = {"zeta1": 0.5, "zeta2": 0.5, "alpha1": 1, "alpha2": 1, "sigma1": 0, "sigma2": 1.0}


def _fixed_point(order, mu, h, guess=(6.3, 2.9, -0.8, 0.5)):
    vals = {k: sp.nsimplify(v) for k, v in P.items() if not k.startswith("sigma")}
    r = derive_coupled("quadratic-1-2", order, {**vals, "h": h})
    st = [*amplitudes(2), sp.Symbol("gamma1"), sp.Symbol("gamma2")]
    rates = [e.subs({"sigma1": P["sigma1"], "sigma2": P["sigma2"], "mu": mu})
             for e in r.slow_flow()]
    f = sp.lambdify([st], rates)
    return fsolve(lambda y: f(y), guess, xtol=1e-13)


def test_saturation():
    """At a steady state with a1 != 0: a1' = 0 gives sin(gamma1) = -4 omega1 zeta1/(alpha1
    a2); mode 1 answers at nu/2, so psi1' = nu/2, B_1 = s/2 = alpha1 a2 cos(gamma1)/(4
    omega1): cos(gamma1) = 2 omega1 s/(alpha1 a2); hence a2 = (2 omega1/alpha1) sqrt(4 zeta1^2
    + s^2), independent of h (omega1 = 1, alpha1 = 1, zeta1 = 1/2, s = 1: 2 sqrt 2)."""
    closed = 2 * math.sqrt(4 * P["zeta1"] ** 2 + P["sigma2"] ** 2)
    err = {}
    for h in (20.0, 30.0):
        y = _fixed_point(1, 0.02, h)
        assert y[1] == pytest.approx(closed, abs=1e-10)  # saturated: the same for both h
        for mu in (0.02, 0.01):
            true = forced_response("quadratic-1-2", {**P, "mu": mu, "h": h})
            assert true.stable and true.multiple == 2
            assert true.liouville[0] == pytest.approx(true.liouville[1], rel=1e-8)
            y2 = _fixed_point(2, mu, h)
            err[(h, mu)] = (abs(true.amplitudes[1] - closed), abs(true.amplitudes[1] - y2[1]),
                            true.amplitudes[0])
    for h in (20.0, 30.0):
        e1 = err[(h, 0.02)][0] / err[(h, 0.01)][0]
        e2 = err[(h, 0.02)][1] / err[(h, 0.01)][1]
        assert 1.7 < e1 < 2.3 and 3.4 < e2 < 4.6, (h, e1, e2)
    # the energy goes into the other mode: a1 grows with the forcing, a2 does not
    assert err[(30.0, 0.01)][2] > err[(20.0, 0.01)][2] + 1.0


def test_below_threshold_the_first_mode_is_quiet():
    """Below h_c the response is the linear one of mode 2, a2 = h/(2 omega2 sqrt(zeta2^2 +
    s^2)), and mode 1 stays at rest."""
    true = forced_response("quadratic-1-2", {**P, "mu": 0.02, "h": 2.0})
    assert true.amplitudes[0] < 1e-6
    assert true.amplitudes[1] == pytest.approx(2.0 / (4 * math.hypot(0.5, 1.0)), rel=0.05)
    assert np.all(np.abs(true.floquet_multipliers) < 1)
