"""The stationary solve's inverse iteration on the largest grids by a Krylov method
(:func:`bordered_inverse_iteration`, what :func:`._stationary_solve.orthonormal_stationary`
runs from :data:`MIXED_POINTS` points on): the factorisation of
:class:`._pentadiagonal.HermitePentadiagonalLU` made in single precision (``single``) is
the preconditioner of a flexible GMRES (Saad, *Iterative Methods for Sparse Linear
Systems*, 2nd ed., sec. 9.4.1; right preconditioning) on the double-precision operator
(``matvec``): mixed-precision refinement in the manner of GMRES-IR (Carson and Higham,
SIAM J. Sci. Comput. 40, A817, 2018).

Each step of inverse iteration, ``A y = c`` normalised, is solved as the bordered system
``[[A, b], [w^T, 0]] [y; mu] = [0; 1]`` with ``b = c`` at the unpinned rows and ``w^T y``
the mass of ``y`` (the quadrature of its marginal): its solution is ``A^-1 c`` normalised
and ``-mu`` the eigenvalue estimate ``lambda_0``.  Not ``A y = c`` itself: ``A`` is
nearly singular (``|lambda_0|`` about 1e-11 at 258 x 1041), and a preconditioner whose
own smallest eigenvalue is not ``A``'s sends the plain refinement astray (the SEDF at
rest, mu = 0.01, 258 x 593: a relative residual of 3e3 after 30 steps); the bordered
matrix is well conditioned when ``w^T`` and ``b`` are not orthogonal to the null vectors.
Its preconditioner is the bordered single-precision factorisation with ``b`` for
``M^-1 b`` (another fixed preconditioner; GMRES needs no more).

The tolerance: the bordered residual's 2-norm at most :data:`RESIDUAL` (the right-hand
side has norm 1), checked on the true residual, not GMRES's recurrence.  Measured on the
SEDF at rest (Delta = 3, D = mu/2, mu = 0.01, 258 functions): its floor in double
precision is about 3e-14 at 1041 points, and at 1e-13 the coefficients came within
3.2e-13 (1041 points) and 6.4e-13 (1301) of the direct solve's, the moments within
3e-13, with 6-7 iterations from two sweeps of inverse iteration with the preconditioner
alone (an eigenvector within 2e-4).  The sweeps of single precision (factors and
vectors) took 160-260 iterations at 258 x 593: the factors are kept in single precision
but the vectors and the sums of the sweeps in double
(:func:`._single_products.single_matvec`; the factors were formerly
kept in double, the same operator to the rounding of a double sum, twice the memory), in
memory up to :data:`._pentadiagonal_disk.FACTOR_MEMORY` and on disk beyond it.

When GMRES does not reach the tolerance within :data:`MAX_ITERATIONS`, or the iteration
does not settle within the caller's ``iterations``, :func:`bordered_inverse_iteration`
returns ``None`` and the caller solves with the direct factorisation (the former result).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["bordered_inverse_iteration", "fgmres", "MIXED_POINTS", "RESIDUAL",
           "MAX_ITERATIONS"]

#: the points per order (after the fold) from which the stationary solve takes this route:
#: below it the factorisation is too small a share of the solve to pay for the iterations
#: (SEDF at rest, D = mu/2, CPU time against the direct solve: 258 functions at mu = 0.01
#: 1.2 times faster on 297 points, 1.6-1.8 on 521 and 651; 182 at mu = 0.02 1.4-1.7 on 371,
#: 1.5-1.7 on 464)
MIXED_POINTS = 350
#: the bordered residual's 2-norm within which a step of inverse iteration is solved
RESIDUAL = 1e-13
#: the GMRES iterations of one step (the SEDF took 6-7) before the direct solve is taken
MAX_ITERATIONS = 30


def fgmres(matvec, precond, rhs: np.ndarray, x0: np.ndarray, tol: float,
           max_iterations: int) -> np.ndarray | None:
    """The solution of ``A x = rhs`` by flexible GMRES from ``x0`` with the right
    preconditioner ``precond`` (Saad, Algorithm 9.6; modified Gram-Schmidt, Givens
    rotations), until the true residual's 2-norm is at most ``tol``; restarted from its
    iterate when the recurrence's residual met ``tol`` but the true one did not.  ``None``
    when ``max_iterations`` products do not reach it."""
    x = np.array(x0, float)
    done = 0
    while True:
        r = rhs - matvec(x)
        beta = float(np.linalg.norm(r))
        if beta <= tol:
            return x
        k = max_iterations - done
        if k <= 0:
            return None
        V, Z = [r / beta], []
        H = np.zeros((k + 1, k))
        g = np.zeros(k + 1)
        g[0] = beta
        cs, sn = np.zeros(k), np.zeros(k)
        j = 0
        for j in range(k):
            z = precond(V[j])
            w = matvec(z)
            Z.append(z)
            for i in range(j + 1):
                H[i, j] = float(np.dot(w, V[i]))
                w -= H[i, j] * V[i]
            H[j + 1, j] = float(np.linalg.norm(w))
            breakdown = not H[j + 1, j] > 0  # the solution is in the space: exact
            V.append(w if breakdown else w / H[j + 1, j])
            for i in range(j):  # the earlier rotations on the new column
                H[i, j], H[i + 1, j] = (cs[i] * H[i, j] + sn[i] * H[i + 1, j],
                                        -sn[i] * H[i, j] + cs[i] * H[i + 1, j])
            h = math.hypot(H[j, j], H[j + 1, j])
            cs[j], sn[j] = (H[j, j] / h, H[j + 1, j] / h) if h > 0 else (1.0, 0.0)
            H[j, j], H[j + 1, j] = h, 0.0
            g[j + 1], g[j] = -sn[j] * g[j], cs[j] * g[j]
            if abs(g[j + 1]) <= tol or breakdown:
                break
        j += 1
        done += j
        y = np.zeros(j)
        for i in range(j - 1, -1, -1):  # back substitution in the rotated H
            y[i] = (g[i] - np.dot(H[i, i + 1:j], y[i + 1:j])) / H[i, i]
        for i in range(j):
            x += y[i] * Z[i]


def bordered_inverse_iteration(precond, matvec, c: np.ndarray, keep: np.ndarray, mass,
                               iterations: int, rtol: float):
    """Inverse iteration for the eigenvector of ``A`` (``matvec``) nearest zero from ``c``
    (module docstring): two sweeps with the single-precision factorisation ``precond``
    alone, then each step a bordered solve by :func:`fgmres`, until the coefficients
    change by at most ``rtol`` (relative to their largest), at most ``iterations`` steps.
    ``keep`` is 0 at the pinned rows, ``mass(c)`` the normalising functional.  Returns
    ``(c, lambda_0, last change)`` with ``mass(c) = 1``, or ``None`` when a step's GMRES
    or the iteration did not converge (the caller's direct solve then)."""
    n = c.size
    lam = 0.0
    for _ in range(2):
        c = precond(keep * c)
        norm = mass(c)
        c /= norm
        lam = 1.0 / norm
    rhs = np.zeros(n + 1)
    rhs[n] = 1.0
    for _ in range(iterations):
        b = keep * c
        wb = mass(b)

        def bordered(z, b=b):
            return np.concatenate([matvec(z[:n]) + z[n] * b, [mass(z[:n])]])

        def bordered_precond(r, b=b, wb=wb):
            y = precond(r[:n])
            mu = (mass(y) - r[n]) / wb
            return np.concatenate([y - mu * b, [mu]])

        z = fgmres(bordered, bordered_precond, rhs, np.concatenate([c, [-lam]]),
                   RESIDUAL, MAX_ITERATIONS)
        if z is None or not np.all(np.isfinite(z)):
            return None
        new = z[:n] / mass(z[:n])
        lam = -float(z[n])
        last = float(np.max(np.abs(new - c))) / float(np.max(np.abs(new)))
        c = new
        if last <= rtol:
            return c, lam, last
    return None
