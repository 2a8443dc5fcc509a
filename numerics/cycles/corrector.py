"""The corrector of pseudo-arclength continuation, shared by the branches of one degree of
freedom (:mod:`numerics.cycles._arclength`) and of ``2N`` dimensions
(:mod:`numerics.coupled.continuation`).

Newton's method on ``R(u) = 0`` and one linear condition ``row . u = target`` (the
hyperplane normal to the tangent, or a fixed parameter), Keller's bordered system
(Doedel, *Lecture notes on numerical analysis of nonlinear equations*, sec. 2).  Each
caller gives its residual and Jacobian and its test of a converged point, which is the
acceptance standard of :mod:`numerics.cycles.acceptance` with the caller's bound on the
correction (the accuracy of the point).  The compiled corrector of one degree of freedom
(:mod:`numerics.flow._shooting_corrector`) runs the same iterations in numba.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from numerics.errors import ConvergenceError

__all__ = ["correct_on_hyperplane"]


def correct_on_hyperplane(evaluate: Callable, u0, row, target: float, *, max_iter: int,
                          accept: Callable, too_large: Callable, where: Callable):
    """Newton on ``R(u) = 0, row . u = target``.

    Parameters
    ----------
    evaluate
        ``u -> (R, J, data)``: the residual, its Jacobian ``dR/du`` (one row fewer than
        ``u`` has components) and what the caller keeps of the evaluation.
    u0, row, target
        The prediction and the linear condition.
    max_iter
        Bound on the corrections.
    accept
        ``(u, R, du, data, iteration) -> bool``: whether ``u`` (with the correction ``du``
        computed there) is a converged point.
    too_large
        ``(u, du) -> str | None``: a message when the correction leaves the region where
        Newton is trusted.
    where
        ``u -> str``: the place named in the error message.

    Returns
    -------
    ``(u, R, du, data, iteration)`` of the accepted iterate.

    Raises
    ------
    numerics.errors.ConvergenceError
        When a correction is too large, or after ``max_iter`` corrections.
    numpy.linalg.LinAlgError
        For a singular bordered matrix.
    """
    u = np.array(u0, dtype=float)
    row = np.asarray(row, dtype=float)
    R = np.full(1, np.nan)
    for it in range(max_iter + 1):
        R, J, data = evaluate(u)
        du = np.linalg.solve(np.vstack([J, row]), -np.append(R, row @ u - target))
        if accept(u, R, du, data, it):
            return u, R, du, data, it
        if it == max_iter:
            break
        msg = too_large(u, du)
        if msg:
            raise ConvergenceError(msg)
        u = u + du
    raise ConvergenceError(f"corrector did not converge in {max_iter} iterations at {where(u)} "
                           f"(|R| = {np.max(np.abs(R)):.2e})")
