"""Period doublings on a forced branch (numerics.shooting.special, issue 25) against plain
shooting.

The Duffing oscillator x'' + x = mu (-2 zeta x' - alpha x^3 + h cos nu t) at mu = 1,
zeta = 0.05, alpha = 1, h = 20 (strong forcing) has, on its period-1 branch, responses with
a multiplier below -1 for nu between 1.17 and 1.50: the continuation's test function
(1 + lambda_1)(1 + lambda_2) locates the period doublings; the reference is a separate
scipy solve_ivp shooting (Newton on the period map, the monodromy from its own variational
equations) with Brent on lambda_min(sigma) + 1.  With a damping that does not depend on the
state, det Phi = exp(-2 zeta mu T) < 1 (Liouville): no Neimark-Sacker point can occur, and
none is reported.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from numerics.flow.forced_system import ForcedSystem
from numerics.shooting.forced_branch import continue_response
from numerics.shooting.forced_orbit import periodic_response
from numerics.shooting.special import detect_special
from _references import duffing_lambda_min

VALS = {"mu": 1, "zeta": 0.05, "alpha": 1, "h": 20}


def test_period_doublings_on_a_forced_duffing_branch():
    system = ForcedSystem("duffing-forced", VALS)
    y = np.zeros(2)
    for _ in range(200):  # the attracting response at nu = 2
        y = system.flow(y, 1.0, extended=False)[-1][:2]
    start = periodic_response(system, 1.0, y)
    branch, _ = continue_response(system, start, (-0.6, 1.2), n_points=200)
    special = detect_special(system, branch)
    kinds = [sp.kind for sp in special]
    assert kinds == ["period-doubling", "period-doubling"], kinds
    for sp in special:
        assert min(m.real for m in sp.orbit.multipliers) == pytest.approx(-1, abs=1e-6)
        ref = brentq(lambda s: duffing_lambda_min(s, sp.orbit.y0) + 1,
                     sp.orbit.sigma - 0.01, sp.orbit.sigma + 0.01, xtol=1e-12)
        assert sp.orbit.sigma == pytest.approx(ref, abs=1e-7)
        assert sp.bracket[1] - sp.bracket[0] < 1e-9


def _averaged_hopf(order, mu, h, a0, s0):
    """The Hopf point of the order-n slow flow of the forced van der Pol oscillator (the
    fixed point, a' = 0 and phi' = 0, where the Jacobian's trace vanishes) nearest the
    detuning s0, from starts at eight phases."""
    import sympy as sp
    from scipy.optimize import fsolve

    from kbm.expansion.forced import derive_forced

    a, phi, sig, m = sp.symbols("a phi sigma mu")
    r = derive_forced("vdp-forced", order)
    A = sum(m**n * r.A[n - 1] for n in range(1, order + 1)).subs({"h": h, m: mu})
    P = (-m * sig + sum(m**n * r.B[n - 1] for n in range(1, order + 1))).subs({"h": h, m: mu})
    tr = sp.Matrix([A, P]).jacobian([a, phi]).trace()
    eqs = sp.lambdify([[a, phi, sig]], [A, P, tr])
    roots = []
    for p0 in np.linspace(-math.pi, math.pi, 8, endpoint=False):
        z, info, ok, _ = fsolve(lambda z: eqs(z), [a0, p0, s0], xtol=1e-13, full_output=True)
        if ok == 1 and z[0] > 0 and np.max(np.abs(eqs(z))) < 1e-10:
            roots.append(z)
    return min(roots, key=lambda z: abs(z[2] - s0))


def test_neimark_sacker_of_the_forced_van_der_pol_against_the_averaged_hopf():
    """Forced van der Pol, h = 2: at the edges of entrainment the locked response loses
    stability to a torus (a complex pair through the unit circle); averaged, the slow flow's
    fixed point has a Hopf bifurcation there.  The true points (continuation + test
    function) against the averaged ones at orders 1 and 2: errors fall like mu and mu^2."""
    from kbm.expansion.forced import derive_forced
    from numerics.shooting.forced_branch import numeric_response

    errors = {}
    for mu in (0.05, 0.025):
        vals = {"mu": mu, "h": 2.0}
        sf = derive_forced("vdp-forced", 1).slow_flow(vals, order=1)
        nr = numeric_response(ForcedSystem("vdp-forced", vals), sf, (-2, 2), (1e-3, 4),
                              n_points=200)
        ns = [sp.orbit for sp in nr.special if sp.kind == "neimark-sacker"]
        assert len(ns) == 2 and ns[0].sigma < 0 < ns[1].sigma
        for o in ns:
            assert abs(o.multipliers[0]) == pytest.approx(1, abs=1e-7)
            assert abs(o.multipliers[0].imag) > 1e-3
            for order in (1, 2):
                z = _averaged_hopf(order, mu, 2.0, o.amplitude, o.sigma)
                errors[(order, mu, o.sigma < 0)] = abs(z[2] - o.sigma)
    for side in (True, False):
        r1 = errors[(1, 0.05, side)] / errors[(1, 0.025, side)]
        r2 = errors[(2, 0.05, side)] / errors[(2, 0.025, side)]
        assert 1.7 < r1 < 2.3 and 3.4 < r2 < 4.6, (side, r1, r2)
        assert errors[(2, 0.025, side)] < 1e-3


def test_neimark_sacker_on_the_driven_slider():
    """The driven slider (the paper's eq. 3 seen from its stage, ``slider``: x'' + x =
    mu ((1 - x^2)(x' + nu) - delta sin(x + nu t)), k = 1, mu = 0.05, delta = 1): the
    self-oscillation locked to the washboard loses stability to a torus at the edge of
    locking.  Located by two continuations with their own test functions (the coupled
    family's, N = 1, and numerics.shooting.forced_branch's), and checked by direct
    integration (scipy):
    0.01 inside, the stroboscopic samples converge to the locked response; 0.01 outside,
    they spread over the torus."""
    from numerics.shooting.coupled_branch import continue_coupled

    vals = {"mu": 0.05, "delta": 1, "k": 1}
    br = continue_coupled("slider", {**vals, "sigma": 0.03}, "sigma", (0.03, 0.13))
    ns = [s for s in br.special if s.kind == "neimark-sacker"]
    assert len(ns) == 1
    s_ns = ns[0]
    assert all(abs(abs(z) - 1) < 1e-8 and abs(z.imag) > 1e-3 for z in s_ns.floquet_multipliers)
    assert s_ns.bracket[1] - s_ns.bracket[0] < 1e-8

    system = ForcedSystem("slider", vals)
    first = br.points[0]
    start = periodic_response(system, first.parameter, np.array(first.state))
    branch, _ = continue_response(system, start, (0.03, 0.13), n_points=100)
    other = [q for q in detect_special(system, branch) if q.kind == "neimark-sacker"]
    assert len(other) == 1 and other[0].orbit.sigma == pytest.approx(s_ns.parameter, abs=1e-8)

    mu = vals["mu"]

    def spread(sig):
        nu = 1 + mu * sig
        T = 2 * math.pi / nu

        def f(t, y):
            return [y[1], -y[0] + mu * ((1 - y[0] ** 2) * (y[1] + nu) - math.sin(y[0] + nu * t))]

        ts = (1500 + np.arange(150)) * T
        sol = solve_ivp(f, (0, ts[-1]), [1.5, 0.0], t_eval=ts, method="DOP853", rtol=1e-10,
                        atol=1e-12)
        return float(np.ptp(sol.y[0]))

    stable_side = [p.stable for p in br.points if p.parameter < s_ns.parameter - 0.005]
    assert all(stable_side) and not any(p.stable for p in br.points
                                        if p.parameter > s_ns.parameter + 0.005)
    assert spread(s_ns.parameter - 0.01) < 1e-6
    assert spread(s_ns.parameter + 0.01) > 0.5
