"""Branches of periodic orbits of coupled systems in one parameter (``kbm branch``,
``kbm response`` for ``N`` degrees of freedom).

Pseudo-arclength continuation (Keller; Doedel, *Lecture notes on numerical analysis of
nonlinear equations*, sec. 2) of the shooting problem, for ``N = 1`` as for ``N > 1``:

- an autonomous system: unknowns ``u = (y0, T, p)``, equations ``phi_T(y0; p) - y0 = 0``
  and the phase condition ``xdot_1(0) = 0``;
- a forced system (``theta = nu t``): unknowns ``u = (y0, p)``, the period
  ``T = m 2 pi/nu(p)`` fixed by the forcing, equations ``phi_T(y0; p) - y0 = 0``.

The Jacobian holds the monodromy ``Phi - I``, the field at the end (autonomous, for ``T``)
and a central difference in ``p``; the tangent is its null vector, the corrector Newton's
method on the hyperplane normal to it.  Every point has all ``2N`` Floquet multipliers.

Special points are located as AUTO-07p does, by a test function that changes sign between
two points and bisection along the arclength:

- fold: the parameter component of the tangent;
- period doubling: ``det(Phi + I)`` (a real multiplier through ``-1``);
- Neimark-Sacker (torus): ``prod_{i<j} (lambda_i lambda_j - 1)`` over the non-trivial
  multipliers, kept only where the located pair is complex (a real pair ``lambda, 1/lambda``
  also zeroes it: a neutral saddle, not a bifurcation).
"""

from __future__ import annotations

import copy
import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from kbm.coupled import CoupledOscillators
from kbm.errors import ParameterError
from numerics.coupled.cycle import coupled_cycle, forced_response
from numerics.cycles.acceptance import accepted, orbit_scale, trivial_ok
from numerics.cycles.corrector import correct_on_hyperplane
from numerics.coupled.flow import bind_coupled, coupled_flow
from numerics.errors import ConvergenceError, IntegrationError, NoCycleError

__all__ = ["CoupledBranch", "CoupledBranchPoint", "CoupledSpecialPoint", "continue_coupled"]

_FAIL = (ConvergenceError, IntegrationError, np.linalg.LinAlgError, ParameterError)


def _mult(z: complex):
    return float(z.real) if z.imag == 0 else [float(z.real), float(z.imag)]


@dataclass(frozen=True)
class CoupledBranchPoint:
    """A periodic orbit on a branch: the parameter, the period, the state at the section
    (autonomous: ``xdot_1 = 0``; forced: ``t = 0``), ``max |x_i|`` over the orbit, the
    ``2N`` multipliers (autonomous: the trivial one first) and Newton's last residual."""

    parameter: float
    period: float
    state: tuple[float, ...]
    amplitudes: tuple[float, ...]
    floquet_multipliers: tuple[complex, ...]
    stable: bool
    residual: float

    def to_json(self) -> dict:
        return {"parameter": self.parameter, "period": self.period,
                "state": list(self.state), "amplitudes": list(self.amplitudes),
                "floquet_multipliers": [_mult(z) for z in self.floquet_multipliers],
                "stable": self.stable, "residual": self.residual}


@dataclass(frozen=True)
class CoupledSpecialPoint:
    """A located special point: ``kind`` is ``fold``, ``period-doubling`` or
    ``neimark-sacker``; ``bracket`` the final bisection interval of the parameter, ``state``
    the orbit's state at the section (a symmetric system has its partner orbit's point at
    the same parameter: both are listed)."""

    kind: str
    parameter: float
    period: float
    amplitudes: tuple[float, ...]
    floquet_multipliers: tuple[complex, ...]
    bracket: tuple[float, float]
    state: tuple[float, ...] = ()

    def to_json(self) -> dict:
        return {"kind": self.kind, "parameter": self.parameter, "period": self.period,
                "amplitudes": list(self.amplitudes),
                "floquet_multipliers": [_mult(z) for z in self.floquet_multipliers],
                "bracket": list(self.bracket), "state": list(self.state)}


@dataclass(frozen=True)
class CoupledBranch:
    """A branch of periodic orbits of a coupled system in one parameter.

    ``reasons`` says why each direction ended (the range's end, a collapse of the steps
    with the numbers, the period's growth, the amplitude's decay to a Hopf point).
    """

    model: str
    parameter: str
    bounds: tuple[float, float]
    forced: bool
    dof: int
    points: tuple[CoupledBranchPoint, ...]
    special: tuple[CoupledSpecialPoint, ...]
    reasons: tuple[str, ...]
    evaluations: int

    def to_json(self) -> dict:
        return {"model": self.model, "parameter": self.parameter, "bounds": list(self.bounds),
                "forced": self.forced, "dof": self.dof,
                "points": [p.to_json() for p in self.points],
                "special": [s.to_json() for s in self.special],
                "reasons": list(self.reasons), "evaluations": self.evaluations}


class _Problem:
    """``R(u)``, its Jacobian and the multipliers, for one model and one parameter."""

    def __init__(self, model: CoupledOscillators, params: dict, vary: str, rtol: float):
        self.model, self.params, self.vary, self.rtol = model, params, vary, rtol
        self.n = model.dof
        self.forced = model.forced
        self.evaluations = 0
        if self.forced:
            self.m = model.response_periods
        self._flows: dict[float, object] = {}
        self._base = None  # compiled once; a model parameter is then a value of it
        #: the unknowns are ``u = scale * v``; steps are taken in ``v`` (each component of
        #: order one along the branch: a weighted arclength, as AUTO-07p's THL/THU)
        self.scale: np.ndarray | None = None

    def flow(self, p: float):
        fl = self._flows.get(p)
        if fl is None:
            if len(self._flows) > 32:
                self._flows.clear()
            if self._base is None:
                self._base = coupled_flow(self.model, {**self.params, self.vary: p})
            if self.vary in self._base.values:
                fl = self._base.at(**{self.vary: p})
            else:  # a physical name (Delta): its scaled values are bound again
                fl = coupled_flow(self.model, {**self.params, self.vary: p})
            self._flows[p] = fl
        return fl

    def period(self, u: np.ndarray, fl) -> float:
        return self.m * 2 * math.pi / fl.nu if self.forced else float(u[2 * self.n])

    def residual(self, v: np.ndarray):
        """``(R, Phi, yT, fl, T)`` at ``u = scale * v``."""
        n2 = 2 * self.n
        u = v * self.scale
        p = float(u[-1])
        fl = self.flow(p)
        T = self.period(u, fl)
        if not (T > 0 and np.all(np.isfinite(u))):
            raise ConvergenceError(f"left the domain: T = {T:.6g} at {self.vary} = {p:.8g}")
        self.evaluations += 1
        yT, Phi, _ = fl.monodromy(u[:n2], T, rtol=self.rtol)
        R = yT - u[:n2]
        if not self.forced:
            R = np.append(R, u[self.n])  # the phase condition xdot_1(0) = 0
        return R, Phi, yT, fl, T

    def jacobian(self, v: np.ndarray, Phi, yT, fl, T) -> np.ndarray:
        """``dR/dv`` (the monodromy, the field, a central difference in the parameter)."""
        n2 = 2 * self.n
        u = v * self.scale
        p = float(u[-1])
        h = 1e-6 * max(1.0, abs(p))
        vp, vm = v.copy(), v.copy()
        vp[-1], vm[-1] = (p + h) / self.scale[-1], (p - h) / self.scale[-1]
        dp = (self.residual(vp)[0] - self.residual(vm)[0]) / (2 * h)
        rows = len(dp)
        J = np.zeros((rows, len(u)))
        J[:n2, :n2] = Phi - np.eye(n2)
        if not self.forced:
            J[:n2, n2] = fl.rhs(yT, T)
            J[n2, self.n] = 1.0
        J[:, -1] = dp
        return J * self.scale

    def multipliers(self, Phi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(all, non-trivial)``: autonomous systems have the trivial one first."""
        z = np.linalg.eigvals(Phi)
        if self.forced:
            z = z[np.lexsort((z.imag, -np.abs(z)))]
            return z, z
        k = int(np.argmin(np.abs(z - 1.0)))
        rest = np.delete(z, k)
        rest = rest[np.lexsort((rest.imag, -np.abs(rest)))]
        return np.concatenate([[z[k]], rest]), rest


class _Pt:
    """A converged point: ``u``, the tangent and what the tests need."""

    def __init__(self, prob: _Problem, v, R, Phi, yT, fl, T, J):
        self.v, self.T = v, T
        self.u = v * prob.scale
        self.res = float(np.max(np.abs(R)))
        self.J = J
        self.mults, self.rest = prob.multipliers(Phi)
        self.Phi = Phi
        n = prob.n
        ys = fl.states(self.u[:2 * n], T, 512, rtol=prob.rtol)[:-1]
        self.amps = tuple(_peak(np.abs(ys[:, i])) for i in range(n))
        self.tangent = _null(J)

    def record(self) -> CoupledBranchPoint:
        n2 = len(self.Phi)
        return CoupledBranchPoint(float(self.u[-1]), float(self.T),
                                  tuple(float(v) for v in self.u[:n2]), self.amps,
                                  tuple(complex(z) for z in self.mults),
                                  bool(np.all(np.abs(self.rest) < 1.0)), self.res)


def _peak(y: np.ndarray) -> float:
    """The largest value of a periodic sample, refined by the parabola through the largest
    sample and its neighbours (error ~ (2 pi/512)^4 of the amplitude)."""
    k = int(np.argmax(y))
    a, b, c = y[k - 1], y[k], y[(k + 1) % len(y)]
    den = a - 2 * b + c
    return float(b - (a - c) ** 2 / (8 * den)) if den < 0 else float(b)


def _null(J: np.ndarray) -> np.ndarray:
    """The unit null vector of the ``k x (k+1)`` matrix ``J``."""
    _, _, vt = np.linalg.svd(J)
    t = vt[-1]
    return t / np.linalg.norm(t)


def _correct(prob: _Problem, v_pred, row, target: float, max_iter: int = 10) -> _Pt:
    """Newton on ``R(v) = 0, row . v = target`` (scaled unknowns), by the corrector shared
    with one degree of freedom (:func:`numerics.cycles.corrector.correct_on_hyperplane`)."""
    def evaluate(v):
        R, Phi, yT, fl, T = prob.residual(v)
        J = prob.jacobian(v, Phi, yT, fl, T)
        return R, J, (Phi, yT, fl, T, J)

    def accept(v, R, dv, data, it):
        # the acceptance standard (numerics.cycles.acceptance), and the accuracy of the
        # point: a scaled correction below 1e-8
        scale = orbit_scale((v * prob.scale)[:2 * prob.n])
        return bool(accepted(float(np.max(np.abs(R))), float(np.max(np.abs(dv * prob.scale))),
                             prob.rtol, scale) and np.max(np.abs(dv)) < 1e-8
                    and (prob.forced or trivial_ok(np.linalg.eigvals(data[0]))))

    def too_large(v, dv):
        if np.max(np.abs(dv)) > 0.5:
            return (f"corrector step too large ({np.max(np.abs(dv)):.3g}, scaled) at "
                    f"{prob.vary} = {v[-1] * prob.scale[-1]:.8g}")
        return None

    v, R, _, (Phi, yT, fl, T, J), _ = correct_on_hyperplane(
        evaluate, v_pred, row, target, max_iter=max_iter, accept=accept, too_large=too_large,
        where=lambda v: f"{prob.vary} = {v[-1] * prob.scale[-1]:.8g}")
    return _Pt(prob, v, R, Phi, yT, fl, T, J)


def _arc(prob: _Problem, pt: _Pt, t: np.ndarray, ds: float) -> _Pt:
    pred = pt.v + ds * t
    new = _correct(prob, pred, t, float(t @ pred))
    if new.tangent @ t < 0:
        new.tangent = -new.tangent
    return new


def _tests(prob: _Problem, pt: _Pt) -> dict[str, float]:
    """The test functions at ``pt``: fold, period doubling, Neimark-Sacker."""
    z = pt.rest
    ns = 1.0
    for i in range(len(z)):
        for j in range(i + 1, len(z)):
            ns *= (z[i] * z[j] - 1.0)
    return {"fold": float(pt.tangent[-1]),
            "period-doubling": float(np.real(np.prod(1.0 + z))),
            "neimark-sacker": float(np.real(ns))}


def _locate(prob: _Problem, a: _Pt, b: _Pt, kind: str, fa: float, tol: float = 1e-11):
    """Bisection for the zero of test ``kind`` between ``a`` and ``b``, on the hyperplanes
    normal to the chord ``b - a`` (each meets the branch between them once, where the
    hyperplanes normal to ``a``'s tangent can miss a sharp fold): ``(the point nearest the
    zero, (the parameter at both ends of the last bracket))``."""
    chord = b.v - a.v
    length = float(np.linalg.norm(chord))
    d = chord / length
    lo, hi = 0.0, length
    p_lo, p_hi = float(a.u[-1]), float(b.u[-1])
    best = None
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        pred = a.v + mid * d
        try:
            pm = _correct(prob, pred, d, float(d @ pred))
        except _FAIL:
            break
        pm.tangent = pm.tangent if pm.tangent @ a.tangent >= 0 else -pm.tangent
        f = _tests(prob, pm)[kind]
        best = pm
        if f * fa > 0:
            lo, p_lo = mid, float(pm.u[-1])
        else:
            hi, p_hi = mid, float(pm.u[-1])
        if hi - lo < tol:
            break
    if best is None:
        return None
    return best, (min(p_lo, p_hi), max(p_lo, p_hi))


def _follow(prob: _Problem, first: _Pt, direction: int, bounds, ds: float, ds_max: float,
            ds_min: float, max_points: int, period_factor: float, hopf_fraction: float):
    t = _null(first.J)
    if t[-1] * direction < 0:
        t = -t
    cur = copy.copy(first)  # the same point, oriented for this direction
    cur.tangent = t
    pts, special = [cur], []
    amp0 = max(first.amps)
    reason = f"{max_points} points (--max-points)"
    while len(pts) < max_points:
        try:
            new = _arc(prob, cur, cur.tangent, ds)
            turn = float(new.tangent @ cur.tangent)
            if turn < 0.9:
                raise ConvergenceError(f"the tangent turned by "
                                       f"{math.degrees(math.acos(max(-1.0, turn))):.0f} degrees")
        except _FAIL as exc:
            ds /= 2
            if ds < ds_min:
                reason = (f"the steps collapsed below {ds_min:g} at {prob.vary} = "
                          f"{cur.u[-1]:.10g} (period {cur.T:.8g}): {exc}")
                break
            continue
        p = float(new.u[-1])
        if p < bounds[0] or p > bounds[1]:
            edge = bounds[0] if p < bounds[0] else bounds[1]
            row = np.zeros(len(new.u))
            row[-1] = 1.0
            try:
                s = (edge - cur.u[-1]) / (new.u[-1] - cur.u[-1])
                end = _correct(prob, cur.v + s * (new.v - cur.v), row, edge / prob.scale[-1])
                end.tangent = cur.tangent
                _specials(prob, cur, end, special)
                pts.append(end)
            except _FAIL:
                pass
            reason = f"reached {prob.vary} = {edge:g}, the end of the range"
            break
        _specials(prob, cur, new, special)
        pts.append(new)
        cur = new
        if len(pts) > 8 and np.linalg.norm(new.v - first.v) < ds \
                and new.tangent @ pts[0].tangent > 0.9:
            reason = (f"the branch closed on itself after {len(pts) - 1} points (an isola: "
                      f"{prob.vary} from {min(q.u[-1] for q in pts):.10g} to "
                      f"{max(q.u[-1] for q in pts):.10g})")
            return pts, special, reason, True
        if not prob.forced and new.T > period_factor * first.T:
            reason = (f"the period grew to {new.T:.6g}, {period_factor:g} times its start, at "
                      f"{prob.vary} = {p:.10g}: a homoclinic end is near")
            break
        if not prob.forced and max(new.amps) < hopf_fraction * amp0:
            reason = (f"the amplitude fell to {max(new.amps):.3g} at {prob.vary} = {p:.10g}: "
                      "the cycle shrinks to an equilibrium (a Hopf end)")
            break
        ds = min(ds * 1.5, ds_max)
    return pts, special, reason, False


def _specials(prob: _Problem, a: _Pt, b: _Pt, out: list) -> None:
    fa, fb = _tests(prob, a), _tests(prob, b)
    for kind in ("fold", "period-doubling", "neimark-sacker"):
        if fa[kind] * fb[kind] >= 0:
            continue
        found = _locate(prob, a, b, kind, fa[kind])
        if found is None:
            continue
        pt, bracket = found
        if kind == "neimark-sacker":
            close = [z for z in pt.rest if abs(abs(z) - 1) < 1e-3 and abs(z.imag) > 1e-6]
            if not close:
                continue  # a real pair lambda, 1/lambda: a neutral saddle
        if kind == "period-doubling" and not any(abs(z + 1) < 1e-3 for z in pt.rest):
            continue
        out.append(CoupledSpecialPoint(kind, float(pt.u[-1]), float(pt.T), pt.amps,
                                       tuple(complex(z) for z in pt.mults), bracket,
                                       tuple(float(v) for v in pt.u[:len(pt.Phi)])))


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
        A :class:`~kbm.coupled.CoupledOscillators` (``N = 1`` included) or a built-in name.
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
        orbit after a transient, :func:`~numerics.coupled.coupled_cycle` or
        :func:`~numerics.coupled.forced_response`).
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
        The transient before the first orbit (see :func:`~numerics.coupled.coupled_cycle`).

    Raises
    ------
    kbm.errors.ParameterError
        For an unknown parameter, an empty range, a start value outside it.
    numerics.errors.NoCycleError
        If there is no periodic orbit to start from.
    """
    params = dict(params or {})
    lo, hi = (float(b) for b in bounds)
    if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
        raise ParameterError(f"the range of {vary} must be FROM < TO, finite; got {lo:g}:{hi:g}")
    p0 = float(params.pop(vary)) if vary in params else lo
    if not lo <= p0 <= hi:
        raise ParameterError(f"the start value {vary} = {p0:g} is outside {lo:g}:{hi:g}")
    m, _ = bind_coupled(model, {**params, vary: p0})
    names = set(m.parameters) | {"mu"}
    if vary not in names:
        raise ParameterError(f"{vary!r} is not a parameter of {m.name!r} (its parameters: "
                             f"{', '.join(sorted(names))})")
    if not 0 < rtol < 1e-4:
        raise ParameterError(f"rtol must be between 0 and 1e-4, got {rtol:g}")
    prob = _Problem(m, params, vary, rtol)
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
    n2 = 2 * m.dof
    ys = max(1.0, float(np.max(np.abs(u0[:n2]))))
    prob.scale = np.concatenate([np.full(n2, ys), [] if m.forced else [u0[n2]],
                                 [max(hi - lo, 1e-6)]])
    row = np.zeros(len(u0))
    row[-1] = 1.0
    try:
        first = _correct(prob, u0 / prob.scale, row, p0 / prob.scale[-1], max_iter=20)
    except _FAIL as exc:
        raise NoCycleError(f"the orbit at {vary} = {p0:g} does not converge as a branch "
                           f"point: {exc}") from None
    ds_max = ds_max or 1.0 / 25
    ds = ds or ds_max / 4
    points: list[_Pt] = [first]
    special: list[CoupledSpecialPoint] = []
    reasons = []
    for d in directions:
        pts, sp_, reason, closed = _follow(prob, first, d, (lo, hi), ds, ds_max, ds_min,
                                           max_points, period_factor, hopf_fraction)
        reasons.append(f"towards {'larger' if d > 0 else 'smaller'} {vary}: {reason}")
        special += sp_
        points = (points + pts[1:]) if d > 0 else (list(reversed(pts[1:])) + points)
        if closed:
            break  # the other direction is the same loop
    recs = tuple(p.record() for p in points)
    special.sort(key=lambda s: s.parameter)
    special = _distinct(special)
    return CoupledBranch(m.name, vary, (lo, hi), m.forced, m.dof, recs, tuple(special),
                         tuple(reasons), prob.evaluations)
