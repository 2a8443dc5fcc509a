"""Where ``kbm lock`` starts to follow the locked state: a value inside the asked interval.

The edges of locking are found by following the locked state out from one value of the
followed parameter in both directions (:mod:`numerics.locking.mutual`).  That value must
lie in the interval the user asked for, and the state must be locked there:

- a detuning whose interval holds 0 starts at 0, the symmetric point of a 1:1 tongue
  (``coupled-vdp``'s ``--vary sigma=-1:1``: the same edges as ever);
- otherwise (an interval that excludes 0, or a parameter that is no detuning, e.g. the
  ``beta`` of ``sedf-dimer``, for which 0 is meaningless) the middle of the interval, then
  the points of a grid over it by their distance from the middle, the ends last: the first
  at which the averaged slow flow has a *stable* locked fixed point.

Each side is followed only up to its own end of the interval (:func:`side_limits`), in
steps scaled to that span (:func:`follow_steps`): a wide interval, or an axis in other
units, is crossed in as many steps as ``--vary sigma=-1:1``.

A physical name on the command line (``--vary Delta=...`` or ``lam=...`` of the sliders,
``delta = Delta/mu``, ``k = 2 pi/lam``) is followed as the model's own parameter over the
mapped interval, and the edges are mapped back (:func:`followed_axis`, the binding
:func:`kbm.parameters.names.physical_axis`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping

import numpy as np

from kbm.model.coupled import CoupledOscillators
from kbm.errors import ParameterError
from kbm.parameters.names import PhysicalAxis, physical_axis
from numerics.errors import NoCycleError
from numerics.flow.coupled_flow import bind_coupled
from numerics.locking.slow_flow import _newton, _slow_flow, _split

__all__ = ["start_values", "side_limits", "first_locked", "locked_start", "followed_axis",
           "follow_steps", "march_out", "AMPLITUDE_FLOOR", "GRID_POINTS", "STABILITY_MARGIN", "FIRST_STEP", "LARGEST_STEP",
           "SMALLEST_STEP"]

#: points of the grid over the asked interval at which a locked state is looked for
GRID_POINTS = 9

#: the start's eigenvalues have real parts below ``-STABILITY_MARGIN`` times the largest
#: modulus: a point on the slow flow's fold (an eigenvalue 0 to rounding, e.g.
#: ``coupled-vdp``'s order-1 edge ``sigma = c`` on the grid) is no start
STABILITY_MARGIN = 1e-6

#: the smallest amplitude of a locked state, relative to the largest of the state it is
#: continued from: past the point where the locked state dies into the origin (amplitude
#: death) Newton on the polar slow flow converges to amplitudes of 1e-40, which are the
#: origin, not a locked state
AMPLITUDE_FLOOR = 1e-8

#: the follow's first step, as a fraction of the span followed on a side
FIRST_STEP = 0.02
#: its largest step (a step grows 1.5 times after each success), the same fraction
LARGEST_STEP = 0.1
#: its smallest step (halved after each failure down to it, then the edge is bracketed),
#: absolute, or the first step if that is smaller
SMALLEST_STEP = 1e-3


def start_values(lo: float, hi: float, points: int = GRID_POINTS) -> list[float]:
    """The values of the followed parameter tried as the start, in order: 0 when inside
    ``[lo, hi]``, then the middle, then a ``points``-point grid over ``[lo, hi]`` by distance
    from the middle (the lower first of two at the same distance)."""
    lo, hi = float(lo), float(hi)
    grid = [lo + (hi - lo) * k / (points - 1) for k in range(points - 1)] + [hi]  # hi exact
    mid = 0.5 * (lo + hi)
    out = [0.0] if lo <= 0.0 <= hi else []
    for s in [mid, *sorted(grid, key=lambda s: (abs(s - mid), s))]:
        if all(s != t for t in out):
            out.append(s)
    return out


def side_limits(at: float, lo: float, hi: float) -> dict[int, float]:
    """How far the state is followed from ``at`` on each side (-1, +1): to the interval's
    end on that side (0 on a side where ``at`` is the end)."""
    return {-1: max(float(at) - float(lo), 0.0), 1: max(float(hi) - float(at), 0.0)}


def follow_steps(span: float) -> tuple[float, float, float]:
    """The first, largest and smallest step of the follow of the locked state over ``span``
    (the distance from the start to the end of the interval on that side): the fractions
    :data:`FIRST_STEP` and :data:`LARGEST_STEP` of it, and :data:`SMALLEST_STEP` or the
    first step, the smaller (``span = 1``, a side of ``--vary sigma=-1:1`` from 0, gives
    0.02, 0.1 and 1e-3: the steps as they were).  The smallest step does not scale up: a
    failure at a step above it is taken for too long a step (the state moved too far for
    Newton), not for the edge, so a wide interval brackets its edges no coarser than
    before; nor down below 1e-3 unless the first step is smaller (a halving more per edge
    is a shot more).  A span that is not finite and positive counts as 1."""
    span = float(span)
    if not (math.isfinite(span) and span > 0.0):
        span = 1.0
    return FIRST_STEP * span, LARGEST_STEP * span, min(SMALLEST_STEP, FIRST_STEP * span)


def march_out(locked: Callable, at: float, state, side: int, limit: float, step: float,
              largest: float, smallest: float, *, grow: bool = True):
    """``(s, state, step)``: the last point held following ``locked(s, state)`` (the state at
    ``s`` from ``state``, or ``None``) from ``at`` on ``side`` in the steps of
    :func:`follow_steps` (growing where ``grow``), and the step that failed from it (``None``
    where ``limit`` from ``at`` was reached)."""
    s = at
    while abs(s - at) < limit:
        nxt = locked(s + side * step, state)
        if nxt is None:  # past the edge, or too long a step to follow the state
            if step <= smallest:
                return s, state, step
            step /= 2
            continue
        s, state = s + side * step, nxt
        if grow:
            step = min(step * 1.5, largest)
    return s, state, None


def first_locked(f: Callable, jac: Callable, y0: np.ndarray, values: list[float], mu: float,
                 dof: int) -> tuple[float, np.ndarray] | None:
    """The first of ``values`` at which Newton from ``y0`` finds a stable fixed point of the
    slow flow ``f(y, s, mu)`` (its amplitudes ``y[:dof]`` above :data:`AMPLITUDE_FLOOR`
    times those of ``y0``, every eigenvalue of
    ``jac`` in the left half-plane by :data:`STABILITY_MARGIN`), with that point; ``None``
    if there is none."""
    for s in values:
        y = _newton(f, jac, np.asarray(y0, dtype=float), float(s), mu)
        if y is None or not np.all(y[:dof] > AMPLITUDE_FLOOR * np.max(np.abs(y0[:dof]))):
            continue
        J = np.asarray(jac(y, float(s), mu), dtype=float)
        if not np.all(np.isfinite(J)):
            continue
        ev = np.linalg.eigvals(J)
        if np.max(ev.real) < -STABILITY_MARGIN * np.max(np.abs(ev)):
            return float(s), y
    return None


def locked_start(model: CoupledOscillators, params: Mapping[str, object], order: int,
                 parameter: str, span: tuple[float, float], where: str = "",
                 axis: PhysicalAxis | None = None) -> float:
    """The value of ``parameter`` in ``span`` that the locked state is followed from: the
    first of :func:`numerics.locking.start.start_values` at which the order-``order``
    slow flow has a stable locked fixed point near the in-phase state ``a_i = 2``,
    ``gamma = 0`` (``where`` names the coupling value, ``axis`` the user's name and
    interval, for the message).

    Raises
    ------
    numerics.errors.NoCycleError
        If there is none: the message gives the interval and the values tried in
        ``--vary``/``-p`` terms.
    """
    lo, hi = span
    tried = start_values(lo, hi)
    model, values = bind_coupled(model, {**dict(params), parameter: tried[0]})
    mu = values["mu"]
    f, jac, m = _slow_flow(model, order, _split(model, values, parameter), parameter)
    y0 = np.array([2.0] * model.dof + [0.0] * (m - model.dof))
    got = first_locked(f, jac, y0, tried, mu, model.dof)
    if got is None:
        ax = axis or PhysicalAxis(parameter, lo, hi, parameter, (lo, hi))
        at = ", ".join(f"{s:g}" for s in sorted(ax.to_user(s) for s in tried))
        raise NoCycleError(f"no locked state of {model.name} for {ax.user} in [{ax.lo:g}, "
                           f"{ax.hi:g}] (--vary {ax.user}={ax.lo:g}:{ax.hi:g}"
                           + (f", {where}" if where else "") + f", mu = {mu:g}): the "
                           f"order-{order} slow flow has no stable locked state at "
                           f"{ax.user} = {at}; ask another interval of {ax.user}"
                           + (" or other coupling values" if where else
                              " or other values of -p (a stronger coupling)"))
    return got[0]


def followed_axis(model: CoupledOscillators, params: Mapping[str, object], user: str,
                  lo: float, hi: float) -> PhysicalAxis:
    """The axis ``kbm lock`` follows for ``--vary user=lo:hi`` on ``model`` with the other
    values ``params`` (no defaults: a map's inputs are given), bound by
    :func:`kbm.parameters.names.physical_axis`: the model's own name as it is, a physical one as
    its scaled parameter over the mapped interval.

    Raises
    ------
    kbm.errors.ParameterError
        For a physical name that sets no or several of the model's parameters, a map
        input without a value, or a map that is not finite and monotone on ``[lo, hi]``.
    """
    import sympy as sp

    lo, hi = float(lo), float(hi)
    if user in model.parameters or user == "mu":
        return PhysicalAxis(user, lo, hi, user, (lo, hi))
    maps = {k: sp.sympify(e) for k, e in model.physical.items()
            if user in {x.name for x in sp.sympify(e).free_symbols}}
    if len(maps) != 1:
        raise ParameterError(f"kbm lock follows one of the parameters of {model.name!r} "
                             f"({', '.join(sorted(model.parameters))}); {user} sets "
                             f"{len(maps)} of them: vary one of those instead"
                             if maps else f"{user!r} is not a parameter of "
                             f"{model.name!r}; its parameters are "
                             f"{', '.join(sorted(model.parameters))}")
    (name, expr), = maps.items()
    rule = f"{name} = {sp.sstr(expr)}"
    missing = sorted(x.name for x in expr.free_symbols if x.name != user
                     and x.name not in params)
    if missing:
        raise ParameterError(f"{rule}: give -p {missing[0]}=VALUE to vary {user}")
    axis = physical_axis(maps, user, lo, hi, params)
    if not axis.monotone:
        raise ParameterError(f"{rule} is not finite and monotone for {user} in [{lo:g}, "
                             f"{hi:g}] (--vary {user}={lo:g}:{hi:g}): give an "
                             f"interval of {user} on one side of its poles")
    return axis
