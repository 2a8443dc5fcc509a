"""Where a branch of cycles ends at a homoclinic (or heteroclinic) loop: the period law.

Near the loop the cycle spends most of its period near the saddles it passes, a time
``-(1/lambda_u) ln|p - p_h|`` at each (Shil'nikov; Kuznetsov, *Elements of Applied
Bifurcation Theory*, sec. 6.2), so

``T(p) = -k ln|p_h - p| + c``,  ``k = sum over the saddles passed of 1/lambda_u``,

with ``lambda_u`` the unstable eigenvalue of each saddle, **computed** from the model's
Jacobian there, not fitted.  ``p_h`` and ``c`` are fitted to the last three converged points
of the branch, and again to the three before them; the estimate drifts towards ``p_h``
linearly in the distance of the points from it (the next term of the law), so the two
are extrapolated to distance zero, and the error bar is twice that correction.

On the SEDF branch of issue 25 (mu = 0.1, beta = 1, lam = 1, Delta from 0) the two
saddles at x = +-1.581 (lambda_u = 4.027) give p_h = 3.24941 +- 0.00015; AUTO-07p's last
point is 3.2494301 (at period 14.47; ``benchmarks/bench_branch.py``).

The end of a branch of :class:`numerics.cycles.continuation.CycleContinuation` there:
:func:`homoclinic_reason` (why the branch is taken to end), :func:`end_estimate` (the law
fitted to its points, refined by the manifolds), :func:`aitken` (without a saddle) and
:func:`long_period_points` (the cycles followed in their period beyond the last point).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from numerics.shooting.branch_result import BranchPoint
from numerics.cycles.localmin import fminbound, integral
from numerics.shooting.arclength import FAIL

__all__ = ["HomoclinicEstimate", "homoclinic_end", "period_law_fit", "saddles_passed",
           "refine_by_manifolds", "homoclinic_reason", "aitken", "long_period_points",
           "end_estimate"]


@dataclass(frozen=True)
class HomoclinicEstimate:
    """The parameter of the homoclinic end with its error bar.

    Attributes
    ----------
    parameter, error : float
    saddles : tuple of float
        The ``x`` of the saddles the cycle passes.
    lambdas : tuple of float
        Their unstable eigenvalues.
    k : float
        ``sum 1/lambda_u``.
    last : float
        The parameter of the last converged point used.
    """

    parameter: float
    error: float
    saddles: tuple
    lambdas: tuple
    k: float
    last: float
    connection: float | None = None
    connection_error: float | None = None

    def text(self, name: str) -> str:
        digits = max(0, 1 - int(math.floor(math.log10(self.error)))) if self.error > 0 else 10
        sad = ", ".join(f"x = {s:.4g}" for s in self.saddles)
        lam = ", ".join(f"{v:.4g}" for v in self.lambdas)
        law = (f"fit of T = -k ln|{name} - {name}_h| + c with k = sum 1/lambda_u = {self.k:.5g} "
               f"computed at the saddles passed, {sad}, lambda_u = {lam}; from the last "
               f"converged points, the last at {name} = {self.last:.8g}; error bar: twice the "
               "extrapolation in the distance to the end")
        if self.connection is None:
            return f"{name}_h = {self.parameter:.{digits}f} +- {self.error:.{digits}f} ({law})"
        return (f"{name}_h = {self.connection:.10f} +- {self.connection_error:.0e} (the saddle "
                f"connection, by shooting the saddles' manifolds: "
                "numerics.cycles.manifolds); the period law agrees: "
                f"{self.parameter:.{digits}f} +- {self.error:.{digits}f} ({law})")

    @property
    def best(self) -> tuple[float, float]:
        """``(parameter, error)``: the manifolds' connection when found, else the law's."""
        if self.connection is not None:
            return self.connection, self.connection_error
        return self.parameter, self.error


def refine_by_manifolds(model, params, vary: str, est: "HomoclinicEstimate"
                        ) -> "HomoclinicEstimate":
    """``est`` with the saddle connection located by shooting the manifolds
    (:func:`numerics.cycles.manifolds.saddle_connection`) near it, when one is found within
    three of its error bars (else ``est`` unchanged)."""
    from dataclasses import replace

    from numerics.cycles.manifolds import saddle_connection

    sad = sorted(est.saddles)
    pairs = [(sad[-1], sad[0]), (sad[0], sad[-1])] if len(sad) >= 2 else [(sad[0], sad[0])]
    width = 3 * est.error + 1e-4
    for x_from, x_to in pairs:
        for leave in (-1, 1):
            for arrive in (-1, 1):
                try:
                    c = saddle_connection(model, params, vary,
                                          (est.parameter - width, est.parameter + width),
                                          x_from, x_to, leave, arrive)
                except Exception:  # noqa: BLE001 - no connection of this kind here
                    continue
                return replace(est, connection=c.parameter, connection_error=c.error)
    return est


def period_law_fit(p, T, k: float, direction: int) -> float:
    """``p_h`` minimising the spread of ``T + k ln|p_h - p|`` (the constant ``c``), ``p_h``
    beyond the last ``p`` in ``direction``."""
    p, T = np.asarray(p, float), np.asarray(T, float)
    span = abs(p[-1] - p[0]) + 1e-300

    def spread(logd):
        ph = p[-1] + direction * math.exp(logd)
        return float(np.var(T + k * np.log(np.abs(ph - p))))

    # Brent's bounded minimiser, scipy's minimize_scalar(method="bounded") to the bit
    best = fminbound(spread, math.log(1e-9 * span), math.log(100 * span), xatol=1e-10)
    return float(p[-1] + direction * math.exp(best))


def homoclinic_end(params, periods, saddles, lambdas) -> HomoclinicEstimate | None:
    """The end from converged points ``(params, periods)`` (at least six) and the saddles
    passed; ``None`` when there are too few points."""
    p, T = np.asarray(params, float), np.asarray(periods, float)
    if len(p) < 6 or not len(saddles):
        return None
    k = float(sum(1.0 / v for v in lambdas))
    direction = 1 if p[-1] > p[-2] else -1
    e0 = period_law_fit(p[-3:], T[-3:], k, direction)
    e1 = period_law_fit(p[-6:-3], T[-6:-3], k, direction)
    d0, d1 = abs(e0 - p[-1]), abs(e1 - p[-4])
    if d1 <= d0:
        return HomoclinicEstimate(e0, abs(e0 - e1) + d0, tuple(saddles), tuple(lambdas), k,
                                  float(p[-1]))
    slope = (e0 - e1) / (d1 - d0)
    est = e0 + slope * d0
    return HomoclinicEstimate(float(est), float(2 * abs(est - e0)), tuple(saddles),
                              tuple(lambdas), k, float(p[-1]))


def saddles_passed(bound, x_lo: float, x_hi: float, x_turn: float, force=None,
                   compiled=None):
    """``(saddles, lambdas)``: the saddles of the conservative part whose energy is the
    separatrix energy nearest the cycle's (the conservative energy ``G(x_turn)`` of its
    turning point ``(x_turn, 0)``) and that lie within the cycle's span ``[x_lo, x_hi]``
    widened by a tenth, with the unstable eigenvalue of the full linearisation (damping
    included) at each; ``((), ())`` when the model has no such saddle.

    ``force``, the vectorised force ``g(x) = -x''(x, 0)`` along the axis (the continuation
    passes its compiled one), skips the symbolic split: the saddles are the zeros of ``g``
    where it falls (on ``[-L, L]`` over the span and its margin, the grid doubled until the
    count is stable, as the portrait's), the energies ``G(x) = int_0^x g`` by adaptive
    quadrature.  Without it they come from the conservative phase portrait
    (:func:`kbm.model.conservative.split_conservative`, :func:`numerics.energy.phase_portrait`);
    both are compared in ``tests/test_manifolds.py``.  ``compiled``, the compiled model
    at the bound values (:class:`numerics.flow.CompiledLine`'s), gives the eigenvalues
    without ``bound``.
    """
    from ..flow import compile_model

    pad = 0.1 * (x_hi - x_lo)
    if force is None:
        found = _saddles_from_portrait(bound, x_turn)
    else:
        found = _saddles_from_force(force, max(abs(x_lo), abs(x_hi)) + pad, x_turn)
    if not found:
        return (), ()
    sad, energy = found
    Es = min({E for _, E in sad}, key=lambda E: abs(E - energy))
    chosen = [x for x, E in sad if abs(E - Es) <= 1e-9 * max(1.0, abs(Es))
              and x_lo - pad <= x <= x_hi + pad]
    jac = (compiled if compiled is not None else compile_model(bound)).jac
    lams = []
    for xs in chosen:
        J = jac(0.0, (xs, 0.0))
        a, b = float(J[1, 0]), float(J[1, 1])
        lams.append((b + math.sqrt(b * b + 4 * a)) / 2)
    return tuple(chosen), tuple(lams)


def _saddles_from_portrait(bound, x_turn: float):
    """``([(x, G(x)) of every saddle], G(x_turn))`` from the conservative phase portrait,
    or ``None``."""
    import sympy as sp

    from kbm.model.conservative import split_conservative

    from ..energy.portrait import phase_portrait

    try:
        split = split_conservative(bound.model, dict(bound.values))
        portrait = phase_portrait(split)
    except Exception:  # noqa: BLE001 - no portrait: no saddle to name
        return None
    sad = [(e.x, e.energy) for e in portrait.equilibria if e.kind == "saddle"]
    return (sad, float(split.G.subs(sp.Symbol("x"), x_turn))) if sad else None


def _saddles_from_force(force, L: float, x_turn: float):
    """``([(x, G(x)) of the saddles on [-L, L]], G(x_turn))`` from the force ``g`` along the
    axis, ``G = int_0^x g``, or ``None``."""
    from ..energy._zeros import _zeros

    sad = [z for z, kind in _zeros(force, L) if kind < 0]
    if not sad:
        return None

    def G(x: float) -> float:  # Gauss-Legendre: the energies only choose the saddles
        return integral(force, 0.0, x)

    return [(x, G(x)) for x in sad], G(x_turn)


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


def log_law(ps: list, Ts: list, n: int = 4, shrink: float = 0.5) -> bool:
    """Whether the period grows like ``T ~ -b log|p - p_h|`` toward a finite ``p_h`` over the
    last ``n`` points (parameters ``ps``, periods ``Ts``): near a homoclinic orbit the
    parameter per unit period, ``|dp/dT| = |p - p_h|/b``, shrinks toward zero, here by at
    least the factor ``shrink`` over the points (Kuznetsov, *Elements of Applied
    Bifurcation Theory*, sec. 6.2).  A period growing like a power of ``p`` keeps it steady
    (van der Pol's relaxation oscillations, ``T ~ (3 - 2 ln 2) mu``: ``|dp/dT| -> 0.62``)."""
    if len(ps) < n:
        return False
    dp, dT = np.diff(np.asarray(ps[-n:], float)), np.diff(np.asarray(Ts[-n:], float))
    if not np.all(dT > 0):
        return False
    w = np.abs(dp / dT)
    return bool(w[-1] < shrink * w[0])


def aitken(ps: list) -> float:
    """Limit of a geometric sequence from its last three terms (``p - p_h ~ exp(-k T)``)."""
    if len(ps) < 3:
        return float(ps[-1])
    d = ps[2] - 2 * ps[1] + ps[0]
    return float(ps[2] - (ps[2] - ps[1]) ** 2 / d) if d != 0 else float(ps[2])


def long_period_points(prob, points: list, T0: float, factor: float) -> str:
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
        except FAIL as exc:
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


def end_estimate(prob, points: list):
    """The homoclinic parameter from the period law (:func:`homoclinic_end`)
    fitted to the converged points, or ``None``."""
    if len(points) < 6:
        return None
    last = points[-1]
    try:
        _, _, _, ys = prob.eval((last.x0, last.period, last.parameter), n_out=400,
                                full=True)
    except FAIL:
        return None
    force = prob.force(last.parameter)
    if force is None:
        from kbm.parameters.bound import bind

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
