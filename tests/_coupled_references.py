"""Independent references for the coupled expansions with sin/cos of the state
(tests/test_coupled_bessel.py, tests/test_coupled_constants.py): the rates of a symbolic
result as numpy functions, sums over the harmonic index cut where their Bessel functions
are negligible, and u_{i,1} by FFT quadrature on the torus (no Bessel function)."""

from __future__ import annotations

import numpy as np
import sympy as sp

__all__ = ["cut_sums", "rates_function", "u_by_fft"]


def rates_function(result, values):
    """The first-order rates of ``result`` as a function of (amplitudes, gammas)."""
    syms = [*sp.symbols(f"a1:{result.model.dof + 1}"), *[g for g, _ in result.gammas]]
    sub = {sp.Symbol(k): v for k, v in values.items()}
    exprs = [*[row[1].subs(sub) for row in result.A], *[row[1].subs(sub) for row in result.B]]
    return sp.lambdify(syms, exprs, ["numpy", "scipy"])


def cut_sums(expr: sp.Expr, terms: int = 80) -> sp.Expr:
    """``expr`` with every sum over the harmonic index cut after ``terms`` terms (the
    Bessel functions J_n(z) of the tests, z < 10, are below 1e-40 there)."""
    return expr.replace(lambda e: isinstance(e, sp.Sum),
                        lambda e: sp.Add(*[e.function.subs(e.limits[0][0], j)
                                           for j in range(int(e.limits[0][1]),
                                                          int(e.limits[0][1]) + terms)]))


def u_by_fft(model, vals, a, i, nodes=64):
    """u_{i,1} by quadrature: F_i on a grid of the torus psi (and theta) at x_j = a_j
    cos psi_j, its FFT, every harmonic h with h . omega != +-omega_i divided by
    omega_i**2 - (h . omega)**2 (the resonant ones are the rates'); a function of the
    angles."""
    n = model.dof
    omega = [float(w) for w in model.omega0] + ([float(model.nu0)] if model.forced else [])
    D = len(omega)
    grid = np.meshgrid(*[2 * np.pi * np.arange(nodes) / nodes] * D, indexing="ij")
    args = [a[j] * np.cos(grid[j]) for j in range(n)] \
        + [-omega[j] * a[j] * np.sin(grid[j]) for j in range(n)]
    args += [grid[-1]] if model.forced else [np.zeros_like(grid[0])]
    syms = [*model.state, sp.Symbol("theta")]
    f = sp.lambdify(syms, model.F[i].subs({sp.Symbol(k): v for k, v in vals.items()}),
                    ["numpy", "scipy"])
    coef = np.fft.fftn(f(*args) * np.ones_like(grid[0])) / nodes**D
    h = np.meshgrid(*[np.fft.fftfreq(nodes, 1 / nodes)] * D, indexing="ij")
    freq = sum(hj * wj for hj, wj in zip(h, omega))
    resonant = np.isclose(np.abs(freq), omega[i], rtol=0, atol=1e-12)
    coef = np.where(resonant, 0, coef / np.where(resonant, 1, omega[i]**2 - freq**2))

    def u(angles):
        phase = sum(hj * t for hj, t in zip(h, angles))
        return float(np.real(np.sum(coef * np.exp(1j * phase))))
    return u
