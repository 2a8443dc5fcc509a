"""Pseudo-arclength continuation of the solutions of ``G(u) = 0``, ``G: R^(n+1) -> R^n``.

One small numerical routine shared by the slow-flow steady states (:mod:`kbm.slowflow.steady`)
and the true periodic orbits (:mod:`numerics.shooting`): the last component of ``u`` is the
continuation parameter; the tangent is the null vector of ``dG/du``; the corrector is
Newton's method on ``G = 0`` and ``t . (u - u_pred) = 0`` (Keller 1977), so the curve is
followed round its folds.  A fold is where the parameter component of the oriented tangent
changes sign; it is then located by Newton's method on ``G = 0`` and that component.  The
steps are driven by the one pseudo-arclength driver, :func:`kbm.slowflow.arclength.walk`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .arclength import walk

__all__ = ["ArcPoint", "Arc", "trace", "both_ways", "tangent", "newton", "passes_start"]


@dataclass(frozen=True)
class ArcPoint:
    """A point ``u`` of the curve and its unit tangent."""

    u: np.ndarray
    tangent: np.ndarray


@dataclass(frozen=True)
class Arc:
    """A traced curve: its points in order, the fold points and why the tracing stopped."""

    points: tuple[ArcPoint, ...]
    folds: tuple[np.ndarray, ...]
    reason: str


def tangent(J: np.ndarray, previous: np.ndarray | None = None) -> np.ndarray:
    """The unit null vector of the ``n x (n+1)`` matrix ``J``, oriented along ``previous``
    (or with a positive parameter component)."""
    _, _, vt = np.linalg.svd(J)
    t = vt[-1]
    ref = previous if previous is not None else np.eye(len(t))[-1]
    return -t if float(np.dot(t, ref)) < 0 else t


def newton(G: Callable, J: Callable, u: np.ndarray, extra: Callable | None = None,
           tol: float = 1e-10, max_iter: int = 12) -> tuple[np.ndarray, int]:
    """Newton's method on ``G(u) = 0`` plus one scalar equation ``extra(u) = (value, grad)``.

    Returns the solution and the number of iterations; raises :class:`ArithmeticError` when
    it does not converge (residuals growing, non-finite values or ``max_iter`` reached).
    """
    u = np.array(u, dtype=float)
    last = np.inf
    for it in range(1, max_iter + 1):
        g = np.asarray(G(u), dtype=float)
        jm = np.asarray(J(u), dtype=float)
        e, grad = extra(u)
        r = np.append(g, e)
        norm = float(np.max(np.abs(r)))
        if not np.isfinite(norm):
            raise ArithmeticError("non-finite residual")
        M = np.vstack([jm, grad])
        du = np.linalg.solve(M, -r)
        u = u + du
        step = float(np.max(np.abs(du)))
        if step < tol * (1 + float(np.max(np.abs(u)))):
            return u, it
        if it > 3 and norm > 2 * last:
            raise ArithmeticError(f"Newton diverges (residual {norm:.3g})")
        last = norm
    raise ArithmeticError(f"Newton did not converge in {max_iter} iterations "
                          f"(residual {last:.3g})")


def trace(G: Callable, J: Callable, u0: np.ndarray, bounds: tuple[float, float], *,
          direction: float = 1.0, ds: float = 0.02, ds_min: float = 1e-6, ds_max: float = 0.1,
          max_points: int = 2000, inside: Callable[[np.ndarray], bool] | None = None,
          tol: float = 1e-10, periods: np.ndarray | None = None) -> Arc:
    """Follow the curve ``G(u) = 0`` from the solution ``u0`` in one direction.

    Parameters
    ----------
    G, J
        ``G(u)`` (length ``n``) and its Jacobian (``n x (n+1)``).
    u0
        A point of the curve (corrected here first with the parameter fixed).
    bounds
        The parameter range; the tracing stops on leaving it (the last point is put on
        the bound).
    direction
        ``+1`` or ``-1``: the initial sense of the parameter.
    ds, ds_min, ds_max
        Initial, smallest and largest arclength step (adapted to Newton's iterations).
    inside
        Further domain test (e.g. amplitude > 0); the tracing stops outside.
    periods
        The period of each component (0 for none, e.g. ``2 pi`` for a phase): a closed
        curve is recognised modulo these.

    Returns
    -------
    Arc
    """
    n1 = len(u0)
    e_last = np.eye(n1)[-1]
    u, _ = newton(G, J, u0, lambda v: (v[-1] - u0[-1], e_last), tol=tol)
    points = [ArcPoint(u, tangent(J(u), direction * e_last))]
    folds: list[np.ndarray] = []
    its = [0]

    def step(pt: ArcPoint, h: float) -> ArcPoint:
        u, t = pt.u, pt.tangent
        pred = u + h * t
        new, its[0] = newton(G, J, pred, lambda v: (float(np.dot(t, v - pred)), t), tol=tol)
        if not (np.all(np.isfinite(new)) and float(np.linalg.norm(new - u)) < 3 * h
                and (inside is None or inside(new))):
            raise ArithmeticError("the corrected point left the step or the domain")
        return ArcPoint(new, tangent(J(new), t))

    def crossed(pt: ArcPoint, new: ArcPoint) -> None:
        if new.tangent[-1] * pt.tangent[-1] < 0:
            f = _fold(G, J, pt.u, new.u, pt.tangent, new.tangent, tol)
            if f is not None:
                folds.append(f)

    def at_edge(pt: ArcPoint, new: ArcPoint, end: float) -> str:
        crossed(pt, new)
        try:
            v, _ = newton(G, J, new.u, lambda v: (v[-1] - end, e_last), tol=tol)
            if float(np.linalg.norm(v - pt.u)) > 1e-9 * (1 + float(np.linalg.norm(pt.u))):
                points.append(ArcPoint(v, tangent(J(v), new.tangent)))
        except (ArithmeticError, np.linalg.LinAlgError):
            pass
        return f"reached the bound {end:g}"

    def visit(pt: ArcPoint, new: ArcPoint, h: float):
        crossed(pt, new)
        if len(points) > 10 and passes_start(points[0].u, pt.u, new.u, periods):
            return pt, h, "closed curve"
        points.append(new)
        return new, min(ds_max, h * 1.4) if its[0] <= 3 else (h * 0.7 if its[0] > 6 else h), ""

    reason = walk(points[0], ds, step=step, visit=visit, ds_min=ds_min,
                  collapsed=lambda pt, exc: (f"the step fell below {ds_min:g} at parameter "
                                             f"{pt.u[-1]:.6g}"),
                  parameter=lambda pt: pt.u[-1], bounds=bounds, at_edge=at_edge,
                  max_turn=-2.0, full=lambda: (f"{max_points} points"
                                               if len(points) >= max_points else None))
    return Arc(tuple(points), tuple(folds), reason)


def both_ways(run: Callable[[float], Arc]) -> list[Arc]:
    """``[run(-1)]`` if that arc closed on itself, else ``[run(-1), run(+1)]``."""
    first = run(-1.0)
    return [first] if first.reason == "closed curve" else [first, run(1.0)]


def passes_start(start, u1, u2, periods=None) -> bool:
    """Whether the step ``u1 -> u2`` passes the start point (modulo ``periods``): the curve
    closed (the slow-flow curves here and the true response curves of
    :mod:`numerics.shooting.forced_branch`)."""
    s = np.array(start, dtype=float)
    if periods is not None:
        per = np.asarray(periods, dtype=float)
        k = per > 0
        s[k] = s[k] + per[k] * np.round((u2[k] - s[k]) / per[k])
    d = u2 - u1
    w = float(np.clip(np.dot(s - u1, d) / max(float(np.dot(d, d)), 1e-300), 0.0, 1.0))
    return float(np.linalg.norm(u1 + w * d - s)) < 0.25 * float(np.linalg.norm(d)) + 1e-9


def _fold(G, J, u1, u2, t1, t2, tol):
    """The fold between two points: Newton on ``G = 0`` and the parameter component of the
    tangent (by finite differences of the null vector), started from the secant root."""
    w = t1[-1] / (t1[-1] - t2[-1])
    guess = u1 + w * (u2 - u1)
    ref = t1 + w * (t2 - t1)

    def extra(v):
        c = tangent(J(v), ref)[-1]
        grad = np.zeros(len(v))
        for i in range(len(v)):
            dv = np.zeros(len(v))
            dv[i] = 1e-6 * (1 + abs(v[i]))
            grad[i] = (tangent(J(v + dv), ref)[-1] - c) / dv[i]
        return c, grad

    try:
        f, _ = newton(G, J, guess, extra, tol=max(tol, 1e-10), max_iter=20)
    except (ArithmeticError, np.linalg.LinAlgError):
        return guess  # the secant estimate: between two converged points of the curve
    if float(np.linalg.norm(f - guess)) > 2 * float(np.linalg.norm(u2 - u1)) + 1e-12:
        return guess
    return f
