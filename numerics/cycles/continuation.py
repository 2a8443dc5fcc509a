"""Branches of limit cycles: pseudo-arclength continuation of the shooting solution.

The unknowns are ``u = (x0, T, p)``: the section point ``x(0) = x0, x'(0) = 0``, the
period and the varied parameter; a cycle solves ``R(u) = (x(T) - x0, x'(T)) = 0``, the
branch is the curve of solutions, followed by Keller's pseudo-arclength through folds and
along unstable cycles, by :class:`CycleContinuation`, the case ``N = 1`` of the one driver
(:class:`numerics.shooting.continuation.Continuation`) on the case ``N = 1`` of the one
branch problem (:class:`numerics.shooting.planar.PlanarProblem`): ``ds`` grows after easy
corrections and is halved after a failed one or a sharp turn of the tangent.

Special points, each labelled with its parameter value:

- ``fold``: ``dp/ds`` changes sign (the non-trivial Floquet multiplier passes
  through +1); located by the secant method on ``dp/ds`` along the branch
  (:func:`numerics.shooting.locate.fold_on_arc`);
- ``hopf``: the amplitude tends to 0; ``p`` extrapolated with ``p - p_H ~ x0^2``;
- ``homoclinic``: the period grows beyond ``period_factor`` times its start value
  (the cycle reaches a separatrix; :meth:`CycleContinuation.homoclinic`) and either the
  cycle passes a saddle of the flow or its period grows like ``-log|p - p_h|``
  (:func:`numerics.cycles.homoclinic.log_law`); a long period of another kind (van der
  Pol's relaxation oscillations, ``T ~ (3 - 2 ln 2) mu``) is followed on;
- ``end``: the step fell below ``ds_min`` (with the reason).

Every integration is bounded (:data:`numerics.shooting.orbit.NEWTON_MAX_STEPS`),
every loop too (``max_points``, ``max_iter``, ``ds_min``): the continuation never hangs.

References
----------
H. B. Keller, "Numerical solution of bifurcation and nonlinear eigenvalue problems"
(1977); Yu. A. Kuznetsov, *Elements of Applied Bifurcation Theory*, ch. 6 and 10.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING

import numpy as np

from kbm.errors import ParameterError

from numerics.shooting.planar import PlanarPoint, PlanarProblem
from numerics.shooting.branch_result import Branch, SpecialPoint, branch_point
from numerics.cycles.homoclinic import (aitken, end_estimate, homoclinic_reason, log_law,
                                        long_period_points)
from numerics.cycles.result import LimitCycle
from numerics.cycles.shooting import limit_cycle
from numerics.errors import ConvergenceError, NoCycleError
from numerics.flow import Method
from numerics.shooting.arclength import FAIL as _FAIL
from numerics.shooting.arclength import parameter_range
from numerics.shooting.continuation import Continuation
from numerics.shooting.locate import fold_on_arc

if TYPE_CHECKING:  # the symbolic model is bound on use (a model card: issue 39)
    from kbm.model.builtins import Oscillator

__all__ = ["continue_cycles", "CycleContinuation"]


class CycleContinuation(Continuation):
    """The case ``N = 1`` of the one driver: folds located on the arc (each a point of the
    branch), the section re-anchored at the largest ``x``, the cubic predictor, the steps
    adapted to Newton's iterations, the Hopf and homoclinic ends."""

    skip_at_bounds = True
    full_text = "stopped after max_points = {n} points"
    #: at a homoclinic end the cycle is followed in its period to this multiple of the
    #: start's (``None``: not followed)
    follow_period: float | None = None

    record = staticmethod(branch_point)

    def begin(self, first: PlanarPoint) -> None:
        self.x_big, self.T0, self.recent = first.size, first.u[1], [first]
        self.previous = None  # (u, tangent) of the point before, for the cubic predictor

    def step(self, pt: PlanarPoint, ds: float) -> PlanarPoint:
        prev, self.previous = self.previous, None  # a failed step starts the next afresh
        new = self.prob.arc(pt, ds, previous=prev)
        if new.u[0] * pt.u[0] <= 0:
            raise ConvergenceError("the section point changed sign")
        return new

    def collapsed(self, pt: PlanarPoint, exc: Exception) -> str:
        msg = (f"continuation stopped at {self.name} = {pt.u[2]:.10g} (x0 = {pt.u[0]:.6g}, "
               f"T = {pt.u[1]:.6g}): step below ds_min = {self.ds_min:.1e} ({exc})")
        self.special.append(SpecialPoint("end", float(pt.u[2]), pt.amp, float(pt.u[1]), msg))
        return msg

    def locate(self, pt: PlanarPoint, new: PlanarPoint, ds: float) -> None:
        if new.tangent[2] * pt.tangent[2] >= 0:
            return
        found = fold_on_arc(self.prob.arc, pt, new, ds)
        fp = new if found.failure is not None else found.point
        if fp is not new and self.converged(fp):
            self.points.append(branch_point(fp))
        if abs(fp.mults[1].real - 1.0) < 1e-5:  # else not a fold (a Hopf end, a section)
            m = fp.mults[1].real
            self.special.append(SpecialPoint(
                "fold", float(fp.u[2]), fp.amp, float(fp.u[1]),
                f"fold of cycles at {self.name} = {fp.u[2]:.10g}: dp/ds = "
                f"{fp.tangent[2]:.1e}, non-trivial multiplier {m:.8f}"))

    def advance(self, pt: PlanarPoint, new: PlanarPoint, ds_used: float):
        moved = self.prob.reanchor(new)
        # the point before for the cubic predictor (none after a re-anchored section, where
        # the unknowns jumped, or after a fold)
        self.previous = ((pt.u.copy(), pt.tangent.copy())
                         if moved is new and new.tangent[2] * pt.tangent[2] > 0 else None)
        new = moved
        self.x_big = max(self.x_big, new.size)
        self.prob.choose(new.u)
        small = ds_used < 0.05 * self.ds_max  # slow Newton near a separatrix: still grow
        ds = min(ds_used * (1.5 if new.iters <= 4 else 1.2 if new.iters <= 6 and small else
                            0.7 if new.iters >= 7 else 1.0), self.ds_max)
        shrink = (pt.size - new.size) / ds_used  # approach a Hopf point in ever shorter steps
        if shrink > 0 and new.size < 0.25 * self.x_big:
            ds = min(ds, max(0.5 * new.size / shrink, 4 * self.ds_min))
        return new, ds

    def end(self, pt: PlanarPoint, new: PlanarPoint, ds: float) -> str:
        name = self.name
        if new.size < self.hopf_fraction * self.x_big and new.size < pt.size:
            a2, b2 = pt.size ** 2, new.size ** 2
            pH = (pt.u[2] * b2 - new.u[2] * a2) / (b2 - a2) if a2 != b2 else new.u[2]
            msg = (f"Hopf end: the cycle shrinks onto the equilibrium at x = {new.mid:.6g} "
                   f"at {name} = {pH:.8g} (peak-to-peak {new.size:.3g} at {name} = "
                   f"{new.u[2]:.8g}; extrapolated with {name} - {name}_H ~ size^2), period "
                   f"-> {new.u[1]:.6g}")
            self.special.append(SpecialPoint("hopf", float(pH), float(new.mid),
                                             float(new.u[1]), msg))
            return msg
        return self.homoclinic(new)

    def homoclinic(self, new: PlanarPoint) -> str:
        """Why the branch ends at a separatrix at ``new`` (``""``: it does not, see
        :func:`homoclinic_reason`; nor without a saddle passed or a period ~ -log|p - p_h|,
        :func:`log_law`), its special point added: the parameter from the period
        law fitted to the points (:mod:`numerics.cycles.homoclinic`, refined by the
        manifolds) or else Aitken's extrapolation; on request the cycles followed in their
        period beyond the last point (:mod:`numerics.cycles.long_period`) join the points."""
        self.recent.append(new)
        why = homoclinic_reason(self.recent, self.T0, self.period_factor,
                                self.bounds[1] - self.bounds[0])
        if not why:
            return ""
        name, points, T0 = self.name, self.points, self.T0
        est = end_estimate(self.prob, points)
        if est is not None:
            ph, where = est.best[0], est.text(name)
        elif not log_law([p.parameter for p in points] + [new.u[2]],
                         [p.period for p in points] + [new.u[1]]):
            # no saddle approached and no period ~ -log|p - p_h|: a long period of another
            # kind (van der Pol's relaxation oscillations, T ~ (3 - 2 ln 2) mu) goes on
            self.recent = self.recent[-1:]
            return ""
        else:
            ps = [r.u[2] for r in self.recent[-3:]]
            ph = aitken(ps)
            if abs(ph - ps[-1]) > 10 * abs(ps[-1] - ps[-2]):  # not geometric: the last
                ph = ps[-1]
            where = (f"{name} extrapolated to {ph:.6g} (Aitken on the last three points; "
                     "no saddle to compute the period law from, error unknown)")
        msg = (f"homoclinic end: {why} at {name} = {new.u[2]:.10g} (period "
               f"{new.u[1]:.6g}, from {T0:.6g}): the cycle approaches a separatrix; "
               f"{where}")
        if self.follow_period and points:
            msg += long_period_points(self.prob, points, T0, self.follow_period)
        # the marker sits on the last printed (converged) point's amplitude and period
        shown = points[-1] if points else branch_point(new)
        self.special.append(SpecialPoint("homoclinic", float(ph), float(shown.amplitude_max),
                                         float(shown.period), msg))
        return msg


def _check_vary(model, params: dict, vary: str, bounds) -> tuple[float, float, float]:
    lo, hi, p0 = parameter_range(vary, bounds, params)
    from numerics.flow.card import card_key
    from numerics.flow.line_card import source_digest
    from numerics.flow.template_cache import FORMAT, read_record, write_record

    code = source_digest("numerics/cycles/continuation.py")  # the checks below
    key = card_key(model, {**params, "--vary": f"{vary}|{lo!r}|{hi!r}|{p0!r}|{code}"})
    if key is not None and read_record(key, "vary") is not None:
        return lo, hi, p0  # checked by an earlier run (a model card's key: issue 39)
    from kbm.parameters.bound import bind

    try:
        b1 = bind(model, {**params, vary: p0})
        b2 = bind(model, {**params, vary: p0 + 1e-3 * max(1.0, abs(p0))})
    except ParameterError as exc:
        raise ParameterError(f"cannot vary {vary!r}: {exc}") from None
    if b1.values == b2.values:
        raise ParameterError(f"parameter {vary!r} does not enter model {b1.name!r} "
                             f"(its parameters: {', '.join(b1.model.parameters)}, mu)")
    if key is not None:
        write_record(key, {"format": FORMAT, "key": key}, "vary")
    return lo, hi, p0


def continue_cycles(model: Oscillator | str, params: Mapping[str, object] | None, vary: str,
                    bounds: tuple[float, float], *,
                    start: LimitCycle | tuple[float, float] | None = None,
                    directions: tuple[int, ...] = (1, -1), ds: float | None = None,
                    ds_max: float | None = None, ds_min: float = 1e-7,
                    max_points: int = 400, rtol: float = 1e-10, method: Method | str = "auto",
                    period_factor: float = 8.0, hopf_fraction: float = 0.02,
                    max_turn: float = 0.9, follow_period: float | None = None) -> Branch:
    """A branch of limit cycles of ``model`` as the parameter ``vary`` runs over ``bounds``.

    Parameters
    ----------
    model : Oscillator or str
        The model (or a built-in name).
    params : Mapping or None
        The other parameter values (physical or scaled names, ``mu``); the value of
        ``vary`` in it, if any, is where the branch starts (default: ``bounds[0]``).
    vary : str
        The parameter to vary: ``mu``, a parameter of the model, or a physical one
        (``Delta``, bound per point by :func:`kbm.parameters.bound.bind`).
    bounds : tuple of float
        ``(FROM, TO)`` with ``FROM < TO``: the branch stops where it leaves them.
    start : LimitCycle or tuple of float, optional
        The cycle to start from, or a guess ``(x_max, period)``; default
        :func:`numerics.cycles.limit_cycle` at the start value.
    directions : tuple of int
        ``1`` follows the branch towards increasing ``vary`` from the start, ``-1``
        towards decreasing (both by default; the points come in the order of ``vary``
        at the start).
    ds, ds_max, ds_min : float
        First, largest and smallest arclength step in ``(x0, T, p)`` (defaults
        ``ds_max = max(TO - FROM, 1)/25``, ``ds = ds_max/4``).
    max_points : int
        Bound on the points per direction.
    rtol : float
        Integrator tolerance (``atol = rtol``).
    method : Method or str
        Integrator (:func:`numerics.flow.choose_method`, purpose ``"shooting"``).
    period_factor : float
        The branch ends as homoclinic when the period exceeds this multiple of its start.
    hopf_fraction : float
        The branch ends at a Hopf point when ``|x0|`` falls below this fraction of its
        largest value on the branch while decreasing.
    max_turn : float
        A step is halved when the cosine of the angle between successive tangents falls
        below this.
    follow_period : float, optional
        At a homoclinic end, continue the cycle in its period, the parameter free, until the
        period is this multiple of the period at the start of the branch (multiple shooting
        on Poincare sections, :func:`numerics.cycles.long_period.follow_period`); the points
        are added to the branch, with the non-trivial multiplier from Liouville's formula.
        AUTO-07p's standard is 20.

    Returns
    -------
    Branch
        Points with period, amplitude and Floquet multipliers (stable and unstable),
        and the special points (folds, Hopf and homoclinic ends, failures).

    Raises
    ------
    kbm.errors.ParameterError
        For an unknown parameter, one that does not enter the model, an empty range or
        a start value outside it.
    numerics.errors.NoCycleError
        If there is no cycle to start from.

    Examples
    --------
    >>> br = continue_cycles("vdp", {"mu": 0.5}, "mu", (0.5, 1.0), directions=(1,))
    >>> round(br.points[-1].parameter, 12), round(br.points[-1].period, 6)
    (1.0, 6.663287)
    """
    import sys

    # not imported: no bound model (issue 39)
    bound_types = sys.modules.get("kbm.parameters.bound")
    params = dict(params or {})
    if bound_types is not None and isinstance(model, bound_types.BoundModel):
        raise ParameterError("continue_cycles needs the model and its parameters separately, "
                             "not a bound model")
    lo, hi, p0 = _check_vary(model, params, vary, bounds)
    if not (0 < rtol < 1e-3):
        raise ParameterError(f"rtol must be between 0 and 1e-3, got {rtol:g}")
    prob = PlanarProblem(model, params, vary, method, rtol, p0)
    if start is None or isinstance(start, LimitCycle):
        try:
            c = start or limit_cycle(model, {**params, vary: p0}, rtol=max(rtol, 1e-12))
        except (NoCycleError, ConvergenceError) as exc:
            raise NoCycleError(f"no limit cycle at {vary} = {p0:g} to start the branch from "
                               f"({exc}); start elsewhere (another {vary} in the range) or "
                               "give a start guess") from None
        guess = (c.amplitude_max, c.period)
    else:
        guess = (float(start[0]), float(start[1]))
    u0 = np.array([guess[0], guess[1], p0])
    prob.choose(u0)
    try:
        first = prob.fix(u0, max_iter=25)
    except _FAIL as exc:
        raise NoCycleError(f"no limit cycle at {vary} = {p0:g} near x_max = {guess[0]:.6g}, "
                           f"T = {guess[1]:.6g} to start the branch from ({exc})") from None
    prob.use_symmetry(first)  # half periods from here on, for an odd field's symmetric cycle
    dsm = ds_max if ds_max is not None else max(hi - lo, 1.0) / 25
    run = CycleContinuation(prob, (lo, hi), ds=ds if ds is not None else dsm / 4, ds_max=dsm,
                            ds_min=ds_min, max_points=max_points, period_factor=period_factor,
                            hopf_fraction=hopf_fraction)
    run.max_turn, run.turn_above, run.follow_period = max_turn, 4 * ds_min, follow_period
    points, special, reasons = run.run(first, directions)
    return Branch(model=model if isinstance(model, str) else model.name, parameter=vary,
                  params=params, bounds=(lo, hi), points=tuple(points), special=tuple(special),
                  reasons=tuple(reasons), evaluations=prob.evaluations, dropped=run.dropped)
