"""The true frequency-response curve: periodic responses continued in the detuning.

The unknowns are ``u = (x(0), x'(0), sigma)`` and ``G(u) = y(T(sigma)) - y0``; its Jacobian
is ``[Phi(T) - I, dG/dsigma]`` (variational equations; a forward difference in ``sigma``).
Pseudo-arclength continuation by the one driver (:func:`numerics.shooting.arclength.walk`)
follows the curve round its folds (the jump points, where a Floquet multiplier passes
through +1), so that stable and unstable responses come out alike; every point is accepted
by the one standard (:mod:`numerics.shooting.acceptance`: the residual relative to the
orbit's scale, and a Newton correction that tells a true orbit from a residual minimum), so
none lies past a fold.  The branches start from the KBM slow-flow fixed
points (:func:`kbm.forced.steady.fixed_points`), each corrected by shooting.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from kbm.errors import ParameterError
from kbm.forced.arclength import passes_start
from kbm.forced.result import SlowFlow
from kbm.forced.steady import fixed_points

from numerics.errors import ConvergenceError, NumericsError
from numerics.forced.shooting import ForcedOrbit, orbit_at, periodic_response
from numerics.forced.system import ForcedSystem
from numerics.shooting.acceptance import accepted, orbit_scale
from numerics.shooting.arclength import FAIL, null_vector, walk
from numerics.shooting.branch_problem import BranchProblem
from numerics.shooting.locate import fold_on_arc

__all__ = ["NumericResponse", "numeric_response", "continue_response", "guess_from", "ACCURACY"]

#: the bound on a point's last Newton correction, relative to ``max(1, |u|)``: the accuracy
#: of the points of a branch (on top of the acceptance standard)
ACCURACY = 1e-9


@dataclass(frozen=True)
class NumericResponse:
    """Branches of true periodic responses and their folds."""

    branches: tuple[tuple[ForcedOrbit, ...], ...]
    folds: tuple[ForcedOrbit, ...]
    evaluations: int
    failures: tuple[str, ...] = ()
    special: tuple = ()

    def points(self) -> list[dict]:
        """``[{"sigma", "amplitude_max", "amplitude", "stable"}]`` along every branch."""
        return [{"sigma": o.sigma, "amplitude_max": o.amplitude_max, "amplitude": o.amplitude,
                 "stable": o.stable} for b in self.branches for o in b]


def guess_from(system: ForcedSystem, amplitude: float, phase: float, sigma: float):
    """``(x(0), x'(0))`` of ``x = a cos((q/p) nu t + phi)``."""
    w = system.resonance.q / system.resonance.p * system.nu(sigma)
    return amplitude * math.cos(phase), -amplitude * w * math.sin(phase)


class _Response(BranchProblem):
    """The response curve as a case of the one branch problem
    (:class:`numerics.shooting.branch_problem.BranchProblem`; a failed integration is a
    failed step): a point passes the standard of :mod:`numerics.shooting.acceptance`
    (forced: no trivial multiplier) with its last correction below :data:`ACCURACY`
    ``max(1, |u|)``; it is ``u`` plus that correction, with the Jacobian at ``u``."""

    max_iter = 12
    through_prediction = False
    vary = "sigma"

    def __init__(self, system: ForcedSystem):
        self.system = system

    def evaluate(self, u):
        try:
            if not np.all(np.isfinite(u)):
                raise ConvergenceError(f"left the finite numbers at sigma = {u[2]:.6g}")
            yT = self.system.flow(u[:2], u[2])[-1]
            h = 1e-7 * (1 + abs(u[2]))
            yh = self.system.flow(u[:2], u[2] + h, extended=False)[-1]
        except (NumericsError, ParameterError) as exc:
            raise ConvergenceError(str(exc)) from None
        Phi = np.array([[yT[2], yT[4]], [yT[3], yT[5]]])
        J = np.column_stack([Phi - np.eye(2), (yh[:2] - yT[:2]) / h])
        return yT[:2] - u[:2], J, J

    def accept(self, u, R, du, J, it) -> bool:
        corr = float(np.max(np.abs(du)))
        return (accepted(float(np.max(np.abs(R))), corr, self.system.rtol, orbit_scale(u[:2]))
                and corr <= ACCURACY * max(1.0, float(np.max(np.abs(u)))))

    def too_large(self, u, du) -> None:
        return None

    def point(self, u, R, du, J, it) -> "_Pt":
        return _Pt(u + du, J)


class _Pt:
    """A converged point ``u`` (``v`` is ``u``) and its unit tangent."""

    def __init__(self, u, J):
        self.u = self.v = u
        self.tangent = null_vector(J)


def _follow(system: ForcedSystem, first: _Pt, direction: int, bounds, ds: float,
            max_points: int, inside):
    """One direction of the curve by :func:`numerics.shooting.arclength.walk`, its folds
    located by :func:`numerics.shooting.locate.fold_on_arc`: ``(points, folds, closed)``."""
    prob = _Response(system)
    start = _Pt(first.u, prob.evaluate(first.u)[1])
    if start.tangent[2] * direction < 0:
        start.tangent = -start.tangent
    pts = [start]
    folds, closed, ds_min = [], [], 1e-7 * (bounds[1] - bounds[0])

    def step(pt, ds):
        new = prob.arc(pt, ds)
        if not inside(new.u) or float(np.linalg.norm(new.u - pt.u)) > 3 * abs(ds):
            raise ConvergenceError(f"the step left the domain at sigma = {new.u[2]:.8g}")
        return new

    def visit(cur, new, h):
        if new.tangent[2] * cur.tangent[2] < 0:
            folds.append(fold_on_arc(step, cur, new, h).point or new)
        if len(pts) > 10 and passes_start(pts[0].u, cur.u, new.u):
            closed.append(True)
            return new, h, "closed curve"
        pts.append(new)
        return new, min(2 * ds, 1.4 * h), ""

    def at_edge(cur, new, edge):
        try:
            end = prob.at_parameter(cur, new, edge)
            if float(np.linalg.norm(end.u - cur.u)) > 1e-9 * (1 + float(np.linalg.norm(cur.u))):
                pts.append(end)
        except FAIL:
            pass
        return f"reached the bound {edge:g}"

    walk(pts[0], ds, step=step, visit=visit, collapsed=lambda c, exc: "the step collapsed",
         ds_min=ds_min, parameter=lambda q: float(q.u[2]), bounds=bounds, at_edge=at_edge,
         turn_above=4 * ds_min, full=lambda: "full" if len(pts) >= max_points else None)
    return pts, folds, bool(closed)


def continue_response(system: ForcedSystem, start: ForcedOrbit, sigmas: tuple[float, float],
                      *, n_points: int = 400, amplitude_bound: float = 50.0):
    """The branch through ``start`` over ``sigmas`` (both directions), with its folds.

    Pseudo-arclength continuation by the one driver
    (:func:`numerics.shooting.arclength.walk`), every point accepted by the standard of
    :mod:`numerics.shooting.acceptance`; the folds located by
    :func:`numerics.shooting.locate.fold_on_arc`.

    Returns
    -------
    ``(orbits, folds)``: the :class:`ForcedOrbit` along the branch in its order, and those
    at its folds.
    """
    lo, hi = sigmas
    ds = (hi - lo) / max(n_points, 10)

    def inside(u):
        return bool(np.all(np.isfinite(u)) and abs(u[0]) < amplitude_bound)

    first = _Response(system).fix(np.array([*start.y0, start.sigma]))
    back, folds, closed = _follow(system, first, -1, (lo, hi), ds, 20 * n_points, inside)
    us = [p.u for p in reversed(back)]
    if not closed:
        ahead, more, _ = _follow(system, first, 1, (lo, hi), ds, 20 * n_points, inside)
        us += [p.u for p in ahead[1:]]
        folds += more
    orbits = tuple(orbit_at(system, u[:2], u[2]) for u in us)
    return orbits, tuple(orbit_at(system, f.u[:2], f.u[2]) for f in folds)


def numeric_response(system: ForcedSystem, sf: SlowFlow, sigmas: tuple[float, float],
                     amplitudes: tuple[float, float] = (1e-3, 5.0), *, n_points: int = 400,
                     seeds_at: int = 3) -> NumericResponse:
    """Every branch of true periodic responses reached from the slow flow's fixed points.

    At ``seeds_at`` detunings (the ends included) each fixed point of ``sf`` gives a
    shooting guess; a converged response not already on a branch is continued over the
    range.
    """
    lo, hi = float(sigmas[0]), float(sigmas[1])
    branches: list[tuple[ForcedOrbit, ...]] = []
    folds: list[ForcedOrbit] = []
    failures: list[str] = []
    for s0 in np.linspace(lo, hi, seeds_at):
        for fp in fixed_points(sf, float(s0), amplitudes):
            try:
                orb = periodic_response(system, fp.sigma,
                                        guess_from(system, fp.amplitude, fp.phase, fp.sigma))
            except NumericsError as exc:
                failures.append(str(exc))
                continue
            if _known(branches, orb):
                continue
            try:
                b, f = continue_response(system, orb, (lo, hi), n_points=n_points)
            except NumericsError as exc:
                failures.append(str(exc))
                continue
            branches.append(b)
            folds.extend(f)
    from numerics.forced.special import detect_special

    special = []
    for b in branches:
        special.extend(detect_special(system, b))
    return NumericResponse(tuple(branches), tuple(sorted(folds, key=lambda o: o.sigma)),
                           system.evaluations, tuple(failures),
                           tuple(sorted(special, key=lambda sp: sp.orbit.sigma)))


def _known(branches, orb: ForcedOrbit) -> bool:
    for b in branches:
        for o1, o2 in zip(b, b[1:]):
            if (o1.sigma - orb.sigma) * (o2.sigma - orb.sigma) <= 0 and o1.sigma != o2.sigma:
                w = (orb.sigma - o1.sigma) / (o2.sigma - o1.sigma)
                y = np.array(o1.y0) + w * (np.array(o2.y0) - np.array(o1.y0))
                tol = 1e-4 + np.linalg.norm(np.array(o2.y0) - np.array(o1.y0))
                if np.linalg.norm(y - np.array(orb.y0)) < tol:
                    return True
    return False
