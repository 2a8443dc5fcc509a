"""Pseudo-arclength continuation of periodic orbits (Keller; Doedel, *Lecture notes on
numerical analysis of nonlinear equations*, sec. 2), the pieces of the one branch problem
(:mod:`numerics.shooting.branch_problem`) and of every branch's steps.

- :func:`correct_on_hyperplane`: Newton on ``R(u) = 0`` and ``row . u = target``, each
  point accepted by the caller's test (the standard of :mod:`numerics.shooting.acceptance`
  with its bound on the correction); :mod:`numerics.flow._shooting_corrector` is its
  compiled twin for one degree of freedom;
- :func:`null_vector` (the tangent) and :func:`predict` (Euler or cubic Hermite);
- :func:`walk`: the one driver of the steps along a branch (:func:`kbm.slowflow.arclength.walk`,
  which also follows the slow-flow curves of :mod:`kbm.slowflow.continuation`).
"""

from __future__ import annotations

import math
from typing import Callable

import numpy as np

from kbm.slowflow.arclength import walk as _walk
from kbm.errors import ParameterError
from numerics.errors import ConvergenceError, IntegrationError

__all__ = ["correct_on_hyperplane", "null_vector", "predict", "walk", "parameter_range", "start_value", "FAIL"]

#: the failures of a step after which it is halved (or a bisection stops)
FAIL = (ConvergenceError, IntegrationError, np.linalg.LinAlgError, ValueError)


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


def null_vector(J: np.ndarray, orient: np.ndarray | None = None) -> np.ndarray:
    """The unit null vector of the ``k x (k+1)`` matrix ``J`` (its last right singular
    vector: the branch's tangent), with ``t . orient >= 0`` when ``orient`` is given."""
    _, _, vt = np.linalg.svd(J)
    t = vt[-1]
    if orient is not None and float(np.dot(t, orient)) < 0:
        t = -t
    return t / np.linalg.norm(t)


def predict(u: np.ndarray, t: np.ndarray, ds: float, previous=None) -> np.ndarray:
    """The predictor ``ds`` along the unit tangent ``t`` at ``u``.

    With ``previous``, the unknowns and the unit tangent ``(u_, t_)`` of the point before,
    it is the cubic Hermite extrapolation through both points with both tangents (in the
    arclength ``s``, the chord ``h`` between them standing for it):
    ``u(s) = u + s t + a s^2 + b s^3`` with ``u(-h) = u_``, ``u'(-h) = t_``; its error is of
    fourth order in the step.
    """
    pred = u + ds * t
    if previous is not None:
        u_, t_ = previous
        h = float(np.linalg.norm(u - u_))
        if h > 0:
            d1 = u_ - u + h * t
            d2 = (t_ if t_ @ t > 0 else -t_) - t
            b = (2 * d1 / h + d2) / h**2
            a = (d1 + b * h**3) / h**2
            pred = pred + a * ds**2 + b * ds**3
    return pred


def walk(first, ds: float, **options):
    """Follow a branch from ``first`` by pseudo-arclength steps (the one driver,
    :func:`kbm.slowflow.arclength.walk`, whose options these are), a step failing on the errors of
    a shooting step (:data:`FAIL`) unless ``failures`` says otherwise."""
    options.setdefault("failures", FAIL)
    return _walk(first, ds, **options)


def parameter_range(vary: str, bounds, params) -> tuple[float, float, float]:
    """``(FROM, TO, start)`` of a branch in ``vary``: ``bounds`` finite with ``FROM < TO``,
    the start ``params[vary]`` (default ``FROM``) inside them; else a
    :class:`~kbm.errors.ParameterError` that says what to give."""
    lo, hi = (float(b) for b in bounds)
    if not (math.isfinite(lo) and math.isfinite(hi)):
        raise ParameterError(f"the range of {vary} must be finite, got {lo:g}:{hi:g}")
    if not lo < hi:
        raise ParameterError(f"empty range {lo:g}:{hi:g} for {vary}: give FROM < TO")
    p0 = start_value(vary, params[vary]) if vary in params else lo
    if not lo <= p0 <= hi:
        raise ParameterError(f"the start value {vary} = {p0:g} is outside the range "
                             f"{lo:g}:{hi:g}")
    return lo, hi, p0


def start_value(name: str, raw: object) -> float:
    """The start value ``raw`` of ``name`` as a float: a number or a decimal text directly,
    a fraction or an expression (``"3/2"``, as ``-p`` reads every value) through
    :func:`kbm.parameters.values.parameter_value`, which imports sympy (the warm path of
    ``kbm branch`` with decimal values imports none, ``tests/test_warm_path.py``)."""
    try:
        return float(raw)
    except (TypeError, ValueError):
        from kbm.parameters.values import parameter_value

        return float(parameter_value(name, raw))
