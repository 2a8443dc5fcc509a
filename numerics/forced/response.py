"""The true frequency-response curve: periodic responses continued in the detuning.

The unknowns are ``u = (x(0), x'(0), sigma)`` and ``G(u) = y(T(sigma)) - y0``; its Jacobian
is ``[Phi(T) - I, dG/dsigma]`` (variational equations; a forward difference in ``sigma``).
Pseudo-arclength continuation (:func:`kbm.forced.arclength.trace`) follows the curve round
its folds (the jump points, where a Floquet multiplier passes through +1), so that stable
and unstable responses come out alike.  The branches start from the KBM slow-flow fixed
points (:func:`kbm.forced.steady.fixed_points`), each corrected by shooting.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from kbm.errors import ParameterError
from kbm.forced.arclength import both_ways, trace
from kbm.forced.result import SlowFlow
from kbm.forced.steady import fixed_points

from numerics.errors import NumericsError
from numerics.forced.shooting import ForcedOrbit, orbit_at, periodic_response
from numerics.forced.system import ForcedSystem

__all__ = ["NumericResponse", "numeric_response", "continue_response", "guess_from"]


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


class _Problem:
    """``G`` and its Jacobian with the last evaluation cached."""

    def __init__(self, system: ForcedSystem):
        self.s = system
        self._key = None
        self._val = None

    def _eval(self, u):
        key = tuple(np.round(u, 15))
        if key != self._key:
            try:
                yT = self.s.flow(u[:2], u[2])[-1]
                h = 1e-7 * (1 + abs(u[2]))
                yh = self.s.flow(u[:2], u[2] + h, extended=False)[-1]
            except (NumericsError, ParameterError) as exc:  # a failed step of the corrector
                raise ArithmeticError(str(exc)) from None
            g = yT[:2] - u[:2]
            dg = (yh[:2] - yT[:2]) / h
            Phi = np.array([[yT[2], yT[4]], [yT[3], yT[5]]])
            self._key, self._val = key, (g, np.column_stack([Phi - np.eye(2), dg]))
        return self._val

    def G(self, u):
        return self._eval(u)[0]

    def J(self, u):
        return self._eval(u)[1]


def continue_response(system: ForcedSystem, start: ForcedOrbit, sigmas: tuple[float, float],
                      *, n_points: int = 400, amplitude_bound: float = 50.0):
    """The branch through ``start`` over ``sigmas`` (both directions), with its folds."""
    lo, hi = sigmas
    span = hi - lo
    ds = span / max(n_points, 10)
    prob = _Problem(system)
    u0 = np.array([start.y0[0], start.y0[1], start.sigma])

    def inside(u):
        return bool(np.all(np.isfinite(u)) and abs(u[0]) < amplitude_bound)

    arcs = both_ways(lambda d: trace(prob.G, prob.J, u0, (lo, hi), direction=d, ds=ds,
                                      ds_max=2 * ds, ds_min=1e-7 * span,
                                      max_points=20 * n_points, inside=inside, tol=1e-9))
    us = [p.u for p in reversed(arcs[0].points)] + [p.u for a in arcs[1:] for p in a.points[1:]]
    orbits = tuple(orbit_at(system, u[:2], u[2]) for u in us)
    folds = tuple(orbit_at(system, f[:2], f[2]) for a in arcs for f in a.folds)
    return orbits, folds


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
