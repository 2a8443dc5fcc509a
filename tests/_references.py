"""Independent references shared by several test modules (not tests themselves).

- :func:`duffing_lambda_min`: the smallest real part of the Floquet multipliers of the
  period-1 response of x'' + 0.1 x' + x + x^3 = 20 cos(nu t), nu = 1 + sigma, by a plain
  scipy shooting (Newton on the period map with its own variational equations): the
  reference for the period doublings of the strongly forced Duffing oscillator;
- :func:`duffing_floquet`: that shooting for any damping, cubic stiffness and forcing;
- :func:`forced_floquet`: the shooting itself, for any forced ``x'' = accel(t, x, x')``.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp


def forced_floquet(accel, jac, T, y0, rtol=1e-12, tol=1e-12, steps=30):
    """The ``T``-periodic response near ``y0`` of ``x'' = accel(t, x, x')`` and its Floquet
    multipliers, by scipy alone: Newton on the period map, the monodromy from the
    variational equations (``jac(x, x')`` the 2x2 Jacobian), DOP853 at ``rtol``, until a
    correction is below ``tol``."""
    def f(t, Y):
        x, v = Y[0], Y[1]
        P = Y[2:].reshape(2, 2)
        return np.concatenate([[v, accel(t, x, v)], (jac(x, v) @ P).ravel()])

    y = np.array(y0, float)
    for _ in range(steps):
        s = solve_ivp(f, (0, T), np.concatenate([y, np.eye(2).ravel()]), method="DOP853",
                      rtol=rtol, atol=1e-12)
        yT, P = s.y[:2, -1], s.y[2:, -1].reshape(2, 2)
        dy = np.linalg.solve(P - np.eye(2), -(yT - y))
        y = y + dy
        if np.max(np.abs(dy)) < tol:
            break
    return y, np.linalg.eigvals(P)


def duffing_floquet(nu, damping, cubic, force, y0):
    """The period-1 response near ``y0`` of ``x'' + damping x' + x + cubic x^3 = force
    cos(nu t)`` and its Floquet multipliers (:func:`forced_floquet`, rtol 1e-12)."""
    return forced_floquet(
        lambda t, x, v: -x - cubic * x**3 - damping * v + force * math.cos(nu * t),
        lambda x, v: np.array([[0.0, 1.0], [-1 - 3 * cubic * x * x, -damping]]),
        2 * math.pi / nu, y0)


def duffing_lambda_min(sigma, y0):
    return float(np.min(duffing_floquet(1 + sigma, 0.1, 1.0, 20.0, y0)[1].real))


def section_cycle(rhs, x0: float, T: float) -> tuple[float, float]:
    """``(x0, T)`` of the periodic orbit of the planar field ``rhs(t, w)`` through ``(x0, 0)``
    (the section ``x' = 0``): Newton on ``(x0, T)`` with finite-difference columns, the
    orbit by scipy's DOP853 at rtol 1e-11 (an integrator independent of the package's)."""
    def end(x0, T):
        s = solve_ivp(rhs, (0, T), [x0, 0.0], method="DOP853", rtol=1e-11, atol=1e-12)
        return s.y[:, -1] - [x0, 0.0]

    for _ in range(30):
        r, e = end(x0, T), 1e-7
        J = np.column_stack([(end(x0 + e, T) - r) / e, (end(x0, T + e) - r) / e])
        d = np.linalg.solve(J, -r)
        x0, T = x0 + d[0], T + d[1]
        if np.max(np.abs(d)) < 1e-10:
            break
    return x0, T
