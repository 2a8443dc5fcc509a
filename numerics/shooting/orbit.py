"""Newton on the periodic orbit of a ``2N``-dimensional flow: the one shooting of the toolkit
(Parker and Chua, *Practical Numerical Algorithms for Chaotic Systems*, ch. 5).

- autonomous: the unknowns are ``y0`` on a section (one coordinate held at 0, e.g.
  ``xdot_1``) and the period ``T``; the shooting matrix is
  ``[Phi(T) - I without the section's column, f(y(T))]``; for ``N = 1`` on ``x' = 0``,
  Newton on the return map ``(x(T) - x0, x'(T)) = 0`` in ``(x0, T)``;
- forced: the period is the drive's; the unknowns are ``y0``, the matrix ``Phi(T) - I``.

Newton's iterate is accepted by the standard of :mod:`numerics.shooting.acceptance`.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from numerics.shooting.acceptance import orbit_scale, shoot_newton

__all__ = ["shoot", "multipliers", "peak", "NEWTON_MAX_STEPS"]

#: bound on the compiled integrator's steps over one period inside Newton's method
NEWTON_MAX_STEPS = 5 * 10**4


def shoot(monodromy: Callable, y0, T: float, *, section: int | None, rtol: float,
          max_iter: int, rhs: Callable | None = None, damp: Callable | None = None,
          noise: Callable | None = None, degenerate: Callable | None = None,
          accuracy: float | None = None, what: str = "", diverge: int = 5):
    """The periodic orbit near ``(y0, T)`` by Newton's method.

    Parameters
    ----------
    monodromy
        ``(y, T) -> (y(T), Phi(T), state)``: one integration of the flow with its
        variational equations (``state`` is what the caller keeps of it).
    y0, T
        The start (autonomous: ``y0[section]`` is taken as 0) and the period (the guess,
        or the drive's period when ``section`` is ``None``).
    section
        The index of the coordinate held at 0 (the phase condition), or ``None`` for a
        forced flow.
    rtol, max_iter
        The integrator's tolerance (the standard's) and the bound on the iterations.
    rhs
        ``(y, T) -> f(y)``, the field at the end (autonomous only).
    damp, noise, degenerate, accuracy, what, diverge
        Passed to :func:`numerics.shooting.acceptance.shoot_newton`; ``damp`` and
        ``degenerate`` see the unknowns ``z`` (autonomous: the free coordinates, then
        ``T``).

    Returns
    -------
    ``(y0, T, iterations, trace, state)`` of the accepted orbit.
    """
    y0 = np.asarray(y0, dtype=float)
    n2 = len(y0)
    kw = dict(rtol=rtol, max_iter=max_iter, damp=damp, noise=noise, degenerate=degenerate,
              accuracy=accuracy, what=what, diverge=diverge)
    if section is None:
        def evaluate_fixed(y):
            yT, Phi, state = monodromy(y, T)
            return yT - y, Phi - np.eye(n2), state

        y, it, trace, state = shoot_newton(evaluate_fixed, y0, scale=orbit_scale, **kw)
        return y, T, it, trace, state
    free = [j for j in range(n2) if j != section]
    eye = np.eye(n2)[:, free]

    def state_of(z):
        y = np.zeros(n2)
        y[free] = z[:-1]
        return y

    def evaluate(z):
        y = state_of(z)
        yT, Phi, state = monodromy(y, z[-1])
        M = np.empty((n2, n2))
        M[:, :-1] = Phi[:, free] - eye
        M[:, -1] = rhs(yT, z[-1])
        return yT - y, M, state

    z, it, trace, state = shoot_newton(evaluate, np.append(y0[free], T),
                                       scale=lambda z: orbit_scale(z[:-1]), **kw)
    return state_of(z), float(z[-1]), it, trace, state


def multipliers(Phi: np.ndarray, autonomous: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """``(all, non-trivial)`` eigenvalues of the monodromy matrix ``Phi``: an autonomous
    orbit's trivial one (nearest 1) first, the others by decreasing modulus."""
    z = np.linalg.eigvals(Phi)
    if not autonomous:
        z = z[np.lexsort((z.imag, -np.abs(z)))]
        return z, z
    k = int(np.argmin(np.abs(z - 1.0)))
    rest = np.delete(z, k)
    rest = rest[np.lexsort((rest.imag, -np.abs(rest)))]
    return np.concatenate([[z[k]], rest]), rest


def peak(y: np.ndarray) -> float:
    """The largest value of a periodic sample, refined by the parabola through the largest
    sample and its neighbours (error ~ ``h^4`` for the spacing ``h``)."""
    k = int(np.argmax(y))
    a, b, c = y[k - 1], y[k], y[(k + 1) % len(y)]
    den = a - 2 * b + c
    return float(b - (a - c) ** 2 / (8 * den)) if den < 0 else float(b)


