"""Frequency locking of self-excited oscillators: the edges of the locking region, averaged
against true.

A detuning ``sigma`` (frequency ``1 + mu sigma`` of the second oscillator) is followed
from 0 in both directions:

- **averaged**: the locked state is a fixed point of the slow flow ``(a, gamma)`` of
  :func:`kbm.expansion.coupled.derive_coupled` at order ``n``; it is continued in ``sigma`` and its
  fold (``f = 0``, ``det J = 0``) is solved by Newton on the augmented system;
- **true**: the locked state is a periodic orbit of the full ``2N``-dimensional system
  (:func:`numerics.shooting.coupled_orbit.coupled_cycle`, continued from the previous
  orbit); the edge is
  where it ceases to exist, bracketed by bisection and located as the fold of the locked
  cycle (:func:`numerics.locking.fold.true_edges`: the zero of the tangent's
  parameter component on the pseudo-arclength branch, with the non-trivial multiplier
  nearest 1 at 1 there, a saddle-node of cycles, as the check); where the cycle is lost
  otherwise (no fold: a torus bifurcation), the bisection goes on to ``tol``.

The amplitude death of the oscillators (the origin made stable by the coupling) is read
from the linearisation of the full system at the origin.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import sympy as sp

from kbm.model.coupled import CoupledOscillators
from kbm.model.coupled_builtins import get_coupled_model
from kbm.errors import ParameterError
from kbm.output.strict_json import complex_pairs, jsonable
from numerics.errors import NoCycleError
from numerics.flow.coupled_flow import bind_coupled
from numerics.locking.fold import LockingEdge, true_edges
from numerics.locking.start import AMPLITUDE_FLOOR, follow_steps, followed_axis, march_out, locked_start, side_limits, start_values
from numerics.locking.slow_flow import _newton, _slow_flow, _split

__all__ = ["LockingRegion", "averaged_edges", "amplitude_death",
           "locking_region", "plot_locking", "check_lockable",
           "COUPLING_NAMES", "coupling_names"]

#: the names a coupling parameter goes by (``c`` of ``coupled-vdp``, ``kappa`` of the
#: sliders, ``k`` of ``duffing-1-3``)
COUPLING_NAMES = ("c", "k", "kappa")


def coupling_names(model: CoupledOscillators) -> tuple[str, ...]:
    """The couplings among ``model``'s parameters: those named as in
    :data:`COUPLING_NAMES` that no physical name sets.  The sliders' ``k = 2 pi/lam`` is
    their wavenumber, a scaled parameter and no coupling: ``kbm lock sedf-dimer --vary
    k=...`` (like ``--vary lam=...``) follows it."""
    return tuple(k for k in COUPLING_NAMES
                 if k in model.parameters and k not in model.physical)


def averaged_edges(model: CoupledOscillators | str, params: Mapping[str, object], order: int,
                   parameter: str = "sigma", limit: float = 10.0, start=None,
                   at: float = 0.0, limits: Mapping[int, float] | None = None
                   ) -> list[LockingEdge]:
    """The edges ``sigma_-`` and ``sigma_+`` of locking from the order-``order`` slow flow.

    Parameters
    ----------
    model
        A coupled system with one internal resonance (its phase ``gamma1``).
    params
        Values of every parameter and ``mu`` (``parameter`` is ignored: it is followed).
    order
        The order of the averaged flow.
    parameter
        The detuning's name.
    limit
        ``|sigma - at|`` up to which an edge is looked for.
    start
        The locked state ``(a_1..a_N, gamma)`` at ``sigma = at`` (default: all ``a_i = 2``,
        ``gamma = 0``, the in-phase van der Pol cycle).
    at
        The value of ``parameter`` the locked state is followed from (default 0; a
        parameter that is no detuning, e.g. a coupling, from inside its range).
    limits
        ``{-1: d_minus, 1: d_plus}``: how far each side is followed from ``at`` (the ends
        of an interval, :func:`numerics.locking.start.side_limits`); default
        ``limit`` on both.

    Raises
    ------
    numerics.errors.NoCycleError
        If there is no locked state at ``sigma = at`` to start from.
    """
    model, values = bind_coupled(model, {**dict(params), parameter: at})
    mu = values["mu"]
    f, jac, m = _slow_flow(model, order, _split(model, values, parameter), parameter)
    y0 = np.array(start if start is not None else [2.0] * model.dof + [0.0] * (m - model.dof),
                  dtype=float)
    y = _newton(f, jac, y0, float(at), mu)
    if y is None:
        near = ", ".join(f"{float(v):g}" for v in y0)
        raise NoCycleError(f"the order-{order} slow flow of {model.name} has no locked state "
                           f"near (a, gamma) = ({near}) at {parameter} = {float(at):g}")
    lim = {-1: limit, 1: limit} if limits is None else limits
    return [_averaged_edge(f, jac, y, side, mu, lim[side], float(at)) for side in (-1, 1)]


def _averaged_edge(f, jac, y, side, mu, limit, at=0.0) -> LockingEdge:
    def locked(s, y):
        """The stable locked state at ``s`` continued from ``y`` (a jump to another fixed
        point, or an unstable one, or the origin past amplitude death, is not the state
        followed)."""
        trial = _newton(f, jac, y, s, mu, it=15)  # from the state next to it: a few steps
        if trial is None or not np.all(trial[:-1] > floor) \
                or np.max(np.abs(trial - y)) > 0.25:
            return None
        ev = np.linalg.eigvals(np.asarray(jac(trial, s, mu), dtype=float))
        return trial if np.all(ev.real < 0) else None

    floor = AMPLITUDE_FLOOR * float(np.max(np.abs(y[:-1])))
    # march out until the locked state is lost ...
    s, held, step = march_out(locked, at, y, side, limit, *follow_steps(limit))
    if step is None:
        return LockingEdge(math.copysign(math.inf, side), 0.0, side, tuple(held))
    last = (s, held)
    lo, hi = s, s + side * step
    while abs(hi - lo) > 1e-4:  # ... bracket the fold (the augmented Newton ends it) ...
        mid = 0.5 * (lo + hi)
        trial = locked(mid, last[1])
        if trial is None:
            hi = mid
        else:
            lo, last = mid, (mid, trial)
    step = abs(hi - lo)
    # Newton on the augmented system (y, sigma): f = 0, det J = 0
    z = np.concatenate([last[1], [last[0]]])
    dz = np.inf
    for _ in range(30):
        def g(zz):
            yy, ss = zz[:-1], zz[-1]
            return np.concatenate([np.asarray(f(yy, ss, mu), dtype=float),
                                   [np.linalg.det(np.asarray(jac(yy, ss, mu), dtype=float))]])
        g0 = g(z)
        h = 1e-7 * np.maximum(1.0, np.abs(z))
        G = np.empty((len(z), len(z)))
        for k in range(len(z)):
            e = np.zeros(len(z))
            e[k] = h[k]
            G[:, k] = (g(z + e) - g(z - e)) / (2 * h[k])
        try:
            dzv = np.linalg.solve(G, -g0)
        except np.linalg.LinAlgError:
            break
        z = z + dzv
        dz = float(abs(dzv[-1]))
        if dz < 1e-12:
            break
    if not (np.isfinite(z).all() and abs(z[-1] - last[0]) < 1e-2):
        return LockingEdge(last[0], abs(step), side, tuple(last[1]))
    return LockingEdge(float(z[-1]), max(dz, 1e-12), side, tuple(z[:-1]))


def amplitude_death(model: CoupledOscillators | str, params: Mapping[str, object]) -> dict:
    """The origin's stability from the full system's linearisation (exact eigenvalues).

    Returns ``{"dead": bool, "eigenvalues": [[re, im], ...]}``: ``dead`` when every
    eigenvalue has a negative real part (the oscillations are quenched by the coupling).
    """
    model, values = bind_coupled(model, params)
    state = list(model.state)
    n = model.dof
    f = [*state[n:], *model.accelerations()]
    sub = {sp.Symbol(k): v for k, v in values.items()}
    J = sp.Matrix(f).jacobian(state).subs({s: 0 for s in state}).subs(sub)
    ev = np.linalg.eigvals(np.array(J.evalf(), dtype=float))
    ev = ev[np.lexsort((ev.imag, -ev.real))]
    return {"dead": bool(np.all(ev.real < 0)),
            "eigenvalues": complex_pairs(ev)}


def check_lockable(model: CoupledOscillators) -> None:
    """Raise :class:`~kbm.errors.ParameterError` unless the model has exactly one declared
    internal resonance (the phase whose locking is followed)."""
    if len(model.internal) != 1:
        raise ParameterError(f"{model.name!r} declares {len(model.internal)} internal "
                             "resonances; the locking region is computed for one phase "
                             "combination (a model with one declared resonance, e.g. "
                             "coupled-vdp)")


@dataclass(frozen=True)
class LockingRegion:
    """The locking region in ``(c, sigma)``: averaged edges per order and the true ones.

    ``averaged[n]`` and ``true`` are lists of ``(c, sigma)`` pairs, both edges at every
    ``c``; ``errors`` the true edges' bisection brackets; ``starts`` the value of ``sigma``
    the locked state was followed from at each ``c`` (0 when the interval holds it);
    ``death`` the origin's linearisation at each ``c`` and that ``sigma``: its
    ``checked_at`` gives the values (the followed parameter as asked, its scaled name
    when that differs, e.g. ``Delta`` and ``delta``, and the coupling).
    """

    model: str
    params: Mapping[str, float]
    detuning: str
    coupling: str
    averaged: Mapping[int, list]
    true: list
    errors: list
    death: list
    starts: tuple = ()

    def to_json(self) -> dict:
        """The edges as ``[c, sigma]`` pairs, ``boundary_averaged`` by order (NaN as ``None``)."""
        return jsonable({"model": self.model, "params": self.params, "detuning": self.detuning,
                         "coupling": self.coupling, "boundary_averaged": self.averaged,
                         "boundary_true": self.true, "boundary_true_error": self.errors,
                         "amplitude_death": self.death})


def locking_region(model: CoupledOscillators | str, params: Mapping[str, object],
                   detuning: tuple[str, float, float], coupling: tuple[str, list] | None = None,
                   orders: tuple[int, ...] = (1, 2), tol: float = 1e-7) -> LockingRegion:
    """Both edges of the locking region at every coupling value, averaged and true.

    At each coupling value the locked state is followed from a value of the detuning inside
    ``[lo, hi]`` (:func:`locked_start`: 0 when the interval holds it, else the first value
    from its middle out at which the lowest order's slow flow has a stable locked state),
    each side up to its end of the interval.

    Parameters
    ----------
    model
        A coupled system with one declared internal resonance.
    params
        The other parameters and ``mu``.
    detuning
        ``(name, lo, hi)``: the parameter followed (a detuning, or any other, e.g. the
        ``beta`` of ``sedf-dimer``) and the interval its edges are looked for in.
    coupling
        ``(name, values)``; ``None`` keeps it at its ``params`` value.
    orders
        The averaged orders.
    tol
        The bisection bracket of the true edges.

    Raises
    ------
    kbm.errors.ParameterError
        For a model without exactly one internal resonance, or an unknown name.
    numerics.errors.NoCycleError
        If at a coupling value no stable locked state exists anywhere in ``[lo, hi]``.
    """
    model = get_coupled_model(model) if isinstance(model, str) else model
    axis = followed_axis(model, params, *detuning)  # Delta, lam: as delta, k
    name, (lo, hi) = axis.name, axis.span
    bound, values = bind_coupled(model, {**dict(params), name: start_values(lo, hi)[0]})
    check_lockable(bound)
    if coupling is None:  # a coupling among the model's own names
        cname = next((k for k in coupling_names(bound) if k != name), "")
        cvals = [values[cname]] if cname else [float("nan")]
    else:
        cname, cvals = coupling
        if cname not in bound.parameters:
            raise ParameterError(f"{cname!r} is not a parameter of {bound.name!r}")
    averaged: dict[int, list] = {n: [] for n in orders}
    true, errors, death, starts = [], [], [], []
    for cv in cvals:
        p = {**dict(params)}
        if cname:
            p[cname] = cv
        at = locked_start(bound, p, min(orders), name, (lo, hi),
                          f"{cname} = {cv:g}" if cname and coupling is not None else "",
                          axis)
        limits = side_limits(at, lo, hi)
        starts.append(axis.to_user(at))
        guess = {}
        for n in orders:
            got = [e for e in averaged_edges(bound, p, n, name, at=at, limits=limits)
                   if lo <= e.sigma <= hi]
            guess.update({e.side: e.sigma for e in got})
            averaged[n] += sorted((cv, axis.to_user(e.sigma)) for e in got)
        for s, err in sorted((axis.to_user(e.sigma), axis.error(e.sigma, e.error))
                             for e in true_edges(bound, p, name, tol=tol, guess=guess or None,
                                                 at=at, limits=limits) if lo <= e.sigma <= hi):
            true.append((cv, s))
            errors.append(err)
        where = {axis.user: axis.to_user(at), name: at, **({cname: cv} if cname else {})}
        death.append({"coupling": cv, **amplitude_death(bound, {**p, name: at}),
                      "checked_at": where})
    return LockingRegion(bound.name, {k: v for k, v in values.items() if k != name},
                         axis.user, cname, averaged, true, errors, death, tuple(starts))


def plot_locking(region: LockingRegion, path) -> "object":
    """The tongue: averaged edges per order as lines, true edges as points."""
    from numerics._plot import pyplot as _plt, save as _save

    plt = _plt()
    fig, ax = plt.subplots(figsize=(6, 4.2))
    styles = ["C0--", "C1-", "C2-.", "C4:"]
    for k, (n, pts) in enumerate(sorted(region.averaged.items())):
        for side in (-1, 1):
            sel = sorted((c, s) for c, s in pts if s * side > 0)
            if sel:
                ax.plot([s for _, s in sel], [c for c, _ in sel], styles[k % 4],
                        label=f"averaged, order {n}" if side > 0 else None)
    if region.true:
        ax.plot([s for _, s in region.true], [c for c, _ in region.true], "ko", ms=4,
                label="true (fold of the locked cycle)")
    ax.set_xlabel(f"detuning {region.detuning} (frequency 1 + mu {region.detuning})")
    ax.set_ylabel(f"coupling {region.coupling}")
    ax.set_title(f"{region.model}: 1:1 locking region, mu = {region.params.get('mu'):g}")
    return _save(fig, ax, path)
