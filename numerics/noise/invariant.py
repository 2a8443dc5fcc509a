"""The exact stationary averages of the BAOAB chain itself, by its transfer operator.

A second method for the weak error of the integrator, with no Monte Carlo noise: the
stationary density of BAOAB (Leimkuhler & Matthews, Appl. Math. Res. Express 2013, 34;
Gaussian increments) on ``x'' = f(x) - gamma x' + sigma xi`` (one degree of freedom,
constant friction) is the fixed point of the chain's transfer operator, computed here on a
Chebyshev grid.  The difference of its averages from the exact Boltzmann quadrature is the
scheme's weak error at the step ``h``, resolved to 1e-8 where an ensemble resolves 1e-4.

The chain is observed right after its O part.  Reading the steps ``...B A O A B B A O A
B...`` from there, one step is the deterministic, area-preserving map
``Phi = A(h/2) B(h) A(h/2)`` (a velocity-Verlet step) followed by the O part
``u -> e u + s g``, ``e = exp(-gamma h)``, ``s = sigma sqrt((1 - e^2)/(2 gamma))``,
``g ~ N(0, 1)``.  So the stationary density ``q(x, u)`` solves

``q(x, u) = (1/e) E[q(Phi^-1(x, U))]``, ``U ~ N(u/e, (s/e)^2)``,

evaluated by Gauss-Hermite quadrature in ``U`` and barycentric Chebyshev interpolation of
``q`` at ``Phi^-1(x, U)`` (zero outside the box); the linear system with the normalisation
``int q = 1`` (Clenshaw-Curtis) is solved densely.  The position the integrator reports at
a step's end is ``x + (h/2) u`` (the second A part), where the averages are taken.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numpy as np

from kbm.errors import ParameterError

__all__ = ["baoab_stationary_averages"]


def _chebyshev(n: int, half: float) -> tuple[np.ndarray, np.ndarray]:
    """Chebyshev points of the second kind on ``[-half, half]`` and their barycentric
    weights."""
    j = np.arange(n)
    w = (-1.0) ** j
    w[0] *= 0.5
    w[-1] *= 0.5
    return -half * np.cos(np.pi * j / (n - 1)), w


def _interpolation_rows(nodes: np.ndarray, w: np.ndarray, pts: np.ndarray,
                        half: float) -> np.ndarray:
    """Rows of the barycentric interpolation matrix at ``pts`` (zero rows outside)."""
    d = pts[:, None] - nodes[None, :]
    hit = np.abs(d) < 1e-14
    d[hit] = 1.0
    r = w[None, :] / d
    with np.errstate(divide="ignore", invalid="ignore"):
        r /= r.sum(axis=1, keepdims=True)
    on = hit.any(axis=1)
    r[on] = hit[on].astype(float)
    r[np.abs(pts) > half] = 0.0
    return r


def _clenshaw_curtis(n: int, half: float) -> np.ndarray:
    """Clenshaw-Curtis weights at the ``n`` Chebyshev points on ``[-half, half]``."""
    N = n - 1
    theta = np.pi * np.arange(n) / N
    w = np.zeros(n)
    v = np.ones(N - 1)
    if N % 2 == 0:
        w[0] = w[N] = 1.0 / (N * N - 1)
        for k in range(1, N // 2):
            v -= 2 * np.cos(2 * k * theta[1:-1]) / (4 * k * k - 1)
        v -= np.cos(N * theta[1:-1]) / (N * N - 1)
    else:
        w[0] = w[N] = 1.0 / (N * N)
        for k in range(1, (N - 1) // 2 + 1):
            v -= 2 * np.cos(2 * k * theta[1:-1]) / (4 * k * k - 1)
    w[1:-1] = 2 * v / N
    return w * half


def baoab_stationary_averages(force: Callable[[np.ndarray], np.ndarray], gamma: float,
                              sigma: float, h: float,
                              observables: Sequence[Callable[[np.ndarray], np.ndarray]], *,
                              nx: int = 96, nu: int = 48, nodes: int = 30,
                              x_half: float = 4.5, u_half: float = 7.0
                              ) -> tuple[list[float], float]:
    """The stationary averages of ``observables`` (functions of the position) under BAOAB
    with step ``h`` and Gaussian increments, exactly up to the grid's resolution.

    Parameters
    ----------
    force : callable
        ``f(x)``, vectorised (the force, the spring included).
    gamma, sigma : float
        The constant friction (> 0) and the noise amplitude ``sqrt(2 D)``.
    h : float
        The step.
    observables : sequence of callables
        Functions of the position at a step's end.
    nx, nu, nodes : int
        Chebyshev points in ``x`` and in the velocity, Gauss-Hermite nodes of the O part.
    x_half, u_half : float
        The box ``|x| <= x_half``, ``|u| <= u_half`` (the density is taken as 0 outside).

    Returns
    -------
    (list of float, float)
        The averages and the largest residual ``|T q - q|`` of the fixed point (a
        resolution check: it grows when the box or the grid is too small for the step).

    Raises
    ------
    kbm.errors.ParameterError
        For ``gamma <= 0``, ``sigma <= 0`` or ``h <= 0``.
    """
    if not (gamma > 0 and sigma > 0 and h > 0):
        raise ParameterError(f"gamma, sigma and h must be positive, got {gamma}, {sigma}, {h}")
    xs, wx = _chebyshev(nx, x_half)
    us, wu = _chebyshev(nu, u_half)
    e = math.exp(-gamma * h)
    s = sigma * math.sqrt((1.0 - e * e) / (2.0 * gamma))
    t, om = np.polynomial.hermite_e.hermegauss(nodes)
    om = om / om.sum()
    X, U = (a.ravel() for a in np.meshgrid(xs, us, indexing="ij"))
    V = U[:, None] / e + (s / e) * t[None, :]
    x1 = X[:, None] - 0.5 * h * V  # Phi^-1: undo A, B, A
    u0 = V - h * force(x1)
    x0 = x1 - 0.5 * h * u0
    Lx = _interpolation_rows(xs, wx, x0.ravel(), x_half).reshape(X.size, nodes, nx)
    Lu = _interpolation_rows(us, wu, u0.ravel(), u_half).reshape(X.size, nodes, nu)
    T = np.einsum("l,tla,tlb->tab", om / e, Lx, Lu, optimize=True).reshape(X.size, -1)
    cw = np.outer(_clenshaw_curtis(nx, x_half), _clenshaw_curtis(nu, u_half)).ravel()
    A = T - np.eye(X.size)
    A[0, :] = cw  # one equation replaced by the normalisation
    rhs = np.zeros(X.size)
    rhs[0] = 1.0
    q = np.linalg.solve(A, rhs)
    residual = float(np.max(np.abs(T @ q - q)))
    end = X + 0.5 * h * U
    return [float(np.sum(cw * q * obs(end))) for obs in observables], residual
