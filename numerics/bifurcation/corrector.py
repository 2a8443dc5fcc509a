"""The corrector of a pseudo-arclength continuation (:mod:`numerics.bifurcation.curve`):
Newton's method on a defining system ``G: R^(n+1) -> R^n`` bordered by one linear row
(:func:`correct`) and ``G'`` by central differences (:func:`numerical_jacobian`); the
tangent is the null vector of ``G'`` (:func:`numerics.shooting.arclength.null_vector`).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from numerics.errors import ConvergenceError, IntegrationError

__all__ = ["FAILURES", "correct", "numerical_jacobian"]

#: exceptions that mean "no point here" (the step is cut), not a bug
FAILURES = (ConvergenceError, IntegrationError, np.linalg.LinAlgError, FloatingPointError,
            ValueError, ArithmeticError)


def numerical_jacobian(G: Callable, z: np.ndarray, h: float = 1e-7) -> np.ndarray:
    """``G'(z)`` by central differences with steps ``h (1 + |z_i|)`` (error O(h^2))."""
    z = np.asarray(z, dtype=float)
    cols = []
    for i in range(z.size):
        e = np.zeros_like(z)
        e[i] = h * (1.0 + abs(z[i]))
        cols.append((np.asarray(G(z + e), dtype=float) - np.asarray(G(z - e), dtype=float))
                    / (2 * e[i]))
    return np.column_stack(cols)


def _jac(G, jac, z, h=1e-7):
    return np.atleast_2d(np.asarray(jac(z), dtype=float)) if jac is not None else \
        numerical_jacobian(G, z, h)


def correct(G: Callable, z: np.ndarray, row: np.ndarray, rhs: float, *, jac=None,
            tol: float = 1e-10, xtol: float = 1e-9, max_steps: int = 12, h: float = 1e-7):
    """Newton's method on ``G(z) = 0, row . z = rhs``.

    Returns ``(z, residual, steps, J)`` once ``max|G| <= tol`` and the last correction
    ``max|dz| <= xtol (1 + max|z|)``; raises :class:`ConvergenceError`
    otherwise (the residuals in the message).
    """
    z = np.array(z, dtype=float)
    hist = []
    for k in range(1, max_steps + 1):
        g = np.atleast_1d(np.asarray(G(z), dtype=float))
        if not np.all(np.isfinite(g)):
            raise ConvergenceError(f"the defining system is not finite at z = {z}")
        J = _jac(G, jac, z, h)
        A = np.vstack([J, row])
        b = -np.concatenate([g, [float(row @ z) - rhs]])
        dz = np.linalg.solve(A, b)
        z = z + dz
        res = float(np.max(np.abs(g)))
        hist.append(res)
        small = float(np.max(np.abs(dz))) <= xtol * (1.0 + float(np.max(np.abs(z))))
        if small:
            g = np.atleast_1d(np.asarray(G(z), dtype=float))
            res = float(np.max(np.abs(g)))
            if res <= tol:
                return z, res, k, J
        if k >= 3 and res > 10 * hist[-2] and hist[-2] > tol:
            break  # diverging
    raise ConvergenceError("Newton on the defining system did not converge: residuals "
                           + ", ".join(f"{r:.2e}" for r in hist))
