"""Where a branch of limit cycles ends near a separatrix (:mod:`numerics.cycles.continuation`).

- :func:`homoclinic_reason`: whether the branch approaches a separatrix (the period grows
  beyond a multiple of its start, the steps collapse while the period grows, or the
  parameter stalls);
- :func:`homoclinic_special`: the end's special point, its parameter from the period law
  fitted to the points (:mod:`numerics.cycles.homoclinic`, refined by the manifolds) or
  else Aitken's extrapolation, and, on request, the cycles followed in their period beyond
  the last point (:mod:`numerics.cycles.long_period`).

References
----------
Yu. A. Kuznetsov, *Elements of Applied Bifurcation Theory*, ch. 6 and 10.
"""

from __future__ import annotations

import numpy as np

from numerics.cycles.branch_result import BranchPoint, SpecialPoint, branch_point
from numerics.shooting.arclength import FAIL as _FAIL

__all__ = ["homoclinic_reason", "homoclinic_special"]


def homoclinic_reason(recent: list, T0: float, factor: float, width: float, n: int = 10) -> str:
    """Why the branch is taken to end at a separatrix, or ``""``."""
    T = recent[-1].u[1]
    if T > factor * T0:
        return f"the period grew beyond {factor:g} times its start value"
    if len(recent) > 2 * n and T > 1.25 * T0:
        last = recent[-2 * n:]
        dp = abs(last[-1].u[2] - last[0].u[2])
        if dp < 1e-3 * width and all(b.u[1] > a.u[1] for a, b in zip(last, last[1:])):
            return (f"the steps collapse ({2 * n} points moved the parameter by {dp:.1e}) "
                    f"while the period grows and the monodromy matrix reaches "
                    f"{last[-1].phi:.3g}")
    if len(recent) <= n:
        return ""
    last = recent[-n:]
    grows = all(b.u[1] > a.u[1] for a, b in zip(last, last[1:]))
    if grows and all(abs(r.tangent[2]) < 2e-3 for r in last) and T > 1.25 * T0:
        return (f"the parameter stalls (|dp/ds| < 2e-3 over {n} points) while the period "
                "grows")
    return ""


def _aitken(ps: list) -> float:
    """Limit of a geometric sequence from its last three terms (``p - p_h ~ exp(-k T)``)."""
    if len(ps) < 3:
        return float(ps[-1])
    d = ps[2] - 2 * ps[1] + ps[0]
    return float(ps[2] - (ps[2] - ps[1]) ** 2 / d) if d != 0 else float(ps[2])


def homoclinic_special(prob, points: list, recent: list, new, T0: float, why: str,
                       follow_period: float | None) -> tuple[SpecialPoint, str]:
    """The special point of a homoclinic end reached at ``new`` (``why`` from
    :func:`homoclinic_reason`) and its message; ``points`` (the printed points) may grow by
    the cycles followed in their period."""
    name = prob.vary
    est = _end_estimate(prob, points)
    if est is not None:
        ph = est.best[0]
        where = est.text(name)
    else:
        ps = [r.u[2] for r in recent[-3:]]
        ph = _aitken(ps)
        if abs(ph - ps[-1]) > 10 * abs(ps[-1] - ps[-2]):  # not geometric: the last
            ph = ps[-1]
        where = (f"{name} extrapolated to {ph:.6g} (Aitken on the last three points; "
                 "no saddle to compute the period law from, error unknown)")
    msg = (f"homoclinic end: {why} at {name} = {new.u[2]:.10g} (period "
           f"{new.u[1]:.6g}, from {T0:.6g}): the cycle approaches a separatrix; "
           f"{where}")
    if follow_period and points:
        msg += _long_period(prob, points, T0, follow_period)
    # the marker sits on the last printed (converged) point's amplitude and period
    shown = points[-1] if points else branch_point(new)
    return SpecialPoint("homoclinic", float(ph), float(shown.amplitude_max),
                        float(shown.period), msg), msg


def _long_period(prob, points: list, T0: float, factor: float) -> str:
    """Add the cycles followed in their period beyond ``points[-1]`` to ``factor * T0``;
    the sentence for the end's message."""
    from numerics.cycles.long_period import follow_period

    params = {k: v for k, v in prob.params.items() if k != prob.vary}
    target = factor * T0
    # the multiple shooting may stall on the way (its Jacobian nearly singular where the
    # mesh waits at the saddles); then it starts again from an earlier point of the branch,
    # whose mesh differs, and the longest continuation is kept
    lps, error, k = None, None, len(points) - 1
    for _ in range(3):
        start = points[k]
        try:
            run = follow_period(prob.model, params, prob.vary, start.x0, start.period,
                                start.parameter, target, rtol=min(prob.rtol, 1e-11))
        except _FAIL as exc:
            error = exc
            run = None
        if run is not None and (lps is None or run[-1].period > lps[-1].period):
            lps, k_used = run, k
        if lps is not None and lps[-1].period >= target:
            break
        k = next((i for i in range(k - 1, -1, -1)
                  if points[i].period <= 0.9 * start.period), None)
        if k is None:
            break
    if lps is None:
        return f"; following the cycle in its period failed: {error}"
    del points[k_used + 1:]  # the branch beyond the start is the followed one
    for q in lps[1:]:
        points.append(BranchPoint(parameter=q.parameter, x0=q.x0, period=q.period,
                                  amplitude_max=q.x0, multipliers=(1.0 + 0j, q.multiplier + 0j),
                                  stable=bool(abs(q.multiplier) < 1.0), residual=q.residual))
    end = lps[-1]
    return (f"; followed in its period (multiple shooting on {end.segments} sections, the "
            f"parameter free) to T = {end.period:.6g}, {end.period / T0:.1f} times the "
            f"start's, at {prob.vary} = {end.parameter:.12g}")


def _end_estimate(prob, points: list):
    """The homoclinic parameter from the period law (:mod:`numerics.cycles.homoclinic`)
    fitted to the converged points, or ``None``."""
    from numerics.cycles.homoclinic import homoclinic_end, refine_by_manifolds, saddles_passed

    if len(points) < 6:
        return None
    last = points[-1]
    try:
        _, _, _, ys = prob.eval((last.x0, last.period, last.parameter), n_out=400,
                                full=True)
    except _FAIL:
        return None
    force = prob.force(last.parameter)
    if force is None:
        from kbm.bound import bind

        bound, compiled = bind(prob.model, {**prob.params, prob.vary: last.parameter}), None
    else:  # the compiled force and the line's model: no symbolic model (issue 39)
        bound, compiled = None, prob.line(last.parameter)
    x = ys[:, 0]
    sad, lams = saddles_passed(bound, float(np.min(x)), float(np.max(x)), last.x0,
                               force=force, compiled=compiled)
    est = homoclinic_end([p.parameter for p in points], [p.period for p in points], sad, lams)
    if est is None:
        return None
    return refine_by_manifolds(prob.model, {k: v for k, v in prob.params.items()
                                            if k != prob.vary}, prob.vary, est)
