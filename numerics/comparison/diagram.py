"""The bifurcation diagram of limit cycles in one parameter: every branch, and the predictions.

:func:`branch_diagram` seeds branches from every cycle that
:func:`numerics.cycles.limit_cycles` finds at the start value (stable and unstable,
the energy-balance predictions confirmed by shooting), follows each by
pseudo-arclength continuation (:func:`numerics.cycles.continuation.continue_cycles`)
unless an earlier branch already passes through it, and sets the analytic branches
beside them (:mod:`numerics.comparison.branches`: KBM of the orders asked for, and
the energy balance).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from kbm.errors import ParameterError

from kbm.output.strict_json import finite
from numerics.shooting.branch_result import Branch
from numerics.cycles.continuation import _check_vary, continue_cycles
from numerics.cycles.every_cycle import limit_cycles
from numerics.cycles.shooting import limit_cycle
from numerics.errors import ConvergenceError, IntegrationError, NoCycleError

if TYPE_CHECKING:  # imported on use: the symbolic model and the KBM derivation (issue 39)
    from kbm.model.builtins import Oscillator
    from numerics.comparison.branches import AnalyticCurve

__all__ = ["BranchDiagram", "branch_diagram"]


@dataclass(frozen=True, eq=False)
class BranchDiagram:
    """Numerical branches of cycles and the analytic predictions over one parameter.

    Attributes
    ----------
    model, parameter : str
    bounds : tuple of float
    branches : tuple of Branch
        One per distinct cycle at the start value.
    analytic : tuple of AnalyticCurve
    failures : tuple of str
        Seeds that could not be continued, and analytic methods that failed.
    """

    model: str
    parameter: str
    bounds: tuple[float, float]
    branches: tuple[Branch, ...]
    analytic: tuple[AnalyticCurve, ...]
    failures: tuple[str, ...] = ()

    def to_json(self) -> dict:
        """``points`` (each: ``parameter, amplitude_max, period, stable, multipliers``, and
        ``branch``), ``special`` (each: ``kind, parameter, amplitude``, ...), ``analytic``
        (``"kbm order N"`` / ``"energy order 1"`` -> points and folds), and the context."""
        points, special = [], []
        for i, b in enumerate(self.branches):
            points += [{**p.to_json(), "branch": i} for p in b.points]
            special += [{**s.to_json(), "branch": i} for s in b.special]
        return finite({
            "model": self.model, "parameter": self.parameter, "bounds": list(self.bounds),
            "points": points, "special": special,
            "analytic": {f"{c.method} order {c.order}": c.to_json() for c in self.analytic},
            "branches": [{"reasons": list(b.reasons), "evaluations": b.evaluations,
                          "dropped": b.dropped,
                          "start": b.points[0].to_json() if b.points else None}
                         for b in self.branches],
            "failures": list(self.failures)})


def _passes(b: Branch, p: float, y: float, rel: float, attr: str) -> bool:
    """Whether the branch's ``attr``, linear in the parameter between its points, comes
    within ``rel max(1, |y|)`` of ``y`` at ``p``."""
    pts = b.points
    for q, r in zip(pts, pts[1:]):
        if min(q.parameter, r.parameter) <= p <= max(q.parameter, r.parameter):
            w = 0.0 if r.parameter == q.parameter else (p - q.parameter) / (r.parameter -
                                                                            q.parameter)
            lo, hi = getattr(q, attr), getattr(r, attr)
            if abs(lo + w * (hi - lo) - y) < rel * max(1.0, abs(y)):
                return True
    return False


def _on_branch(b: Branch, p0: float, x0: float) -> bool:
    """Whether the branch passes through the cycle with section point ``x0`` at ``p0``."""
    return _passes(b, p0, x0, 1e-3, "x0") or any(
        abs(q.parameter - p0) < 1e-12 and abs(q.x0 - x0) < 1e-6 for q in b.points)


def _near(b: Branch, p: float, amp: float, rel: float) -> bool:
    return _passes(b, p, amp, rel, "amplitude_max")


def _more_seeds(model, params, vary, bounds, eb, branches, failures, budget, kw) -> None:
    """Continue from energy-balance cycles that no branch passes near (``budget`` tries)."""
    for p, amp, T, _ in eb.points:
        if budget <= 0:
            return
        if any(_near(b, p, amp, 0.05) for b in branches):
            continue
        budget -= 1
        here = {**params, vary: p}
        try:
            c = limit_cycle(model, here, guess=(amp, T))
            if any(_near(b, p, c.amplitude_max, 1e-3) for b in branches):
                continue
            branches.append(continue_cycles(model, here, vary, bounds, start=c, **kw))
        except (NoCycleError, ConvergenceError, IntegrationError) as exc:
            failures.append(f"predicted cycle x_max = {amp:.6g} at {vary} = {p:g}: {exc}")


def branch_diagram(model: Oscillator | str, params: Mapping[str, object] | None, vary: str,
                   bounds: tuple[float, float], *, orders: Sequence[int] = (1,),
                   energy: bool = True, n_analytic: int = 161, extra_seeds: int = 6,
                   **continuation) -> BranchDiagram:
    """Every branch of limit cycles through the start value, and the analytic branches.

    Parameters
    ----------
    model, params, vary, bounds
        As for :func:`numerics.cycles.continuation.continue_cycles` (the start value is
        ``params[vary]``, default ``bounds[0]``).
    orders : sequence of int
        KBM orders of the analytic branches (empty: none).
    energy : bool
        Add the energy-balance branch (order 1).
    n_analytic : int
        Grid points of the analytic branches.
    extra_seeds : int
        Bound on the further seeds: energy-balance cycles elsewhere in the range that no
        branch passes near (within 5% in amplitude) are shot (:func:`limit_cycle` from
        the prediction) and, if new, continued too (up to this many attempts).
    continuation
        Passed to :func:`~numerics.cycles.continuation.continue_cycles` (``rtol``,
        ``ds_max``, ``max_points``, ...).

    Raises
    ------
    kbm.errors.ParameterError
        For a bad parameter name or range (see ``continue_cycles``).
    numerics.errors.NoCycleError
        When no cycle is found at the start value.
    """
    params = dict(params or {})
    lo, hi, p0 = _check_vary(model, params, vary, bounds)
    if energy or orders:  # the analytic branches: sympy, the KBM derivation (issue 39)
        from numerics.comparison.branches import energy_branch, kbm_branch
    if any(int(o) < 1 for o in orders):
        raise ParameterError(f"KBM orders must be >= 1, got {list(orders)}")
    start = {**params, vary: p0}
    try:
        seeds = limit_cycles(model, start)
    except (NoCycleError, ConvergenceError, IntegrationError) as exc:
        raise NoCycleError(f"no limit cycle at {vary} = {p0:g} to start a branch from "
                           f"({exc}); start elsewhere (another {vary} in the range)") from None
    if not seeds:
        reason = seeds.predictions.reason if seeds.predictions is not None else ""
        raise NoCycleError(f"no limit cycle at {vary} = {p0:g} to start a branch from"
                           + (f" ({reason})" if reason else "")
                           + f"; start elsewhere (another {vary} in the range)")
    branches, failures = [], []
    for c in seeds:
        if any(_on_branch(b, p0, c.amplitude_max) for b in branches):
            continue
        try:
            branches.append(continue_cycles(model, start, vary, (lo, hi), start=c,
                                            **continuation))
        except (NoCycleError, ConvergenceError, IntegrationError) as exc:
            failures.append(f"cycle x_max = {c.amplitude_max:.6g} at {vary} = {p0:g}: {exc}")
    if energy:
        eb = energy_branch(model, params, vary, (lo, hi), n=max(11, n_analytic // 2))
        _more_seeds(model, params, vary, (lo, hi), eb, branches, failures, extra_seeds,
                    continuation)
    analytic = []
    for o in orders:
        try:
            analytic.append(kbm_branch(model, params, vary, (lo, hi), order=int(o),
                                       n=n_analytic))
        except (ParameterError, ConvergenceError, ValueError) as exc:
            failures.append(f"KBM order {o}: {exc}")
    if energy:
        analytic.append(eb)
    name = model if isinstance(model, str) else model.name
    return BranchDiagram(name, vary, (lo, hi), tuple(branches), tuple(analytic),
                         tuple(failures))
