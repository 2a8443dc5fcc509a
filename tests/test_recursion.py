"""The one KBM recursion (kbm.expansion.recursion, issue 35): every engine runs it, over one
protocol.

- Each of the seven entries that expand an oscillator (exact one degree of freedom, its
  evaluated and numeric backends, the exact and numeric forced engines, the exact coupled
  engine and its jets) calls :func:`kbm.expansion.recursion.kbm_recursion`, seen by a profiler on
  its code object (so a private copy of the loop in any engine fails here, however it is
  imported), and returns the textbook first order: van der Pol's ``A_1 = a/2 - a**3/8``
  (Bogoliubov & Mitropolsky 1961, ch. 1), forced Duffing's ``A_1 = -zeta a - h sin(phi)/2``
  (Nayfeh & Mook 1979, eq. 4.1.18).
- Every algebra the engines pass is a :class:`~kbm.algebra.base.RecursionAlgebra` (the
  one-angle ones through :class:`~kbm.expansion.recursion.OneAngle`).
"""

from __future__ import annotations

import sys
from contextlib import contextmanager

import numpy as np
import pytest
import sympy as sp

import kbm.expansion.recursion
from kbm import derive, derive_values, numeric_derive
from kbm.algebra.base import RecursionAlgebra
from kbm.symbols import a


@contextmanager
def _calls(seen: list):
    """Record every call of :func:`kbm.expansion.recursion.kbm_recursion` (its algebra and
    order)."""
    code = kbm.expansion.recursion.kbm_recursion.__code__

    def profile(frame, event, arg):
        if event == "call" and frame.f_code is code:
            seen.append((frame.f_locals["alg"], frame.f_locals["order"]))

    old = sys.getprofile()
    sys.setprofile(profile)
    try:
        yield seen
    finally:
        sys.setprofile(old)


def _vdp_a1(av):
    return av / 2 - av**3 / 8


def _one_dof_exact():
    return float(derive("vdp", 2).A[1].subs(a, 1.5))


def _one_dof_values():
    return float(derive_values("vdp", 2, [1.5]).A[1][0])


def _one_dof_numeric():
    return float(numeric_derive("vdp", 2, (0.5, 3)).A[1](1.5))


def _forced_exact():
    from kbm.expansion.forced import derive_forced
    from kbm.model.forced import phi

    r = derive_forced("duffing-forced", 2, {"zeta": "1/10", "alpha": 1, "h": "1/2"})
    return float(r.A[0].subs({a: 1.5, phi: 0}))


def _forced_numeric():
    from kbm.backend.forced import numeric_derive_forced

    r = numeric_derive_forced("duffing-forced", 2, (0.5, 2),
                              {"zeta": 0.1, "alpha": 1, "h": 0.5})
    return float(r.A[0](1.5, 0.0, 0.0))


def _coupled_exact():
    from kbm.expansion.coupled import derive_coupled

    r = derive_coupled("coupled-vdp", 2, {"c": 0})
    return float(r.A[0][1].subs(sp.Symbol("a1"), 1.5))


def _coupled_jets():
    from kbm.model.coupled_builtins import get_coupled_model
    from kbm.backend.jets import jet_expansion

    ex = jet_expansion(get_coupled_model("coupled-vdp"), {"c": 0.0, "sigma": 0.0}, 2,
                       [1.5, 1.0], [0.3])
    return ex.A[0][0]


ENTRIES = {
    "one degree of freedom, exact": (_one_dof_exact, _vdp_a1(1.5)),
    "one degree of freedom, evaluated": (_one_dof_values, _vdp_a1(1.5)),
    "one degree of freedom, numeric": (_one_dof_numeric, _vdp_a1(1.5)),
    "forced, exact": (_forced_exact, -0.1 * 1.5),
    "forced, numeric": (_forced_numeric, -0.1 * 1.5),
    "coupled, exact": (_coupled_exact, _vdp_a1(1.5)),
    "coupled, jets": (_coupled_jets, _vdp_a1(1.5)),
}


@pytest.mark.parametrize("name", list(ENTRIES))
def test_every_engine_runs_the_one_recursion(name):
    """The entry calls kbm_recursion (to order 2) over a RecursionAlgebra, and its A_1 is the
    textbook first order (van der Pol: a/2 - a^3/8; forced Duffing at phi = 0: -zeta a)."""
    fn, expected = ENTRIES[name]
    with _calls([]) as seen:
        value = fn()
    assert seen, f"{name} did not run kbm.expansion.recursion.kbm_recursion"
    assert all(order == 2 for _, order in seen)
    assert all(isinstance(alg, RecursionAlgebra) for alg, _ in seen)
    assert np.isclose(value, expected, rtol=0, atol=1e-9)


def test_the_one_angle_adapter_is_the_case_n_equals_1():
    """OneAngle gives a FourierAlgebra the protocol of N = 1 without forcing: x0(0) is a cos
    psi, L0 = omega0 d/dpsi (so L0 x0 = -omega0 a sin psi), no detuning."""
    from kbm.algebra.poly_fourier import PolyAlgebra
    from kbm.model.builtins import get_model
    from kbm.symbols import psi

    model = get_model("duffing")
    inner = PolyAlgebra(model)
    alg = kbm.expansion.recursion.OneAngle(inner)
    assert isinstance(alg, RecursionAlgebra)
    assert alg.dof == 1 and alg.detuned is False
    w0 = model.omega0
    assert sp.simplify(inner.series_expr(alg.x0(0)) - a * sp.cos(psi)) == 0
    assert sp.simplify(inner.series_expr(alg.L0(alg.x0(0))) + w0 * a * sp.sin(psi)) == 0
