"""The numeric backend of any ``N`` (Taylor jets on the torus, :mod:`kbm.backend.jets`) at
``N = 1`` is the one-degree-of-freedom numeric backends' expansion.

Issue 35 asks for one numeric backend for any smooth ``F``, any ``N``, forced or not, with
one degree of freedom a case of it.  The jets (any ``N``, at one point ``a*``, exact
derivatives in ``a``) and the one-degree backends (Chebyshev grids in ``a``:
:func:`kbm.numeric_derive`, :func:`kbm.backend.forced.numeric_derive_forced`; Jacobi-Anger jets at
given amplitudes: :func:`kbm.derive_values`) run the one recursion
(:func:`kbm.expansion.recursion.kbm_recursion`) over different sampled algebras, so each is a
second method for the other: Bogoliubov & Mitropolsky's ``A_n``, ``B_n`` of the same ``F`` agree
to rounding.
"""

from __future__ import annotations

import pytest

from kbm import custom_model, derive_values, numeric_derive
from kbm.backend.coupled import numeric_average
from kbm.backend.forced import numeric_derive_forced


@pytest.mark.parametrize("model,params,order", [
    ("vdp", {}, 4),
    (custom_model("-tanh(xdot/0.5) + (1 - x**2)*xdot"), {}, 3),
])
def test_one_degree_interval_backend(model, params, order):
    """``x'' + x = mu F(x, x')``: the jets at ``a* = 1.5`` against the Chebyshev interval
    backend (van der Pol's ``A_1 = a(1 - a^2/4)/2`` among them)."""
    ex = numeric_average(model, params).expansion([1.5], [], order)
    ref = numeric_derive(model, order, (0.5, 3), params)
    if model == "vdp":  # the closed form of the first order
        assert ex.A[0][0] == pytest.approx(1.5 / 2 * (1 - 1.5**2 / 4), abs=1e-13)
    for n in range(1, order + 1):
        assert ex.A[0][n - 1] == pytest.approx(float(ref.A[n](1.5)), abs=1e-12)
        assert ex.B[0][n - 1] == pytest.approx(float(ref.B[n](1.5)), abs=1e-12)


def test_one_degree_bessel_values():
    """The SEDF (``sin(k x)``, Jacobi-Anger sums) at order 4: the jets against
    :func:`kbm.derive_values` at three amplitudes."""
    p = {"beta": 1.0, "delta": 0.5, "k": 2.0}
    avg = numeric_average("sedf", p)
    ref = derive_values("sedf", 4, [0.7, 1.5, 2.2], p)
    for q, a in enumerate(ref.a):
        ex = avg.expansion([float(a)], [], 4)
        for n in range(1, 5):
            assert ex.A[0][n - 1] == pytest.approx(ref.A[n][q], abs=1e-12)
            assert ex.B[0][n - 1] == pytest.approx(ref.B[n][q], abs=1e-12)


def test_forced_one_degree():
    """Forced Duffing at the primary resonance, order 3: the jets' slow phase is
    ``gamma = theta - psi = -phi`` of :mod:`kbm.expansion.forced`
    (``A_1 = -zeta a - h sin(phi)/2``)."""
    vals = {"zeta": 0.1, "alpha": 1, "h": 1}
    ex = numeric_average("duffing-forced", {**vals, "sigma": 0.2}).expansion([1.2], [0.3], 3)
    ref = numeric_derive_forced("duffing-forced", 3, (0.5, 2), vals)
    for n in range(3):
        assert ex.A[0][n] == pytest.approx(float(ref.A[n](1.2, -0.3, 0.2)), abs=1e-12)
        assert ex.B[0][n] == pytest.approx(float(ref.B[n](1.2, -0.3, 0.2)), abs=1e-12)


def test_autonomous_is_the_forced_grid_without_theta():
    """One grid algebra and one driver for one degree of freedom, forced or not: van der
    Pol given to the forced backend (a forcing angle that ``F`` does not hold, resonance
    1:1) has rates independent of ``phi`` and ``sigma``, equal to the autonomous backend's
    (the same grid algebra without the forcing angle) and to the closed form
    ``A_1 = a(1 - a^2/4)/2``, ``B_2 = -(1 - a^2 + 7a^4/32)/8`` (Nayfeh & Mook 1979, §4.2)."""
    import numpy as np
    from kbm.model.forced import ForcedOscillator
    from kbm.symbols import x, xdot

    forced = numeric_derive_forced(ForcedOscillator("vdp-as-forced", (1 - x**2) * xdot), 3,
                                   (0.5, 2.5))
    auto = numeric_derive("vdp", 3, (0.5, 2.5))
    a = np.array([0.6, 1.3, 2.0, 2.4])
    assert auto.A[1](a) == pytest.approx(a * (1 - a**2 / 4) / 2, abs=1e-12)
    assert auto.B[2](a) == pytest.approx(-(1 - a**2 + 7 * a**4 / 32) / 8, abs=1e-12)
    for phi, s in [(0.0, 0.0), (1.1, -0.7), (2.9, 0.4)]:
        for n in range(3):
            assert forced.A[n](a, phi, s) == pytest.approx(auto.A[n + 1](a), abs=1e-11)
            assert forced.B[n](a, phi, s) == pytest.approx(auto.B[n + 1](a), abs=1e-11)
