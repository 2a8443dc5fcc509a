"""The forced response of two cubic oscillators in 1:3 internal resonance (duffing-1-3,
Nayfeh & Mook 1979, sec. 6.6.2), the second mode forced near its frequency, against the
textbook's first-order modulation equations and against shooting (issue 23).

x1'' + x1 = mu (-2 zeta1 x1' - alpha1 x1^3 - 3 k x1^2 x2),
x2'' + 9 x2 = mu (-2 zeta2 x2' - alpha2 x2^3 - k x1^3 + h cos nu t), nu = 3 + mu sigma.

With x_i = a_i cos psi_i, gamma1 = psi2 - 3 psi1 and gamma2 = nu t - psi2, first-order
averaging by hand (the textbook's equations, omega1 = 1, omega2 = 3) gives

a1' = mu (-zeta1 a1 - 3 k a1^2 a2 sin(gamma1)/8),
a2' = mu (-zeta2 a2 + k a1^3 sin(gamma1)/24 + h sin(gamma2)/6),
psi1' - 1 = mu (3 alpha1 a1^2/8 + 3 k a1 a2 cos(gamma1)/8),
psi2' - 3 = mu (alpha2 a2^2/8 + k a1^3 cos(gamma1)/(24 a2) - h cos(gamma2)/(6 a2)).

Mode 1 is not excited linearly (its forcing through x1^2 x2 is quadratic in a1): a1 = 0
is always a response, and the one with both modes at work lies on another branch, which
the shooting is started on from the averaged fixed point.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp
from scipy.optimize import fsolve

from kbm.expansion.coupled import derive_coupled
from kbm.model.variables import amplitudes
from numerics.shooting.coupled_orbit import forced_response

VALS = {"zeta1": sp.Rational(1, 10), "zeta2": sp.Rational(1, 10), "alpha1": 1, "alpha2": 1,
        "k": 1}
H, SIGMA = 6.0, 0.0


def _state():
    return [*amplitudes(2), sp.Symbol("gamma1"), sp.Symbol("gamma2")]


def test_first_order_is_the_textbooks():
    a1, a2 = amplitudes(2)
    g1, g2, m, h, s = sp.symbols("gamma1 gamma2 mu h sigma")
    z1, z2, al1, al2, k = sp.symbols("zeta1 zeta2 alpha1 alpha2 k")
    r = derive_coupled("duffing-1-3", 1)
    rate1 = -z1 * a1 - 3 * k * a1**2 * a2 * sp.sin(g1) / 8
    rate2 = -z2 * a2 + k * a1**3 * sp.sin(g1) / 24 + h * sp.sin(g2) / 6
    B1 = 3 * al1 * a1**2 / 8 + 3 * k * a1 * a2 * sp.cos(g1) / 8
    B2 = al2 * a2**2 / 8 + k * a1**3 * sp.cos(g1) / (24 * a2) - h * sp.cos(g2) / (6 * a2)
    book = [m * rate1, m * rate2, m * (B2 - 3 * B1), m * (s - B2)]  # gamma2 = nu t - psi2
    for ours, ref in zip(r.slow_flow(), book):
        assert sp.simplify(sp.expand(ours - ref)) == 0, (ours, ref)


def _fixed_point(order, mu, guess):
    r = derive_coupled("duffing-1-3", order, VALS)
    rates = [e.subs({"h": H, "sigma": SIGMA, "mu": mu}) for e in r.slow_flow()]
    f = sp.lambdify([_state()], rates)
    jac = sp.lambdify([_state()], sp.Matrix(rates).jacobian(_state()))
    z = fsolve(f, guess, xtol=1e-13)
    assert np.max(np.abs(f(z))) < 1e-12
    return z, np.linalg.eigvals(np.array(jac(z), dtype=float))


def test_forced_response_with_both_modes_against_shooting():
    """The stable averaged state with a1 != 0 (h = 6, sigma = 0, zeta = 0.1) against the true
    periodic response of period 3 x 2 pi/nu, shot from it: order 1 errs like mu, order 2
    like mu^2."""
    guess = [2.26, 2.26, -3.09, 0.25]
    errs = {}
    for mu in (0.02, 0.01, 0.005):
        z1, ev = _fixed_point(1, mu, guess)
        assert np.all(ev.real < 0)  # the averaged state is stable
        z2, _ = _fixed_point(2, mu, z1)
        a1, a2, g1, g2 = z1
        psi2 = -g2
        psi1 = (psi2 - g1) / 3
        y0 = [a1 * math.cos(psi1), a2 * math.cos(psi2), -a1 * math.sin(psi1),
              -3 * a2 * math.sin(psi2)]
        true = forced_response("duffing-1-3", {**{k: float(v) for k, v in VALS.items()},
                                               "mu": mu, "h": H, "sigma": SIGMA},
                               start=y0, transient_periods=0)
        assert true.stable and true.multiple == 3
        assert true.liouville[0] == pytest.approx(true.liouville[1], rel=1e-8)
        assert true.amplitudes[0] > 2.0  # both modes at work
        errs[mu] = (np.max(np.abs(true.amplitudes - z1[:2])),
                    np.max(np.abs(true.amplitudes - z2[:2])))
    for big, small in ((0.02, 0.01), (0.01, 0.005)):
        r1 = errs[big][0] / errs[small][0]
        r2 = errs[big][1] / errs[small][1]
        assert 1.7 < r1 < 2.3, errs
        assert 2.9 < r2 < 4.6, errs
    assert errs[0.005][1] < 5e-4
