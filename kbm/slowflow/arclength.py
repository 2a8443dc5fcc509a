"""The one pseudo-arclength driver of the toolkit (Keller 1977; Doedel, *Lecture notes on
numerical analysis of nonlinear equations*, sec. 2).

:func:`walk` follows a branch step by step, halving a failed step; what a step is
(predictor and corrector) and what is done at an accepted point are the caller's.  It
drives the slow-flow curves of :func:`kbm.slowflow.continuation.trace`, the periodic-orbit
branches of :mod:`numerics` (:func:`numerics.shooting.arclength.walk`) and the codim-1
curves of its diagrams (:func:`numerics.bifurcation.curve.continue_curve`).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

__all__ = ["walk", "TangentTurned"]


class TangentTurned(ArithmeticError):
    """A step whose tangent turned by more than the driver allows (a failed step)."""


def walk(first, ds: float, *, step: Callable, visit: Callable, collapsed: Callable,
         ds_min: float, parameter: Callable | None = None, bounds=None,
         at_edge: Callable | None = None, max_turn: float = 0.9, turn_above: float = 0.0,
         full: Callable | None = None,
         failures: tuple = (ArithmeticError, np.linalg.LinAlgError)):
    """Follow a branch from ``first`` by pseudo-arclength steps; the reason it ends.

    Parameters
    ----------
    first
        The first point (with a unit ``tangent`` oriented in the direction followed).
    ds
        The first step.
    step
        ``(point, ds) -> point``: predictor and corrector (raises one of ``failures``).
    visit
        ``(point, new, ds) -> (current, ds, reason)``: the caller's work at an accepted
        point ``new``: recording it, special points, the ends of the branch; the point to
        go on from, the next step and ``reason`` (not empty: the branch ends).
    collapsed
        ``(point, error) -> reason``: the step fell below ``ds_min`` at ``point``.
    parameter, bounds, at_edge
        The point's parameter and its range; a point outside it ends the branch with
        ``at_edge(point, new, edge) -> reason`` (the caller places the point at the edge).
    max_turn, turn_above
        A step whose tangent's cosine with the last falls below ``max_turn`` is a failed
        step (:class:`TangentTurned`), while the step is above ``turn_above``.
    full
        ``() -> reason or None``: asked before each step (a bound on the points).
    failures
        The errors that halve the step.
    """
    cur = first
    while True:
        why = full() if full is not None else None
        if why:
            return why
        try:
            new = step(cur, ds)
            turn = float(new.tangent @ cur.tangent)
            if turn < max_turn and ds > turn_above:
                deg = math.degrees(math.acos(max(-1.0, min(1.0, turn))))
                raise TangentTurned(f"the tangent turned by {deg:.0f} degrees")
        except (*failures, TangentTurned) as exc:
            ds /= 2
            if ds < ds_min:
                return collapsed(cur, exc)
            continue
        if bounds is not None:
            p = parameter(new)
            if p < bounds[0] or p > bounds[1]:
                return at_edge(cur, new, bounds[0] if p < bounds[0] else bounds[1])
        cur, ds, why = visit(cur, new, ds)
        if why:
            return why
