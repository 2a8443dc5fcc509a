"""Branches of periodic orbits of coupled systems in one parameter (``kbm branch``,
``kbm response`` for ``N`` degrees of freedom, ``N = 1`` included): pseudo-arclength
continuation of the shooting problem (:class:`numerics.shooting.branch_problem.OrbitProblem`,
scaled unknowns ``(y0, T, p)`` autonomous, ``(y0, p)`` forced) by
:class:`CoupledContinuation`, a case of the one driver
(:class:`numerics.shooting.continuation.Continuation`), with the results of
:mod:`numerics.shooting.branch_result`.

The special points: fold (the parameter component of the tangent), period doubling
(``det(Phi + I)``, a real multiplier through ``-1``) and Neimark-Sacker
(``prod_{i<j} (lambda_i lambda_j - 1)`` over the non-trivial multipliers, kept only where
the located pair is complex: a real pair ``lambda, 1/lambda`` is a neutral saddle), located
as AUTO-07p does (a test function's sign change, bisection on the chord by the one locator,
:func:`numerics.shooting.locate.zero_on_chord`; Doedel, *Lecture notes on numerical
analysis of nonlinear equations*, sec. 2).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from kbm.model.coupled import CoupledOscillators
from kbm.errors import ParameterError
from numerics.shooting.branch_result import CoupledBranch, CoupledBranchPoint, CoupledSpecialPoint
from numerics.shooting.coupled_orbit import coupled_cycle, forced_response
from numerics.flow.coupled_flow import bind_coupled, coupled_flow
from numerics.errors import ConvergenceError, IntegrationError, NoCycleError
from numerics.shooting.arclength import FAIL as _FAIL
from numerics.shooting.arclength import parameter_range
from numerics.shooting.branch_problem import OrbitPoint, OrbitProblem
from numerics.shooting.continuation import Continuation
from numerics.shooting.locate import zero_on_chord

__all__ = ["continue_coupled",
           "CoupledContinuation"]


class CoupledContinuation(Continuation):
    """The case of ``N`` degrees of freedom of the one driver: folds, period doublings and
    Neimark-Sacker points located on the chord, isolas (the branch closes on itself), and
    an autonomous branch's ends at a long period or a small amplitude."""

    edge_text = "reached {name} = {edge:g}, the end of the range"
    reason_text = "towards {side} {name}: {why}"

    @staticmethod
    def record(pt: OrbitPoint) -> CoupledBranchPoint:
        return CoupledBranchPoint(float(pt.u[-1]), float(pt.T),
                                  tuple(float(v) for v in pt.u[:len(pt.Phi)]), pt.amps,
                                  tuple(complex(z) for z in pt.mults),
                                  bool(np.all(np.abs(pt.rest) < 1.0)), pt.res)

    def begin(self, first: OrbitPoint) -> None:
        self.first, self.amp0 = first, max(first.amps)

    def collapsed(self, c: OrbitPoint, exc: Exception) -> str:
        return (f"the steps collapsed below {self.ds_min:g} at {self.name} = {c.u[-1]:.10g} "
                f"(period {c.T:.8g}): {exc}")

    def at_edge(self, cur: OrbitPoint, end: OrbitPoint) -> None:
        end.tangent = cur.tangent
        self.locate(cur, end, 0.0)

    def advance(self, cur: OrbitPoint, new: OrbitPoint, ds: float):
        return new, min(ds * 1.5, self.ds_max)

    def end(self, cur: OrbitPoint, new: OrbitPoint, ds: float) -> str:
        name, pts, first = self.name, self.points, self.first
        p = float(new.u[-1])
        if len(pts) > 8 and np.linalg.norm(new.v - first.v) < ds \
                and new.tangent @ first.tangent > 0.9:
            self.closed = True
            return (f"the branch closed on itself after {len(pts) - 1} points (an "
                    f"isola: {name} from {min(q.parameter for q in pts):.10g} to "
                    f"{max(q.parameter for q in pts):.10g})")
        if not self.prob.forced and new.T > self.period_factor * first.T:
            return (f"the period grew to {new.T:.6g}, {self.period_factor:g} times its "
                    f"start, at {name} = {p:.10g}: a homoclinic end is near")
        if not self.prob.forced and max(new.amps) < self.hopf_fraction * self.amp0:
            return (f"the amplitude fell to {max(new.amps):.3g} at {name} = "
                    f"{p:.10g}: the cycle shrinks to an equilibrium (a Hopf end)")
        return ""

    def locate(self, a: OrbitPoint, b: OrbitPoint, ds: float) -> None:
        fa, fb = _tests(a), _tests(b)
        for kind in ("fold", "period-doubling", "neimark-sacker"):
            if fa[kind] * fb[kind] >= 0:
                continue
            found = zero_on_chord(self.prob.correct, a, b, lambda pm: _tests(pm)[kind],
                                  fa[kind])
            if found is None:
                continue
            pt, bracket = found
            if kind == "neimark-sacker":
                close = [z for z in pt.rest if abs(abs(z) - 1) < 1e-3 and abs(z.imag) > 1e-6]
                if not close:
                    continue  # a real pair lambda, 1/lambda: a neutral saddle
            if kind == "period-doubling" and not any(abs(z + 1) < 1e-3 for z in pt.rest):
                continue
            self.special.append(CoupledSpecialPoint(
                kind, float(pt.u[-1]), float(pt.T), pt.amps, tuple(complex(z) for z in pt.mults),
                bracket, tuple(float(v) for v in pt.u[:len(pt.Phi)])))


def _tests(pt: OrbitPoint) -> dict[str, float]:
    """The test functions at ``pt``: fold, period doubling, Neimark-Sacker."""
    z = pt.rest
    ns = 1.0
    for i in range(len(z)):
        for j in range(i + 1, len(z)):
            ns *= (z[i] * z[j] - 1.0)
    return {"fold": float(pt.tangent[-1]),
            "period-doubling": float(np.real(np.prod(1.0 + z))),
            "neimark-sacker": float(np.real(ns))}


def _distinct(special: list[CoupledSpecialPoint]) -> list[CoupledSpecialPoint]:
    """Each located point once (a point met again, from the other side of the start or
    around a closed branch, is dropped)."""
    out: list[CoupledSpecialPoint] = []
    for s in special:
        if not any(o.kind == s.kind
                   and abs(o.parameter - s.parameter) <= 1e-7 * max(1.0, abs(o.parameter))
                   and np.max(np.abs(np.subtract(o.state, s.state))) < 1e-4 for o in out):
            out.append(s)
    return out


def continue_coupled(model: CoupledOscillators | str, params: Mapping[str, object] | None,
                     vary: str, bounds: tuple[float, float], *, start=None,
                     directions: tuple[int, ...] = (1, -1), ds: float | None = None,
                     ds_max: float | None = None, ds_min: float = 1e-6,
                     max_points: int = 200, rtol: float = 1e-11,
                     period_factor: float = 8.0, hopf_fraction: float = 0.02,
                     transient: float | None = None) -> CoupledBranch:
    """A branch of periodic orbits of a coupled system as ``vary`` runs over ``bounds``.

    Parameters
    ----------
    model
        A :class:`~kbm.model.coupled.CoupledOscillators` (``N = 1`` included) or a built-in name.
    params
        The other values (``mu`` included); the value of ``vary`` in it, if any, is where
        the branch starts (default ``bounds[0]``).
    vary
        A parameter of the model or ``mu`` (for a forced system, its detuning follows the
        frequency response).
    bounds
        ``(FROM, TO)`` with ``FROM < TO``.
    start
        The state ``(x_1..x_N, xdot_1..xdot_N)`` to start from (default: the attracting
        orbit after a transient, :func:`~numerics.shooting.coupled_orbit.coupled_cycle` or
        :func:`~numerics.shooting.coupled_orbit.forced_response`).
    directions
        ``1`` towards larger ``vary``, ``-1`` towards smaller (both by default).
    ds, ds_max, ds_min
        First, largest and smallest arclength step in the scaled unknowns ``y0/Y, T/T0,
        p/(TO - FROM)`` (``Y`` the largest ``|y0|`` at the start, ``T0`` the first period;
        defaults ``1/25`` and a quarter of it; a step whose tangent turns by more than 25
        degrees is halved).
    max_points
        Bound on the points per direction.
    rtol
        Integrator tolerance.
    period_factor, hopf_fraction
        An autonomous branch ends when the period exceeds this multiple of its start, or
        the largest amplitude falls below this fraction of its start.
    transient
        The transient before the first orbit (see
        :func:`~numerics.shooting.coupled_orbit.coupled_cycle`).

    Raises
    ------
    kbm.errors.ParameterError
        For an unknown parameter, an empty range, a start value outside it.
    numerics.errors.NoCycleError
        If there is no periodic orbit to start from.
    """
    params = dict(params or {})
    lo, hi, p0 = parameter_range(vary, bounds, params)
    params.pop(vary, None)
    m, _ = bind_coupled(model, {**params, vary: p0})
    names = set(m.parameters) | {"mu"}
    if vary not in names:
        raise ParameterError(f"{vary!r} is not a parameter of {m.name!r} (its parameters: "
                             f"{', '.join(sorted(names))})")
    if not 0 < rtol < 1e-4:
        raise ParameterError(f"rtol must be between 0 and 1e-4, got {rtol:g}")
    prob = OrbitProblem(m, params, vary, rtol, coupled_flow)
    try:
        if m.forced:
            r = forced_response(m, {**params, vary: p0}, start=start,
                                transient_periods=0 if start is not None else None)
            u0 = np.append(r.state, p0)
        else:
            c = coupled_cycle(m, {**params, vary: p0}, start=start, transient=transient)
            u0 = np.concatenate([c.state, [c.period, p0]])
    except (ConvergenceError, NoCycleError, IntegrationError) as exc:
        raise NoCycleError(f"no periodic orbit of {m.name} at {vary} = {p0:g} to start the "
                           f"branch from: {exc}") from None
    try:
        first = prob.start(u0, max(hi - lo, 1e-6))
    except _FAIL as exc:
        raise NoCycleError(f"the orbit at {vary} = {p0:g} does not converge as a branch "
                           f"point: {exc}") from None
    ds_max = ds_max or 1.0 / 25
    run = CoupledContinuation(prob, (lo, hi), ds=ds or ds_max / 4, ds_max=ds_max,
                              ds_min=ds_min, max_points=max_points,
                              period_factor=period_factor, hopf_fraction=hopf_fraction)
    points, special, reasons = run.run(first, directions, prepend=False)
    special.sort(key=lambda s: s.parameter)
    return CoupledBranch(m.name, vary, (lo, hi), tuple(points), tuple(_distinct(special)),
                         tuple(reasons), prob.evaluations, forced=m.forced, dof=m.dof)
