"""A purely numerical KBM recursion: the independent reference for the symbolic engine.

Only numerical evaluations of ``F`` are used.  Every quantity is a table on a grid
``a_i`` (Chebyshev points on ``[a0 - r, a0 + r]``, ``a0`` the middle node) times
``psi_j`` (uniform on ``[0, 2 pi)``); ``d/dpsi`` is done with FFTs, ``d/da`` with the
Chebyshev differentiation matrix (Trefethen, *Spectral Methods in MATLAB*, ch. 6), and
the ``eps**m`` Taylor coefficient of ``F(x(eps), xdot(eps))`` by the Cauchy integral on
a circle in the complex ``eps`` plane (FFT over ``M`` points).  The recursion is the
harmonic balance of Bogoliubov & Mitropolsky: at order ``n``,
``A_n = -R^{sin 1}/(2 w0)``, ``B_n = -R^{cos 1}/(2 w0 a)``, ``u_n`` harmonic by harmonic
without the first harmonic.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np


def cheb(N: int) -> tuple[np.ndarray, np.ndarray]:
    """Chebyshev points x_k = cos(pi k/N) on [-1, 1] and the differentiation matrix."""
    if N == 0:
        return np.array([1.0]), np.zeros((1, 1))
    x = np.cos(np.pi * np.arange(N + 1) / N)
    c = np.hstack([2.0, np.ones(N - 1), 2.0]) * (-1.0) ** np.arange(N + 1)
    X = np.tile(x, (N + 1, 1)).T
    dX = X - X.T
    D = np.outer(c, 1.0 / c) / (dX + np.eye(N + 1))
    D = D - np.diag(D.sum(axis=1))
    return x, D


def numerical_kbm(F: Callable, omega0: float, order: int, a0: float, *, n_psi: int = 64,
                  n_cheb: int = 14, radius: float | None = None, n_eps: int = 64,
                  eps_radius: float = 0.5) -> dict:
    """``A[n](a0)``, ``B[n](a0)``, ``u[n](a0, psi)`` for n = 1..order, numerically.

    ``F(x, xdot)`` must accept complex numpy arrays.  ``n_cheb`` must be even (so that
    ``a0`` is a node).
    """
    if n_cheb % 2:
        raise ValueError("n_cheb must be even")
    r = radius if radius is not None else 0.25 * a0
    xc, Dc = cheb(n_cheb)
    a = a0 + r * xc                       # nodes, a[n_cheb // 2] = a0
    Da = Dc / r
    mid = n_cheb // 2
    psi = 2 * np.pi * np.arange(n_psi) / n_psi
    m = np.fft.fftfreq(n_psi, d=1.0 / n_psi)
    A_grid = a[:, None] * np.ones((1, n_psi))

    def dpsi(f):
        return np.real(np.fft.ifft(1j * m * np.fft.fft(f, axis=1), axis=1))

    def da(f):
        return Da @ f

    def harm1(f):
        c = np.fft.fft(f, axis=1) / n_psi
        return 2 * np.real(c[:, 1]), -2 * np.imag(c[:, 1])   # cos, sin coefficients

    def solve(R):
        c = np.fft.fft(R, axis=1)
        den = omega0**2 * (1.0 - m**2)
        keep = np.abs(np.abs(m) - 1) > 0.5
        out = np.zeros_like(c)
        out[:, keep] = c[:, keep] / den[keep]
        return np.real(np.fft.ifft(out, axis=1))

    X = [A_grid * np.cos(psi)[None, :]]
    V = [omega0 * dpsi(X[0])]
    A, B, U = [], [], []
    k = np.arange(n_eps)
    e = eps_radius * np.exp(2j * np.pi * k / n_eps)

    def taylor_F(n):
        xs = sum(e[:, None, None] ** j * X[j][None] for j in range(len(X)))
        vs = sum(e[:, None, None] ** j * V[j][None] for j in range(len(V)))
        vals = F(xs, vs)
        coef = np.mean(vals * (e[:, None, None] ** (-n)), axis=0)
        return np.real(coef)

    def D(j, f):
        return A[j - 1][:, None] * da(f) + B[j - 1][:, None] * dpsi(f)

    for n in range(1, order + 1):
        Fn = taylor_F(n - 1)
        v_known = sum((D(j, X[n - j]) for j in range(1, n)), np.zeros_like(X[0]))
        acc = omega0 * dpsi(v_known) + sum((D(j, V[n - j]) for j in range(1, n)),
                                           np.zeros_like(X[0]))
        R = Fn - acc
        c1, s1 = harm1(R)
        A.append(-s1 / (2 * omega0))
        B.append(-c1 / (2 * omega0 * a))
        un = solve(R)
        U.append(un)
        X.append(un)
        V.append(omega0 * dpsi(un) + D(n, X[0]) + v_known)
    return {"A": [None] + [x[mid] for x in A], "B": [None] + [x[mid] for x in B],
            "u": [None] + [x[mid] for x in U], "psi": psi}
