"""Independent references shared by several test modules (not tests themselves).

- :func:`duffing_lambda_min`: the smallest real part of the Floquet multipliers of the
  period-1 response of x'' + 0.1 x' + x + x^3 = 20 cos(nu t), nu = 1 + sigma, by a plain
  scipy shooting (Newton on the period map with its own variational equations): the
  reference for the period doublings of the strongly forced Duffing oscillator.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp


def duffing_lambda_min(sigma, y0):
    nu = 1 + sigma
    T = 2 * math.pi / nu

    def f(t, Y):
        x, v = Y[0], Y[1]
        P = Y[2:].reshape(2, 2)
        J = np.array([[0.0, 1.0], [-1 - 3 * x * x, -0.1]])
        return np.concatenate([[v, -x - x**3 - 0.1 * v + 20 * math.cos(nu * t)],
                               (J @ P).ravel()])

    y = np.array(y0, float)
    for _ in range(30):
        s = solve_ivp(f, (0, T), np.concatenate([y, np.eye(2).ravel()]), method="DOP853",
                      rtol=1e-12, atol=1e-12)
        yT, P = s.y[:2, -1], s.y[2:, -1].reshape(2, 2)
        dy = np.linalg.solve(P - np.eye(2), -(yT - y))
        y = y + dy
        if np.max(np.abs(dy)) < 1e-12:
            break
    return float(np.min(np.linalg.eigvals(P).real))
