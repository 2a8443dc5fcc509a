"""Two-parameter bifurcation curves of a forced oscillator, true and averaged (issue 38).

The forced oscillator ``x'' + omega0**2 x = mu F(x, x', nu t)``, ``nu = (p/q) omega0 + mu
sigma``, has periodic responses of the drive's period ``T = 2 pi p/nu``: fixed points of the
stroboscopic map ``y0 -> y(T)``.  Their codim-1 bifurcations are continued in two
parameters (one of them the detuning ``sigma``) by :func:`numerics.bifurcation.curve.
continue_curve` on the defining systems (unknowns ``z = (x(0), x'(0), p1, p2)``; the flow
and its monodromy ``Phi(T)`` from one compiled integration,
:meth:`numerics.flow.coupled_flow.CoupledFlow.monodromy`):

- **fold** (saddle-node of responses, the jump points): ``y(T) - y0 = 0`` and
  ``det(Phi - I) = 0`` (a multiplier +1);
- **period doubling**: ``det(Phi + I) = 0`` (a multiplier -1);
- **Neimark–Sacker**: ``det Phi - 1 = 0`` with ``|tr Phi| < 2`` (a complex pair on the unit
  circle; the curve ends where the pair becomes real, a neutral saddle).

For a 2x2 monodromy ``det(Phi -+ I) = 1 -+ tr Phi + det Phi`` (Kuznetsov, *Elements of
Applied Bifurcation Theory*, 3rd ed., sec. 10.3.2 for the maps' defining systems).  Codim-2
points are zeros of test functions along the curves, located to convergence:

- **cusp** on a fold curve: the fold curve's tangent has no parameter component (the
  projection of the curve onto the parameter plane turns back; Kuznetsov sec. 8.2);
- **Bogdanov–Takens** (the 1:1 resonance of the map, where a fold curve and a
  Neimark–Sacker curve end on each other) on a fold curve: the other multiplier
  ``det Phi`` at 1; **fold-flip**: at -1;
- **strong resonances** on a Neimark–Sacker curve: ``e^{+-i theta}`` with ``theta = 0,
  pi, 2 pi/3, pi/2`` (``tr Phi = 2, -2, -1, 0``: 1:1 (named ``bogdanov-takens``), 1:2,
  1:3, 1:4);
- on a period-doubling curve: 1:2 resonance (``det Phi = 1``) and fold-flip
  (``det Phi = -1``).

**Averaged curves.**  The slow flow ``a' = A(a, phi)``, ``phi' = B(a, phi)`` of
:func:`kbm.expansion.forced.derive_forced` at orders 1..3 (the parameters of both axes kept as
symbols): its folds ``A = B = det d(A, B)/d(a, phi) = 0`` (the averaged fold curves, with
their cusp) and its Hopf points ``A = B = tr d(A, B)/d(a, phi) = 0``, ``det > 0`` (the
averaged Neimark–Sacker curves).  Their distance to the true curves is reported.

Seeds: the one-parameter true response curves in ``sigma`` at a few values of the other
parameter (:func:`numerics.shooting.forced_branch.numeric_response`, started from the KBM
fixed points) give
the folds and the sign changes of the period-doubling and Neimark–Sacker tests; the
averaged response curves (:func:`kbm.slowflow.steady.response_curve`) give the averaged seeds.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence

import numpy as np

from kbm.errors import ParameterError
from numerics.bifurcation.result import Codim2Point, Curve
from numerics.bifurcation.twoway import (FD_STEP, Task, both_ways, codim2_points, dropped_seed,
                                         interruptible, joined, on_known, trimmed, why_short)
from numerics.errors import NumericsError

__all__ = ["DrivenProblem", "MAP_TESTS", "forced_seeds", "forced_true_curves"]
#: kinds of codim-1 curves of the stroboscopic map and their test functions
MAP_TESTS = {
    "fold": {"bogdanov-takens": lambda tr, det: det - 1.0,
             "fold-flip": lambda tr, det: det + 1.0},
    "period-doubling": {"1:2 resonance": lambda tr, det: det - 1.0,
                        "fold-flip": lambda tr, det: det + 1.0},
    "neimark-sacker": {"bogdanov-takens": lambda tr, det: tr - 2.0,
                       "1:2 resonance": lambda tr, det: tr + 2.0,
                       "1:3 resonance": lambda tr, det: tr + 1.0,
                       "1:4 resonance": lambda tr, det: tr},
}


class DrivenProblem:
    """The periodic responses of a one-degree-of-freedom forced model in two parameters.

    Parameters
    ----------
    model
        A built-in forced model's name or a :class:`kbm.model.forced.ForcedOscillator`.
    values
        Every other parameter's value (``mu`` included).
    axes
        The two varied parameters ``(p1, p2)``.
    rtol
        The integrator's tolerance (``atol = rtol/10``).
    """

    def __init__(self, model, values: Mapping[str, float], axes: tuple[str, str],
                 rtol: float = 1e-11):
        from kbm.model.forced_builtins import get_forced_model
        from numerics.flow.coupled_flow import coupled_flow

        self.forced = get_forced_model(model) if isinstance(model, str) else model
        if getattr(self.forced, "resonance", None) is None:
            raise ParameterError(f"{getattr(model, 'name', model)!r} is not a forced model")
        self.system = self.forced  # the one model type: a forced oscillator is its N = 1 case
        self.axes = tuple(axes)
        self.values = {k: float(v) for k, v in values.items() if k not in self.axes}
        start = {**self.values, **{k: 0.0 for k in self.axes}}
        self.flow = coupled_flow(self.system, start)
        self._direct = all(k in self.flow.values for k in self.axes)
        self.periods = self.system.response_periods
        self.rtol = rtol

    def at(self, p1: float, p2: float):
        """The compiled flow at ``(p1, p2)``."""
        vals = {self.axes[0]: float(p1), self.axes[1]: float(p2)}
        if self._direct:
            return self.flow.at(**vals)
        from numerics.flow.coupled_flow import coupled_flow

        return coupled_flow(self.system, {**self.values, **vals})

    def period(self, fl) -> float:
        nu = fl.nu
        if not nu > 0:
            raise ArithmeticError(f"the forcing frequency {nu:.6g} is not positive")
        return self.periods * 2 * math.pi / nu

    @interruptible
    def monodromy(self, z) -> tuple[np.ndarray, np.ndarray]:
        """``(y(T) - y0, Phi(T))`` at ``z = (x0, v0, p1, p2)``."""
        fl = self.at(z[2], z[3])
        yT, Phi, _ = fl.monodromy(np.asarray(z[:2], dtype=float), self.period(fl),
                                  rtol=self.rtol, atol=self.rtol / 10)
        return yT - np.asarray(z[:2], dtype=float), Phi

    def system_for(self, kind: str) -> Callable:
        """The defining system ``G(z)`` of a curve of ``kind``."""
        def G(z):
            r, Phi = self.monodromy(z)
            tr, det = float(np.trace(Phi)), float(np.linalg.det(Phi))
            extra = {"fold": 1.0 - tr + det, "period-doubling": 1.0 + tr + det,
                     "neimark-sacker": det - 1.0}[kind]
            return np.array([r[0], r[1], extra])
        return G

    def jacobian_for(self, kind: str) -> Callable:
        """``G'(z)``: central differences (step :data:`FD_STEP`), the state block of the
        residual rows exact (``Phi - I``)."""
        G = self.system_for(kind)

        def J(z):
            z = np.asarray(z, dtype=float)
            cols = []
            for i in range(4):
                e = np.zeros(4)
                e[i] = FD_STEP * (1 + abs(z[i]))
                cols.append((G(z + e) - G(z - e)) / (2 * e[i]))
            M = np.column_stack(cols)
            M[:2, :2] = self.monodromy(z)[1] - np.eye(2)
            return M
        return J

    def partner(self, z) -> np.ndarray | None:
        """The point of the symmetric partner orbit: ``z`` with the state ``-y(pi/nu)``
        (the response from ``y0`` half a drive period on, mirrored), where the field is odd
        under the half-period shift, ``f(t + pi/nu, -y) = -f(t, y)`` (checked at the
        parameters of ``z`` on four states and times of a fixed random stream; Duffing's
        ``(x, x', theta) -> (-x, -x', theta + pi)``); ``None`` where it is not.  The partner
        has the same multipliers at the same parameters: it traces the same curves in the
        parameter plane."""
        fl = self.at(z[2], z[3])
        nu = fl.nu
        if not nu or not nu > 0:
            return None
        rng = np.random.default_rng(0)
        for _ in range(4):
            y, t = rng.normal(size=2), rng.uniform(0.0, 2 * math.pi / nu)
            f, g = fl.rhs(y, t), fl.rhs(-y, t + math.pi / nu)
            if not np.allclose(g, -f, rtol=1e-12, atol=1e-12):
                return None
        yh, _, _ = fl.monodromy(np.asarray(z[:2], dtype=float), math.pi / nu,
                                rtol=self.rtol, atol=self.rtol / 10)
        return np.concatenate([-yh, np.asarray(z[2:], dtype=float)])

    def multipliers(self, z) -> tuple[float, float]:
        """``(tr Phi, det Phi)`` at ``z``."""
        Phi = self.monodromy(z)[1]
        return float(np.trace(Phi)), float(np.linalg.det(Phi))


# -- true curves -------------------------------------------------------------------------------

def forced_seeds(prob: DrivenProblem, sigma_range: tuple[float, float], others: Sequence[float],
                 *, amplitudes=(1e-3, 5.0), n_points: int = 200) -> list[tuple[str, np.ndarray]]:
    """Seeds ``(kind, z0)`` of the true curves from the one-parameter response curves in
    ``sigma`` at each value in ``others`` of the other axis: its folds, and the sign changes
    of ``det(Phi + I)`` (period doubling) and of ``det Phi - 1`` with a complex pair
    (Neimark–Sacker) between neighbouring responses (interpolated)."""
    from kbm.expansion.forced import derive_forced
    from numerics.flow.forced_system import ForcedSystem
    from numerics.shooting.forced_branch import numeric_response

    s_idx = prob.axes.index("sigma")
    o_name = prob.axes[1 - s_idx]
    res = derive_forced(prob.forced, 1)
    seeds: list[tuple[str, np.ndarray]] = []

    def z_of(y0, s, o):
        z = np.zeros(4)
        z[:2] = y0
        z[2 + s_idx], z[3 - s_idx] = s, o
        return z

    for o in others:
        vals = {**prob.values, o_name: float(o)}
        system = ForcedSystem(prob.forced, vals, rtol=prob.rtol)
        sf = res.slow_flow({k: v for k, v in vals.items()})
        nr = numeric_response(system, sf, sigma_range, amplitudes, n_points=n_points)
        for f in nr.folds:
            seeds.append(("fold", z_of(f.y0, f.sigma, o)))
        for branch in nr.branches:
            for o1, o2 in zip(branch, branch[1:]):
                m1, m2 = np.array(o1.multipliers), np.array(o2.multipliers)
                pd1, pd2 = (float(np.real(np.prod(1 + m))) for m in (m1, m2))
                ns1, ns2 = (float(np.real(np.prod(m))) - 1 for m in (m1, m2))
                for kind, f1, f2, ok in (
                        ("period-doubling", pd1, pd2, True),
                        ("neimark-sacker", ns1, ns2,
                         bool(np.any(np.abs(m1.imag) > 0) and np.any(np.abs(m2.imag) > 0)))):
                    if ok and f1 * f2 < 0:
                        w = f1 / (f1 - f2)
                        y = (1 - w) * np.array(o1.y0) + w * np.array(o2.y0)
                        seeds.append((kind, z_of(y, (1 - w) * o1.sigma + w * o2.sigma, o)))
    return seeds


def forced_true_curves(prob: DrivenProblem, ranges: Mapping[str, tuple[float, float]],
                       seeds: Sequence[tuple[str, np.ndarray]], *, ds: float = 0.02,
                       max_points: int = 400, progress=None, on_task=None,
                       stored: Mapping[int, list] | None = None, dropped: list | None = None
                       ) -> tuple[list[Task], list[Curve], list[Codim2Point]]:
    """Continue the true curves from ``seeds`` (a seed already on a found curve of its kind
    is skipped); ``stored`` maps a task's index to its stored paths (resumed); ``dropped``
    receives a :func:`~numerics.bifurcation.twoway.dropped_seed` record of each seed that
    gave no curve (its correction failed, or its paths hold one point).

    Returns the tasks, their :class:`Curve` (``method = "true"``) and the codim-2 points."""
    bounds = {2: tuple(ranges[prob.axes[0]]), 3: tuple(ranges[prob.axes[1]])}
    spans = [bounds[2][1] - bounds[2][0], bounds[3][1] - bounds[3][0]]
    scale = np.array([1.0, 1.0, spans[0], spans[1]])
    tasks: list[Task] = []
    curves, points = [], []
    curve_of: dict[int, int] = {}
    stored = dict(stored or {})
    partners: dict[int, int] = {}
    for kind, z0 in seeds:
        if on_known(np.asarray(z0), tasks, kind, scale, 5 * ds):
            continue
        known = _partner_known(prob, z0, tasks, kind, scale, 5 * ds)
        if known is not None:  # the symmetric partner's copy of a curve found
            partners[known] = partners.get(known, 0) + 1
            continue
        task = Task(kind, "true", None, np.asarray(z0, dtype=float), problem=prob)
        idx = len(tasks)
        tasks.append(task)
        tests = {name: (lambda fn: lambda z: fn(*prob.multipliers(z)))(fn)
                 for name, fn in MAP_TESTS[kind].items()}
        if kind == "fold":
            tests["cusp"] = lambda z, t: float(t[3] / scale[3])
        stop = None
        if kind == "neimark-sacker":
            def stop(pt, path):
                tr, _ = prob.multipliers(pt.z)
                return "the multipliers became real (|tr Phi| > 2: a neutral saddle)" \
                    if abs(tr) > 2 else None
        try:
            task.paths = both_ways(prob.system_for(kind), z0, jac=prob.jacobian_for(kind),
                                   bounds=bounds, scale=scale, ds=ds, ds_max=5 * ds,
                                   max_points=max_points, tests=tests, stop=stop,
                                   progress=progress, resume=stored.get(idx, ()))
        except NumericsError as exc:
            tasks.pop()
            if dropped is not None:
                dropped.append(dropped_seed(kind, "true", None, z0[2:], str(exc)))
            continue
        if on_task is not None:
            on_task(idx, task)
        pts = joined(task.paths) if kind != "neimark-sacker" else \
            trimmed(task.paths, lambda z: abs(prob.multipliers(z)[0]) <= 2)
        if len(pts) < 2:
            if dropped is not None:
                dropped.append(dropped_seed(kind, "true", None, z0[2:], why_short(task.paths)))
            continue
        res = max(p.residual for path in task.paths for p in path.points)
        curves.append(Curve(kind, [tuple(p[2:]) for p in pts], "true", None,
                            {"residual_max": res, "points_converged": len(pts),
                             "ends": [p.end for p in task.paths]}))
        curve_of[idx] = len(curves) - 1
        points += codim2_points(task, (2, 3), prob.jacobian_for(kind), scale)
        if any(p.end == "interrupted" for p in task.paths):
            break
    for idx, n in partners.items():
        if idx in curve_of:
            c = curves[curve_of[idx]]
            curves[curve_of[idx]] = Curve(c.kind, c.points, c.method, c.order, {
                **dict(c.detail), "symmetric_partner": "the orbit (x, x')(t) -> -(x, x')(t + "
                "pi/nu) traces this curve too (reported once)"})
    return tasks, curves, points


def _partner_known(prob: DrivenProblem, z0, tasks: Sequence[Task], kind: str, scale, tol):
    """The index of the task whose curve the symmetric partner of the seed ``z0``
    (:meth:`DrivenProblem.partner`) lies on, else ``None``."""
    try:
        zp = prob.partner(np.asarray(z0, dtype=float))
    except (NumericsError, ArithmeticError):
        return None
    if zp is None:
        return None
    for i, t in enumerate(tasks):
        if t.kind == kind and on_known(zp, [t], kind, scale, tol):
            return i
    return None
