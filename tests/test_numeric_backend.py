"""The one numeric backend of one degree of freedom (:mod:`kbm.backend.sampled`, issue 35: "the
single numeric backend for any smooth F ... forced or not"), through both its cases:
:func:`kbm.numeric_derive` (no forcing angle) and :func:`kbm.backend.forced.numeric_derive_forced`
(a declared resonance).

The references are independent of the backend: the exact symbolic engine :func:`kbm.derive`
(Bogoliubov & Mitropolsky's ``A_n``, ``B_n`` of polynomial ``F``), the closed form of the
damped linear oscillator (``x = a exp(-mu zeta t) cos(sqrt(1 - mu^2 zeta^2) t)``), and the
first-order averages ``A_1 = -<F sin psi>/omega0``, ``B_1 = -<F cos psi>/(omega0 a)``
(Krylov-Bogoliubov) by a fine FFT of ``F`` along the unperturbed orbit.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from kbm import custom_model, derive, numeric_derive
from kbm.algebra.smooth import TaylorTable
from kbm.errors import UnsupportedTermError
from kbm.backend.sampled import measure, sampled_expansion
from kbm.model.forced import ForcedOscillator
from kbm.backend.forced import numeric_derive_forced
from kbm.model.builtins import get_model
from kbm.symbols import x, xdot

AA = np.linspace(0.5, 2.0, 13)
#: (phi, sigma) where the forced case is read: a theta-free F gives rates free of both
SLOW_POINTS = [(0.0, 0.0), (1.3, -0.6), (2.8, 0.9)]


def _both(F: sp.Expr, order: int, a_range=(0.4, 2.2)):
    """The unforced case and the forced case (resonance 1:1, F without theta) of one F."""
    auto = numeric_derive(custom_model(str(F)), order, a_range)
    forced = numeric_derive_forced(ForcedOscillator("as-forced", F), order, a_range)
    return auto, forced


@pytest.mark.parametrize("name, order", [("vdp", 4), ("duffing", 4), ("rayleigh", 3)])
def test_both_cases_equal_the_exact_engine(name, order):
    """Orders 1..N of van der Pol, Duffing (``F = -x^3``) and Rayleigh against the exact
    engine (Nayfeh & Mook 1979, §4.2: van der Pol's ``A_1 = a(1 - a^2/4)/2``), in both cases;
    the forced case's rates do not depend on ``phi`` or ``sigma``, and every difference is
    within ten times the error the backend reports."""
    F = get_model(name).F
    auto, forced = _both(F, order)
    fx = derive(name, order).functions("numpy")
    for n in range(1, order + 1):
        A, B = fx.A[n](AA) + 0 * AA, fx.B[n](AA) + 0 * AA
        scale = max(np.max(np.abs(A)), np.max(np.abs(AA * B)), 1.0)
        assert np.max(np.abs(auto.A[n](AA) - A)) <= max(10 * auto.A_error[n], 1e-12 * scale)
        assert np.max(np.abs(auto.B[n](AA) - B)) <= max(10 * auto.B_error[n], 1e-12 * scale)
        for phi, s in SLOW_POINTS:
            fA, fB = forced.A[n - 1](AA, phi, s), forced.B[n - 1](AA, phi, s)
            assert np.max(np.abs(fA - A)) <= max(10 * forced.A_error[n - 1], 1e-11 * scale)
            assert np.max(np.abs(fB - B)) <= max(10 * forced.B_error[n - 1], 1e-11 * scale)


def test_linear_damping_is_the_closed_form_in_both_cases():
    """``x'' + x = -2 mu zeta x'``: ``A_1 = -zeta a``, ``A_n = 0`` above, and ``B_n`` the
    mu-series of ``sqrt(1 - mu^2 zeta^2) - 1``: ``B_2 = -zeta^2/2``, ``B_4 = -zeta^4/8``,
    odd orders 0."""
    zeta = 0.3
    auto, forced = _both(-2 * zeta * xdot, 4, (0.5, 2.0))
    B = {1: 0.0, 2: -zeta**2 / 2, 3: 0.0, 4: -zeta**4 / 8}
    for n in range(1, 5):
        A = -zeta * AA if n == 1 else 0 * AA
        assert np.max(np.abs(auto.A[n](AA) - A)) < 1e-12
        assert np.max(np.abs(auto.B[n](AA) - B[n])) < 1e-12
        for phi, s in SLOW_POINTS:
            assert np.max(np.abs(forced.A[n - 1](AA, phi, s) - A)) < 1e-11
            assert np.max(np.abs(forced.B[n - 1](AA, phi, s) - B[n])) < 1e-11


def _averages(F: sp.Expr, a: np.ndarray, K: int = 4096) -> tuple[np.ndarray, np.ndarray]:
    """``A_1``, ``B_1`` (``omega0 = 1``) by the FFT of ``F(a cos psi, -a sin psi)`` on ``K``
    phases: ``F = ... + c_1 cos psi + s_1 sin psi + ...`` gives ``A_1 = -s_1/2``,
    ``B_1 = -c_1/(2 a)``."""
    f = sp.lambdify((x, xdot), F, "numpy")
    psi = 2 * np.pi * np.arange(K) / K
    spec = np.fft.rfft(f(a[:, None] * np.cos(psi), -a[:, None] * np.sin(psi)), axis=1) * 2 / K
    return spec[:, 1].imag / 2, -spec[:, 1].real / (2 * a)


@pytest.mark.parametrize("F", [-sp.tanh(xdot / sp.Rational(1, 2)) + (1 - x**2) * xdot,
                               -sp.exp(-x**2) * xdot - x**3 / (1 + x**2)])
def test_first_order_is_the_fft_average_in_both_cases(F):
    """A smooth non-polynomial ``F`` (smoothed Coulomb friction, a Gaussian damping with a
    saturating stiffness): the first order of both cases is the averaged ``F``."""
    auto, forced = _both(F, 2)
    A1, B1 = _averages(F, AA)
    assert np.max(np.abs(auto.A[1](AA) - A1)) < 1e-11
    assert np.max(np.abs(auto.B[1](AA) - B1)) < 1e-11
    for phi, s in SLOW_POINTS:
        assert np.max(np.abs(forced.A[0](AA, phi, s) - A1)) < 1e-10
        assert np.max(np.abs(forced.B[0](AA, phi, s) - B1)) < 1e-10


def test_the_run_measures_one_tail_per_axis():
    """The backend's measure: ``(scale, tails of A_n, B_n, u_n in a, u_n per angle)`` per
    order, and one relative tail per grid axis (``a``, ``psi``; with forcing also
    ``theta``), each below ``tol`` on the final grid; the grid axes are those measured."""
    tables = {0: TaylorTable((1 - x**2) * xdot)}
    run, errs, diffs = sampled_expansion(tables, 1.0, None, 0.5, 2.0, 3, 1e-10, (32, 1),
                                         (257, 2**15, 2**21), "vdp")
    assert run.alg.N == 1 and len(errs) == len(diffs) == 3
    assert all(len(e) == 5 and len(d) == 3 for e, d in zip(errs, diffs))
    _, rel = measure(run)
    assert len(rel) == 2 and max(rel) <= 1e-10
    # the size of order 1 on the grid: the larger of |A_1| = |a(1 - a^2/4)/2| and
    # |u_1| = |a^3 sin(3 psi)/32| (Nayfeh & Mook 1979, §4.2) at its points
    a, psi = run.alg.a, run.alg.psi
    size = max(np.max(np.abs(a * (1 - a**2 / 4) / 2)),
               np.max(np.abs(a[:, None]**3 * np.sin(3 * psi) / 32)))
    assert errs[0][0] == pytest.approx(size, rel=1e-12)


def test_an_F_numpy_cannot_evaluate_is_refused_in_both_cases():
    """An undefined function of ``x`` cannot be sampled: one refusal, naming ``F``."""
    g = sp.Function("g")(x)
    with pytest.raises(UnsupportedTermError, match="cannot be evaluated"):
        sampled_expansion({0: TaylorTable(g)}, 1.0, None, 0.5, 2.0, 1, 1e-10, (32, 1),
                          (257, 2**15, 2**21), "g")
    with pytest.raises(UnsupportedTermError, match="cannot be evaluated"):
        numeric_derive_forced(ForcedOscillator("g", g), 1, (0.5, 2.0))
