"""The true frequency-response curve: periodic responses continued in the detuning.

The unknowns are ``u = (x(0), x'(0), sigma)`` and ``G(u) = y(T(sigma)) - y0``; its Jacobian
is ``[Phi(T) - I, dG/dsigma]`` (variational equations; a forward difference in ``sigma``).
Pseudo-arclength continuation by a case of the one driver
(:class:`numerics.shooting.continuation.Continuation`) follows the curve round its folds (the
jump points, where a Floquet multiplier passes through +1), so that stable and unstable
responses come out alike; every point is accepted by the one standard
(:mod:`numerics.shooting.acceptance`: the residual relative to the orbit's scale, and a
Newton correction that tells a true orbit from a residual minimum), so none lies past a
fold.  The branches start from the KBM slow-flow fixed points
(:func:`kbm.slowflow.steady.fixed_points`), each corrected by shooting.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from kbm.errors import ParameterError
from kbm.slowflow.continuation import passes_start
from kbm.expansion.forced_result import SlowFlow
from kbm.slowflow.steady import fixed_points

from numerics.errors import ConvergenceError, NumericsError
from numerics.shooting.forced_orbit import ForcedOrbit, orbit_at, periodic_response
from numerics.flow.forced_system import ForcedSystem
from numerics.shooting.acceptance import accepted, orbit_scale
from numerics.shooting.arclength import null_vector
from numerics.shooting.branch_problem import BranchProblem
from numerics.shooting.continuation import Continuation
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


class _Follow(Continuation):
    """The curve as a case of the one driver: a step out of ``|x(0)| < bound`` fails, the
    folds are located on the arc, the curve closes when it passes its start again, and the
    point at the end of the range is kept unless it is the last point."""

    record = staticmethod(lambda pt: pt)

    def __init__(self, system: ForcedSystem, bounds, ds: float, max_points: int, bound):
        ds_min = 1e-7 * (bounds[1] - bounds[0])
        super().__init__(_Response(system), bounds, ds=ds, ds_max=ds, ds_min=ds_min,
                         max_points=max_points, period_factor=0.0, hopf_fraction=0.0)
        self.turn_above, self.bound = 4 * ds_min, bound

    def begin(self, first: _Pt) -> None:
        pass

    def step(self, pt: _Pt, ds: float) -> _Pt:
        new = self.prob.arc(pt, ds)
        if not (np.all(np.isfinite(new.u)) and abs(new.u[0]) < self.bound) \
                or float(np.linalg.norm(new.u - pt.u)) > 3 * abs(ds):
            raise ConvergenceError(f"the step left the domain at sigma = {new.u[2]:.8g}")
        return new

    def collapsed(self, pt: _Pt, exc: Exception) -> str:
        return "the step collapsed"

    def locate(self, a: _Pt, b: _Pt, ds: float) -> None:
        if b.tangent[2] * a.tangent[2] < 0:
            self.special.append(fold_on_arc(self.step, a, b, ds).point or b)
        self.closed = len(self.points) > 10 and passes_start(self.points[0].u, a.u, b.u)

    def converged(self, pt: _Pt) -> bool:
        return not self.closed  # the point that closes the curve is its first

    def advance(self, a: _Pt, b: _Pt, ds: float):
        return b, min(2 * self.ds, 1.4 * ds)

    def end(self, a: _Pt, b: _Pt, ds: float) -> str:
        return "closed curve" if self.closed else ""

    def at_edge(self, a: _Pt, end: _Pt) -> None:
        if float(np.linalg.norm(end.u - a.u)) <= 1e-9 * (1 + float(np.linalg.norm(a.u))):
            raise ValueError("the end of the range is the last point")


def continue_response(system: ForcedSystem, start: ForcedOrbit, sigmas: tuple[float, float],
                      *, n_points: int = 400, amplitude_bound: float = 50.0):
    """The branch through ``start`` over ``sigmas`` (both directions), with its folds.

    Pseudo-arclength continuation by the one driver
    (:class:`numerics.shooting.continuation.Continuation`), every point accepted by the
    standard of :mod:`numerics.shooting.acceptance`; the folds located by
    :func:`numerics.shooting.locate.fold_on_arc`.

    Returns
    -------
    ``(orbits, folds)``: the :class:`ForcedOrbit` along the branch in its order, and those
    at its folds.
    """
    lo, hi = sigmas
    run = _Follow(system, (lo, hi), (hi - lo) / max(n_points, 10), 20 * n_points,
                  amplitude_bound)
    first = run.prob.fix(np.array([*start.y0, start.sigma]))
    points, folds, _ = run.run(_Pt(first.u, run.prob.evaluate(first.u)[1]), (-1, 1), False)
    orbits = tuple(orbit_at(system, p.u[:2], p.u[2]) for p in points)
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
    from numerics.shooting.special import detect_special

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
