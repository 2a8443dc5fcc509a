"""Scaling symmetries of the KBM expansion (exact identities the recursion must respect).

1. Amplitude scaling.  For ``F = (1 - beta x^2) x'`` the substitution ``x = y/sqrt(beta)``
   maps the model onto van der Pol, so ``A_n(a; beta) = A_n^vdP(sqrt(beta) a)/sqrt(beta)``,
   ``B_n(a; beta) = B_n^vdP(sqrt(beta) a)`` and
   ``u_n(a, psi; beta) = u_n^vdP(sqrt(beta) a, psi)/sqrt(beta)``.
2. Time scaling.  ``x'' + w^2 x = eps F(x, x')`` with ``tau = w t`` is
   ``x_tautau + x = (eps/w^2) F(x, w x_tau)``, so
   ``A_n = w^(1 - 2n) A~_n`` and ``B_n = w^(1 - 2n) B~_n`` where ``~`` is the expansion of
   ``F~(x, y) = F(x, w y)`` with ``w = 1``.
"""

from __future__ import annotations

import sympy as sp
from hypothesis import given, strategies as st

from kbm import custom_model, derive

a, psi = sp.symbols("a psi")
beta, w = sp.Symbol("beta"), sp.Symbol("w")


@given(st.integers(min_value=1, max_value=5))
def test_amplitude_scaling_maps_onto_van_der_pol(order):
    """x = y/sqrt(beta) maps (1 - beta x^2) x' onto van der Pol at every order."""
    res = derive(custom_model("(1 - beta*x**2)*xdot"), order)
    vdp = derive("vdp", order)
    s = sp.sqrt(beta)
    for n in range(1, order + 1):
        assert sp.simplify(res.A[n] - vdp.A[n].subs(a, s * a) / s) == 0
        assert sp.simplify(res.B[n] - vdp.B[n].subs(a, s * a)) == 0
        assert sp.simplify(sp.expand(res.u[n] - vdp.u[n].subs(a, s * a) / s)) == 0


@given(st.sampled_from(["(1 - x**2)*xdot", "-x**3", "(1 - xdot**2/3)*xdot",
                        "-x**2 + x*xdot", "-x**3 - 2*xdot + x**2*xdot"]),
       st.integers(min_value=1, max_value=4))
def test_time_scaling_of_omega0(F, order):
    """omega0 = w is equivalent to F(x, w y)/w^2 with omega0 = 1 and time measured in 1/w."""
    with_w = derive(custom_model(F, omega0=w), order)
    Ft = sp.sympify(F, locals={"x": sp.Symbol("x"), "xdot": sp.Symbol("xdot")}).subs(
        sp.Symbol("xdot"), w * sp.Symbol("xdot"))
    scaled = derive(custom_model(Ft), order)
    for n in range(1, order + 1):
        assert sp.simplify(with_w.A[n] - w**(1 - 2 * n) * scaled.A[n]) == 0
        assert sp.simplify(with_w.B[n] - w**(1 - 2 * n) * scaled.B[n]) == 0
        assert sp.simplify(sp.expand(with_w.u[n] - w**(-2 * n) * scaled.u[n])) == 0
