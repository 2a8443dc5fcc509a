"""The fold of the SEDF's side-well cycles continued into its Bautin point (issue 38,
:mod:`numerics.bifurcation.hopf_folds`).

The SEDF written here: ``x'' + mu (beta x^2 - 1) x' + Delta sin(2 pi x) + x = 0``
(mu = 0.1).  Independent references:

- the Bautin point from the first Lyapunov coefficient of Guckenheimer & Holmes (3.4.11)
  with the derivatives of ``f`` taken by hand: on the side well's Hopf curve
  (``x_e + Delta sin(2 pi x_e) = 0``, ``beta = 1/x_e^2``), ``16 l1 = 2 mu beta
  (4 pi^2 x_e^2/w^2 - 1)`` with ``w^2 = 1 + 2 pi Delta cos(2 pi x_e)``, so ``l1 = 0`` is the
  scalar equation ``w^2 = 4 pi^2 x_e^2`` solved by Brent's method;
- a fold of cycles has both Floquet multipliers 1: ``det M = 1`` and ``tr M = 2`` for the
  monodromy ``M`` of the SEDF shot by scipy's DOP853 with its variational equations.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from kbm import custom_model
from numerics.bifurcation.autonomous import OneDof
from numerics.bifurcation.hopf_folds import bautin_point, into_bautin

MU = 0.1


def _bautin_by_hand() -> tuple[float, float, float]:
    def delta(x):
        return -x / math.sin(2 * math.pi * x)

    def l1_zero(x):  # w^2 - 4 pi^2 x^2 on the Hopf curve
        return 1 + 2 * math.pi * delta(x) * math.cos(2 * math.pi * x) - 4 * math.pi ** 2 * x * x

    x = brentq(l1_zero, 0.95, 0.99, xtol=1e-15, rtol=1e-15)
    return x, delta(x), 1 / x ** 2


def _monodromy(x0, T, delta, beta):
    """``(x(T) - x0, x'(T), M)`` of the SEDF from ``(x0, 0)`` (scipy, variational eqs)."""
    def rhs(t, y):
        x, v = y[0], y[1]
        fx = -2 * MU * beta * x * v - 2 * math.pi * delta * math.cos(2 * math.pi * x) - 1
        fv = -MU * (beta * x * x - 1)
        P = y[2:].reshape(2, 2)
        acc = fv * v - delta * math.sin(2 * math.pi * x) - x
        return np.concatenate([[v, acc], (np.array([[0, 1], [fx, fv]]) @ P).ravel()])

    sol = solve_ivp(rhs, (0, T), [x0, 0, 1, 0, 0, 1], method="DOP853", rtol=1e-13,
                    atol=1e-15)
    y = sol.y[:, -1]
    return y[0] - x0, y[1], y[2:].reshape(2, 2)


@pytest.fixture(scope="module")
def tail():
    kit = OneDof("sedf", {"mu": "0.1", "lam": "1"}, ("Delta", "beta"), (3.0, 1.0))
    xb, ab, bb = _bautin_by_hand()
    # a start (x0, T, a, b) near where the ordinary fold system stopped (issue 38's note:
    # (5.887586, 1.055051); there that system is too singular for Newton): a cycle of size
    # 0.016 at a - a_B = 46 eps^2 (into_bautin finds the cycle, then the fold)
    eps = 0.016
    w = math.sqrt(1 + 2 * math.pi * ab * math.cos(2 * math.pi * xb))
    z = np.array([xb + eps, 2 * math.pi / w, ab + 46 * eps ** 2, bb])
    return kit, (xb, ab, bb), z, into_bautin(kit, z, bautin_point(kit, (xb, ab, bb)))


@pytest.mark.slow
def test_fold_of_cycles_ends_at_the_bautin_point(tail):
    kit, (xb, ab, bb), z, out = tail
    # the end: the Bautin point, against the one by hand (G&H 3.4.11, l1 = 0)
    assert abs(out["end"][1] - ab) < 1e-9 and abs(out["end"][2] - bb) < 1e-9
    pts = np.array(out["points"])
    assert pts[0][1] == pytest.approx(z[0] - pts[0][0], rel=1e-3)  # from the start's size
    assert abs(pts[-1][1]) == pytest.approx(1e-4, rel=1e-12)
    assert max(out["residuals"]) <= 1e-13
    # the last scaled fold point (cycle size 1e-4) within 1e-6 of the Bautin point
    assert abs(pts[-1][3] - ab) <= 1e-6 and abs(pts[-1][4] - bb) <= 1e-6
    # the fold curve leaves the Bautin point like eps^2 (Kuznetsov sec. 8.3): (a - a_B)/eps^2
    # is nearly constant (46) from eps = 1e-3 down; at eps = 1e-4 within 2e-8 of c eps^2
    ratio = (pts[:, 3] - ab) / pts[:, 1] ** 2
    assert np.ptp(ratio[1:-1]) < 0.01 * abs(ratio[1])
    assert abs(pts[-1][3] - ab - ratio[-2] * pts[-1][1] ** 2) < 2e-8
    assert np.all(np.diff(np.abs(pts[:, 1])) < 0)


@pytest.mark.slow
def test_scaled_fold_point_is_a_true_fold_of_cycles(tail):
    kit, (xb, ab, bb), z, out = tail
    xe, eps, T, a, b = out["points"][1]
    gx, gv, M = _monodromy(xe + eps, T, a, b)
    assert abs(gx) < 1e-12 and abs(gv) < 1e-10  # a cycle
    # both multipliers 1 (the trivial one and the fold's): det M = 1, tr M = 2
    assert abs(np.linalg.det(M) - 1) < 1e-9 and abs(np.trace(M) - 2) < 1e-8
    # off the fold (b moved by 1e-5 off its cycle, a cycle of the same size re-found) the
    # test would fail: the non-trivial multiplier moves by far more than the tolerance
    _, _, M2 = _monodromy(xe + 4 * eps, T, a, b)
    assert abs(np.linalg.det(M2) - 1) > 1e-6


def test_bautin_point_against_the_one_by_hand():
    kit = OneDof("sedf", {"mu": "0.1", "lam": "1"}, ("Delta", "beta"), (3.0, 1.0))
    xb, ab, bb = _bautin_by_hand()
    x, a, b = bautin_point(kit, (xb + 1e-3, ab + 1e-2, bb - 1e-3))
    assert abs(x - xb) < 1e-12 and abs(a - ab) < 1e-10 and abs(b - bb) < 1e-12
    assert (a, b) == pytest.approx((5.876790, 1.055155), abs=1e-6)  # issue 38's note


def test_extended_precision_runge_kutta_on_the_harmonic_oscillator():
    """The scaled flow's integrator on a harmonic oscillator (``f = -w^2 x``, ``w^2 = -f_x``
    from the model): after one period ``2 pi/w`` the state is ``(1, 0)`` again to the
    extended precision, and the divergence integral is 0."""
    from numerics.bifurcation.hopf_folds import _A, _B, ScaledFold

    c = _A.sum(axis=1)
    L = np.longdouble
    assert abs(_B.sum() - 1) < 1e-18 and abs(_B @ c - L(1) / 2) < 1e-18
    assert abs(_B @ (c * c) - L(1) / 3) < 1e-18 and abs(_B @ (_A @ c) - L(1) / 6) < 1e-18
    kit = OneDof(custom_model("-c*x + nu*xdot"), {"mu": "1"}, ("nu", "c"), (0.0, 4.0))
    w = math.sqrt(-kit.d(1, 0, 0.0, 0.0, 0.0, 4.0))
    for eps in (1e-3, 0.1):  # the Taylor series and the direct field
        T = 2 * math.pi / w
        r = ScaledFold(kit, 400).G([0.0, eps, T, 0.0, 4.0])
        assert max(abs(r[0]), abs(r[1]), abs(r[3])) < 1e-17
        assert abs(r[2]) < 4 * w * w * np.spacing(T)  # T is a float: w(T) = -w^2 u dT
        r = ScaledFold(kit, 400).G([0.0, eps, 2 * math.pi / w * (1 + 1e-9), 0.0, 4.0])
        assert np.max(np.abs(r)) > 1e-9  # a period off by 1e-9 is seen


def test_no_bautin_point_is_said_in_plain_numbers():
    """``x'' + x = mu ((c - x^2) - g^2 x^2) x'``: on its Hopf line c = 0 (x_e = 0) the first
    Lyapunov coefficient has the sign of ``F_xxv = -2 mu (1 + g^2) < 0`` for every g
    (Guckenheimer & Holmes (3.4.11), no quadratic terms), so Newton finds no Bautin point;
    the message gives the guess as plain numbers (it printed ``[np.float64(0.0), ...]``)."""
    from kbm.errors import KBMError

    model = custom_model("(c - x**2)*xdot - g**2*x**2*xdot", name="no_bautin")
    kit = OneDof(model, {"mu": "0.1"}, ("c", "g"), (0.0, 1.0))
    with pytest.raises(KBMError, match=r"no Bautin point near \(x_e, a, b\) = \(0, 0, 1\): "
                                       r"residual [0-9.e-]+ ") as err:
        bautin_point(kit, [np.float64(0.0), np.float64(0.0), np.float64(1.0)])
    assert "np." not in str(err.value) and "[" not in str(err.value)
