"""Strong resonances on the true Neimark-Sacker curve of the forced van der Pol oscillator
(issue 38), each checked by an independent Floquet computation.

``x'' + x = mu ((1 - x^2) x' + h cos nu t)``, ``nu = 1 + mu sigma``, ``mu = 0.1``: each
Neimark-Sacker curve of the drive-period response, continued in ``(sigma, h)`` from its
Bogdanov-Takens end (``(-0.2516, 0.9811)`` and ``(0.2485, 1.0186)``), carries multipliers
``e^{+-i theta}`` whose angle grows from 0 with ``|sigma|``: 1:4 at
``(-2.01387, 5.14863)`` and ``(3.34402, 11.08408)``, 1:3 at ``(-2.51071, 6.22727)``.
The code locates the 1:4 and 1:3 strong resonances as the zeros of ``tr Phi`` and
``tr Phi + 1`` (Kuznetsov, *Elements of Applied Bifurcation Theory*, 3rd ed., sec. 9.5:
``theta = pi/2, 2 pi/3``).  At each
located point the test finds the response again by Newton's method on the stroboscopic
map and its monodromy from the variational equations ``Phi' = A(t) Phi`` written here,
integrated by scipy's DOP853 (rtol 1e-12): a second method, sharing nothing with the
compiled flow of :mod:`numerics.flow.coupled_flow`.  Its multipliers lie on the unit circle at angle
``pi/2`` (``2 pi/3``) to 1e-6.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from numerics.bifurcation.forced import DrivenProblem, forced_seeds, forced_true_curves

MU = 0.1
RANGES = {"sigma": (-4.0, 4.0), "h": (0.05, 12.0)}


def _flow(y0, sigma, h):
    """``(y(T), Phi(T))`` of the forced vdp over the drive's period ``T = 2 pi/nu``: the
    state and its variational equations, ``A = [[0, 1], [-1 - 2 mu x v, mu (1 - x^2)]]``."""
    nu = 1.0 + MU * sigma

    def rhs(t, w):
        x, v = w[0], w[1]
        P = w[2:].reshape(2, 2)
        A = np.array([[0.0, 1.0], [-1.0 - 2.0 * MU * x * v, MU * (1.0 - x * x)]])
        acc = -x + MU * ((1.0 - x * x) * v + h * math.cos(nu * t))
        return np.concatenate(([v, acc], (A @ P).ravel()))

    w0 = np.concatenate((y0, np.eye(2).ravel()))
    sol = solve_ivp(rhs, (0.0, 2 * math.pi / nu), w0, method="DOP853", rtol=1e-12,
                    atol=1e-13)
    assert sol.success
    return sol.y[:2, -1], sol.y[2:, -1].reshape(2, 2)


def _floquet(y0, sigma, h):
    """The response's multipliers at ``(sigma, h)``: Newton on ``y(T) = y0`` from ``y0``."""
    y = np.array(y0, dtype=float)
    for _ in range(20):
        yT, Phi = _flow(y, sigma, h)
        dy = np.linalg.solve(Phi - np.eye(2), -(yT - y))
        y = y + dy
        if np.max(np.abs(dy)) < 1e-13:
            break
    yT, Phi = _flow(y, sigma, h)
    assert np.max(np.abs(yT - y)) < 1e-10
    return np.linalg.eigvals(Phi)


@pytest.fixture(scope="module")
def ns_curves():
    """Both Neimark-Sacker curves, from their seeds on the response curve at h = 1.2 (the
    side of each: the sign of sigma)."""
    prob = DrivenProblem("vdp-forced", {"mu": MU}, ("sigma", "h"))
    seeds = [s for s in forced_seeds(prob, (-1.5, 1.5), [1.2]) if s[0] == "neimark-sacker"]
    out = {}
    for seed in seeds:
        tasks, _, points = forced_true_curves(prob, RANGES, [seed], ds=0.05, max_points=200)
        events = {ev.name: ev for t in tasks for path in t.paths for ev in path.events}
        out[int(np.sign(seed[1][2]))] = (events, {p.kind: p.point for p in points})
    return out


@pytest.mark.parametrize("side, kind, theta", [(-1, "1:4 resonance", math.pi / 2),
                                               (-1, "1:3 resonance", 2 * math.pi / 3),
                                               (1, "1:4 resonance", math.pi / 2)])
def test_forced_vdp_strong_resonance_against_scipy_floquet(ns_curves, side, kind, theta):
    """The located 1:4 (1:3) point: scipy's multipliers are e^{+-i pi/2} (e^{+-2 pi i/3})
    to 1e-6 (Kuznetsov sec. 9.5), and the point is named in the codim-2 list."""
    events, named = ns_curves[side]
    ev = events[kind]
    x0, v0, sigma, h = ev.z
    assert side * sigma > 0
    assert named[kind] == pytest.approx((sigma, h), abs=1e-12)
    lam = _floquet((x0, v0), sigma, h)
    assert np.max(np.abs(np.abs(lam) - 1.0)) <= 1e-6
    assert np.max(np.abs(np.abs(np.angle(lam)) - theta)) <= 1e-6
    assert lam[0].imag * lam[1].imag < 0


def test_forced_vdp_rotation_angle_grows_to_the_resonances(ns_curves):
    """Along each curve the angle arccos(tr Phi/2) rises from the Bogdanov-Takens end
    (theta = 0, tr Phi = 2) with |sigma| and h: the 1:4 point lies beyond the
    Bogdanov-Takens point, and on sigma < 0 the 1:3 point beyond the 1:4 one.  The true
    curves are not mirror images (nu = 1 + mu sigma): the angle grows faster for sigma < 0,
    where the drive is slower than the free oscillation."""
    (_, m), (_, p) = ns_curves[-1], ns_curves[1]
    assert abs(m["bogdanov-takens"][0]) < abs(m["1:4 resonance"][0]) < abs(m["1:3 resonance"][0])
    assert m["bogdanov-takens"][1] < m["1:4 resonance"][1] < m["1:3 resonance"][1]
    assert abs(p["bogdanov-takens"][0]) < abs(p["1:4 resonance"][0])
    assert p["bogdanov-takens"][1] < p["1:4 resonance"][1]
    assert abs(m["1:4 resonance"][0]) < abs(p["1:4 resonance"][0])
