"""Two-parameter bifurcation curves of a forced oscillator, true and averaged (issue 38).

The forced oscillator ``x'' + omega0**2 x = mu F(x, x', nu t)``, ``nu = (p/q) omega0 + mu
sigma``, has periodic responses of the drive's period ``T = 2 pi p/nu``: fixed points of the
stroboscopic map ``y0 -> y(T)``.  Their codim-1 bifurcations are continued in two
parameters (one of them the detuning ``sigma``) by :func:`numerics.bifurcation.curve.
continue_curve` on the defining systems (unknowns ``z = (x(0), x'(0), p1, p2)``; the flow
and its monodromy ``Phi(T)`` from one compiled integration,
:meth:`numerics.coupled.flow.CoupledFlow.monodromy`):

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
:func:`kbm.forced.derive_forced` at orders 1..3 (the parameters of both axes kept as
symbols): its folds ``A = B = det d(A, B)/d(a, phi) = 0`` (the averaged fold curves, with
their cusp) and its Hopf points ``A = B = tr d(A, B)/d(a, phi) = 0``, ``det > 0`` (the
averaged Neimark–Sacker curves).  Their distance to the true curves is reported.

Seeds: the one-parameter true response curves in ``sigma`` at a few values of the other
parameter (:func:`numerics.forced.numeric_response`, started from the KBM fixed points) give
the folds and the sign changes of the period-doubling and Neimark–Sacker tests; the
averaged response curves (:func:`kbm.forced.steady.response_curve`) give the averaged seeds.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
import sympy as sp

from kbm.errors import ParameterError
from numerics.bifurcation.curve import CurvePath, continue_curve
from numerics.bifurcation.result import Codim2Point, Curve, Diagram
from numerics.errors import NumericsError

__all__ = ["DrivenProblem", "Task", "both_ways", "rates_system", "forced_seeds",
           "forced_true_curves", "averaged_fold_curves", "merged", "trimmed", "forced_diagram", "curve_distance", "FD_STEP"]

#: the central-difference step of the defining systems' Jacobians (relative)
FD_STEP = 1e-6
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
        A built-in forced model's name or a :class:`kbm.forced.ForcedOscillator`.
    values
        Every other parameter's value (``mu`` included).
    axes
        The two varied parameters ``(p1, p2)``.
    rtol
        The integrator's tolerance (``atol = rtol/10``).
    """

    def __init__(self, model, values: Mapping[str, float], axes: tuple[str, str],
                 rtol: float = 1e-11):
        from kbm.coupled import CoupledOscillators
        from kbm.forced import get_forced_model
        from numerics.coupled import coupled_flow

        self.forced = get_forced_model(model) if isinstance(model, str) else model
        if getattr(self.forced, "resonance", None) is None:
            raise ParameterError(f"{getattr(model, 'name', model)!r} is not a forced model")
        self.system = CoupledOscillators.from_oscillator(self.forced)
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
        from numerics.coupled import coupled_flow

        return coupled_flow(self.system, {**self.values, **vals})

    def period(self, fl) -> float:
        nu = fl.nu
        if not nu > 0:
            raise ArithmeticError(f"the forcing frequency {nu:.6g} is not positive")
        return self.periods * 2 * math.pi / nu

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

    def multipliers(self, z) -> tuple[float, float]:
        """``(tr Phi, det Phi)`` at ``z``."""
        Phi = self.monodromy(z)[1]
        return float(np.trace(Phi)), float(np.linalg.det(Phi))


@dataclass
class Task:
    """One curve to continue: its kind, method (``"true"``/``"averaged"``), order, the
    seed ``z0`` and the paths found (both directions)."""

    kind: str
    method: str
    order: int | None
    z0: np.ndarray
    paths: list = field(default_factory=list)
    problem: object = None


def both_ways(G, z0, *, jac=None, bounds, scale=None, ds=0.02, ds_max=0.1, max_points=400,
              tests=None, stop=None, progress=None, tol=1e-10, resume=()
              ) -> list[CurvePath]:
    """The curve through ``z0`` continued in both directions (the second path not started
    when the first closed on itself); ``resume`` the stored paths (continued)."""
    out = []
    first_tangent = None
    for k, sign in enumerate((1.0, -1.0)):
        old = resume[k] if k < len(resume) else None
        if old is not None and old.end not in ("interrupted", ""):
            out.append(old)
            if old.end == "closed":
                break
            continue
        tangent = None if first_tangent is None else sign * first_tangent
        path = continue_curve(G, z0, jac=jac, tangent=tangent, ds=ds, ds_max=ds_max,
                              bounds=bounds, max_points=max_points, tol=tol, tests=tests,
                              stop=stop, progress=progress, scale=scale, resume=old)
        out.append(path)
        if path.points and first_tangent is None:
            first_tangent = np.asarray(path.points[0].tangent, dtype=float)
        if path.end in ("closed", "interrupted"):
            break
    return out


def joined(paths: Sequence[CurvePath]) -> np.ndarray:
    """The points of two paths from one seed as one array (the second reversed first)."""
    if not paths or not paths[0].points:
        return np.zeros((0, 0))
    a = [p.z for p in paths[0].points]
    b = [p.z for p in paths[1].points[1:]] if len(paths) > 1 else []
    return np.array(list(reversed(b)) + a)


def trimmed(paths: Sequence[CurvePath], ok: Callable) -> np.ndarray:
    """:func:`joined` without the end points where ``ok(z)`` fails (a Neimark–Sacker path
    stopped one point past its Bogdanov–Takens end), that end's located test zero put in
    their place."""
    kept = []
    for path in paths:
        pts = [p.z for p in path.points]
        if pts and not ok(pts[-1]):
            pts = pts[:-1]
            ends = [e.z for e in path.events if e.name == "bogdanov-takens"]
            if ends:
                pts.append(np.asarray(ends[-1]))
        kept.append(pts)
    if not kept or not kept[0]:
        return np.zeros((0, 0))
    rest = kept[1][1:] if len(kept) > 1 else []
    return np.array(list(reversed(rest)) + kept[0])


def _near_polyline(pt: np.ndarray, line: np.ndarray) -> float:
    """Distance from ``pt`` to the polyline through the rows of ``line``."""
    if len(line) == 0:
        return math.inf
    if len(line) == 1:
        return float(np.linalg.norm(pt - line[0]))
    a, b = line[:-1], line[1:]
    d = b - a
    den = np.maximum(np.einsum("ij,ij->i", d, d), 1e-300)
    s = np.clip(np.einsum("ij,ij->i", pt - a, d) / den, 0.0, 1.0)
    return float(np.min(np.linalg.norm(a + s[:, None] * d - pt, axis=1)))


def curve_distance(a: Sequence, b: Sequence) -> float:
    """The largest distance from a point of the curve ``a`` to the polyline ``b`` (both in
    the parameter plane): the directed Hausdorff distance."""
    A, B = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    if len(A) == 0 or len(B) == 0:
        return math.nan
    return max(_near_polyline(p, B) for p in A)


def _on_known(z0: np.ndarray, tasks: Sequence[Task], kind: str, scale: np.ndarray,
              tol: float) -> bool:
    for t in tasks:
        if t.kind == kind:
            pts = joined(t.paths)
            if len(pts) and _near_polyline(z0 / scale, pts / scale) < tol:
                return True
    return False


def _codim2(task: Task, axes_idx: tuple[int, int], ptest) -> list[Codim2Point]:
    """The located test-function zeros of a task's paths as named points (a ``cusp`` only
    where both parameter components of the tangent vanish)."""
    out = []
    i, j = axes_idx
    for path in task.paths:
        for ev in path.events:
            kind = ev.name
            if kind == "cusp" and not ptest(ev.z):
                continue
            p = (float(ev.z[i]), float(ev.z[j]))
            if any(o.kind == kind and math.hypot(o.point[0] - p[0], o.point[1] - p[1]) < 1e-6
                   for o in out):
                continue
            out.append(Codim2Point(kind, p, {"on": task.kind, "method": task.method,
                                             "order": task.order, "test": float(ev.value),
                                             "residual": float(ev.residual)}))
    return out


# -- true curves -------------------------------------------------------------------------------

def forced_seeds(prob: DrivenProblem, sigma_range: tuple[float, float], others: Sequence[float],
                 *, amplitudes=(1e-3, 5.0), n_points: int = 200) -> list[tuple[str, np.ndarray]]:
    """Seeds ``(kind, z0)`` of the true curves from the one-parameter response curves in
    ``sigma`` at each value in ``others`` of the other axis: its folds, and the sign changes
    of ``det(Phi + I)`` (period doubling) and of ``det Phi - 1`` with a complex pair
    (Neimark–Sacker) between neighbouring responses (interpolated)."""
    from kbm.forced import derive_forced
    from numerics.forced import ForcedSystem, numeric_response

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
                       stored: Mapping[int, list] | None = None
                       ) -> tuple[list[Task], list[Curve], list[Codim2Point]]:
    """Continue the true curves from ``seeds`` (a seed already on a found curve of its kind
    is skipped); ``stored`` maps a task's index to its stored paths (resumed).

    Returns the tasks, their :class:`Curve` (``method = "true"``) and the codim-2 points."""
    bounds = {2: tuple(ranges[prob.axes[0]]), 3: tuple(ranges[prob.axes[1]])}
    spans = [bounds[2][1] - bounds[2][0], bounds[3][1] - bounds[3][0]]
    scale = np.array([1.0, 1.0, spans[0], spans[1]])
    tasks: list[Task] = []
    curves, points = [], []
    stored = dict(stored or {})
    for kind, z0 in seeds:
        if _on_known(np.asarray(z0), tasks, kind, scale, 5 * ds):
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
        except NumericsError:
            tasks.pop()
            continue
        if on_task is not None:
            on_task(idx, task)
        pts = joined(task.paths) if kind != "neimark-sacker" else \
            trimmed(task.paths, lambda z: abs(prob.multipliers(z)[0]) <= 2)
        if len(pts) < 2:
            continue
        res = max(p.residual for path in task.paths for p in path.points)
        curves.append(Curve(kind, [tuple(p[2:]) for p in pts], "true", None,
                            {"residual_max": res, "points_converged": len(pts),
                             "ends": [p.end for p in task.paths]}))

        def cusp_ok(z, prob=prob, kind=kind):
            _, _, vt = np.linalg.svd(prob.jacobian_for(kind)(z))
            t = vt[-1] / scale
            t /= np.linalg.norm(t)
            return abs(t[2]) < 1e-3 and abs(t[3]) < 1e-3
        points += _codim2(task, (2, 3), cusp_ok)
        if any(p.end == "interrupted" for p in task.paths):
            break
    return tasks, curves, points


# -- averaged curves ---------------------------------------------------------------------------

def _averaged_system(forced, values: Mapping[str, float], axes: tuple[str, str], order: int):
    """``G(z)``, ``G'(z)`` of the order-``order`` slow flow's fold and Hopf curves,
    ``z = (a, phi, p1, p2)``, the rates divided by ``mu`` (the same zeros)."""
    from kbm.forced import derive_forced
    from kbm.forced.model import phi as phi_s
    from kbm.symbols import a as a_s

    res = derive_forced(forced, order)
    da, dph = res.amplitude_rate(order), res.phase_rate(order)
    P = [sp.Symbol(n) for n in axes]
    mu_v = float(values.get("mu", 0)) if "mu" not in axes else None
    subs = {sp.Symbol(k): sp.nsimplify(v) if k != "mu" else v for k, v in values.items()
            if k not in axes}
    da, dph = da.subs(subs), dph.subs(subs)
    mu_e = P[axes.index("mu")] if mu_v is None else mu_v
    da, dph = da / mu_e, dph / mu_e
    systems = {kind: rates_system([da, dph], [a_s, phi_s], P, test)
               for kind, test in (("fold", "det"), ("neimark-sacker", "trace"))}
    jac2 = sp.lambdify((a_s, phi_s, *P), sp.Matrix([da, dph]).jacobian([a_s, phi_s]).tolist(),
                       "numpy", cse=True)
    return systems, lambda z: np.array(jac2(*z), dtype=float)


def rates_system(rates: Sequence[sp.Expr], state: Sequence[sp.Symbol], P: Sequence[sp.Symbol],
                 test: str) -> tuple[Callable, Callable]:
    """``G(z) = (f, det df/dy)`` (``test = "det"``: folds) or ``(f, tr df/dy)``
    (``"trace"``: Hopf points) of the slow flow ``y' = f(y; p1, p2)``, ``z = (y, p1, p2)``,
    and its Jacobian: ``df/dz`` exact (lambdified), the test's row by central differences."""
    var = (*state, *P)
    F = sp.Matrix(list(rates))
    f = sp.lambdify(var, list(rates), "numpy", cse=True)
    jac = sp.lambdify(var, F.jacobian(var).tolist(), "numpy", cse=True)
    m = len(state)

    def extra(Jz):
        Jy = Jz[:, :m]
        return float(np.linalg.det(Jy)) if test == "det" else float(np.trace(Jy))

    def G(z):
        Jz = np.array(jac(*z), dtype=float)
        return np.append(np.array(f(*z), dtype=float), extra(Jz))

    def J(z):
        z = np.asarray(z, dtype=float)
        Jz = np.array(jac(*z), dtype=float)
        row = np.empty(len(z))
        for i in range(len(z)):
            e = np.zeros(len(z))
            e[i] = FD_STEP * (1 + abs(z[i]))
            row[i] = (extra(np.array(jac(*(z + e)), dtype=float))
                      - extra(np.array(jac(*(z - e)), dtype=float))) / (2 * e[i])
        return np.vstack([Jz, row])
    return G, J


def averaged_fold_curves(forced, values: Mapping[str, float], axes: tuple[str, str],
                         ranges: Mapping[str, tuple[float, float]], orders: Sequence[int],
                         others: Sequence[float], *, ds: float = 0.02, max_points: int = 400,
                         amplitudes=(1e-3, 5.0)) -> tuple[list[Curve], list[Codim2Point]]:
    """The slow flow's fold curves (with their cusp and Bogdanov–Takens points) and Hopf
    curves (the averaged Neimark–Sacker curves, ``det > 0``) at each order, seeded from the
    averaged response curves in ``sigma`` at the values ``others`` of the other axis."""
    from kbm.forced import derive_forced
    from kbm.forced.steady import response_curve

    s_idx = axes.index("sigma")
    o_name = axes[1 - s_idx]
    bounds = {2: tuple(ranges[axes[0]]), 3: tuple(ranges[axes[1]])}
    spans = [bounds[2][1] - bounds[2][0], bounds[3][1] - bounds[3][0]]
    scale = np.array([1.0, 1.0, spans[0], spans[1]])
    curves, points = [], []
    for n in orders:
        systems, jac2 = _averaged_system(forced, values, axes, n)
        res = derive_forced(forced, n)
        seeds = []
        for o in others:
            sf = res.slow_flow({**values, o_name: float(o)}, n)
            rc = response_curve(sf, tuple(ranges["sigma"]), amplitudes, n_points=200)
            for f in rc.folds:
                z = np.zeros(4)
                z[:2] = (f.amplitude, f.phase)
                z[2 + s_idx], z[3 - s_idx] = f.sigma, o
                seeds.append(("fold", z))
            for b in rc.branches:
                trs = []
                for k in range(len(b.sigma)):
                    Jm = sf.jacobian(b.amplitude[k], b.phase[k], b.sigma[k])[:, :2]
                    trs.append((np.trace(Jm), np.linalg.det(Jm)))
                for k in range(len(trs) - 1):
                    if trs[k][0] * trs[k + 1][0] < 0 and trs[k][1] > 0 and trs[k + 1][1] > 0:
                        z = np.zeros(4)
                        z[:2] = (b.amplitude[k], b.phase[k])
                        z[2 + s_idx], z[3 - s_idx] = b.sigma[k], o
                        seeds.append(("neimark-sacker", z))
        tasks: list[Task] = []
        for kind, z0 in seeds:
            if _on_known(z0, tasks, kind, scale, 5 * ds):
                continue
            G, J = systems[kind]
            tests = {"cusp": lambda z, t: float(t[3] / scale[3])} if kind == "fold" else {}
            if kind == "fold":
                tests["bogdanov-takens"] = lambda z: float(np.trace(jac2(z)))
            stop = None
            if kind == "neimark-sacker":
                tests["bogdanov-takens"] = lambda z: float(np.linalg.det(jac2(z)))

                def stop(pt, path):
                    return "the eigenvalues became real (det < 0: a neutral saddle)" \
                        if np.linalg.det(jac2(pt.z)) <= 0 else None
            task = Task(kind, "averaged", n, z0)
            try:
                task.paths = both_ways(G, z0, jac=J, bounds=bounds, scale=scale, ds=ds,
                                       ds_max=5 * ds, max_points=max_points, tests=tests,
                                       stop=stop, tol=1e-12)
            except NumericsError:
                continue
            tasks.append(task)
            pts = joined(task.paths) if kind != "neimark-sacker" else \
                trimmed(task.paths, lambda z: np.linalg.det(jac2(z)) > 0)
            if len(pts) >= 2:
                curves.append(Curve(kind, [tuple(p[2:]) for p in pts], "averaged", n))

            def cusp_ok(z, J=J):
                _, _, vt = np.linalg.svd(J(z))
                t = vt[-1] / scale
                t /= np.linalg.norm(t)
                return abs(t[2]) < 1e-3 and abs(t[3]) < 1e-3
            points += _codim2(task, (2, 3), cusp_ok)
    return curves, points


def forced_diagram(model, params: Mapping[str, float], axes: tuple[str, str],
                   ranges: Mapping[str, tuple[float, float]], *, orders: Sequence[int] = (1, 2, 3),
                   seeds_at: int = 3, ds: float = 0.02, max_points: int = 400, progress=None
                   ) -> Diagram:
    """The two-parameter diagram of a forced model: true curves, averaged curves at
    ``orders``, codim-2 points, and the distances (true against averaged) in ``detail``.

    Raises
    ------
    kbm.errors.ParameterError
        When ``sigma`` is not one of the axes.
    """
    if "sigma" not in axes:
        raise ParameterError("a forced diagram varies the detuning and one other parameter: "
                             f"--vary sigma=FROM:TO --vary {axes[0]}=FROM:TO")
    prob = DrivenProblem(model, params, axes)
    o_name = axes[1 - axes.index("sigma")]
    lo, hi = ranges[o_name]
    others = list(np.linspace(lo, hi, seeds_at + 1)[1:][::-1])
    seeds = forced_seeds(prob, tuple(ranges["sigma"]), others)
    _, curves, points = forced_true_curves(prob, ranges, seeds, ds=ds, max_points=max_points,
                                           progress=progress)
    av_curves, av_points = averaged_fold_curves(prob.forced, prob.values, axes, ranges, orders,
                                                others, ds=ds, max_points=max_points)
    return Diagram(prob.forced.name, dict(prob.values), axes, ranges,
                   tuple(curves + av_curves), tuple(merged(points + av_points)),
                   {"distance": distances(curves, av_curves, points, av_points)})


def distances(true: Sequence[Curve], averaged: Sequence[Curve], tp: Sequence[Codim2Point],
              ap: Sequence[Codim2Point]) -> dict:
    """``{kind: {order: d}}``: for a curve kind, the largest distance from a point of the
    true curves of that kind to the averaged ones of the order (the parameter plane); for
    a codim-2 kind (``cusp``, ``bogdanov-takens``, ...), the largest distance from a true
    point to the nearest averaged point of that kind and order."""
    out: dict = {}
    for kind in sorted({c.kind for c in true}):
        tpts = [p for c in true if c.kind == kind for p in c.points]
        for n in sorted({c.order for c in averaged if c.kind == kind}):
            apts = [c for c in averaged if c.kind == kind and c.order == n]
            d = max((min(curve_distance([p], c.points) for c in apts) for p in tpts),
                    default=math.nan)
            out.setdefault(kind, {})[str(n)] = d
    for kind in sorted({p.kind for p in tp}):
        orders = sorted({a.detail.get("order") for a in ap if a.kind == kind})
        for n in orders:
            near = [a.point for a in ap if a.kind == kind and a.detail.get("order") == n]
            d = max(min(math.dist(t.point, q) for q in near) for t in tp if t.kind == kind)
            out.setdefault(kind, {})[str(n)] = d
    return out


def merged(points: Sequence[Codim2Point], tol: float = 1e-6) -> list[Codim2Point]:
    """The codim-2 points with the copies found on two curves (a Bogdanov–Takens point
    ends both a fold and a Neimark–Sacker curve) merged, their curves listed in ``on``."""
    out: list[Codim2Point] = []
    for p in points:
        same = next((q for q in out if q.kind == p.kind and
                     q.detail.get("method") == p.detail.get("method") and
                     q.detail.get("order") == p.detail.get("order") and
                     math.dist(q.point, p.point) < tol * (1 + math.hypot(*p.point))), None)
        if same is None:
            out.append(p)
            continue
        on = sorted({*str(same.detail.get("on", "")).split(","), str(p.detail.get("on", ""))})
        out[out.index(same)] = Codim2Point(same.kind, same.point,
                                           {**dict(same.detail), "on": ",".join(on)})
    return out
