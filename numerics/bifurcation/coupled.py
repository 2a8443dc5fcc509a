"""The locking tongue of coupled self-excited oscillators as fold curves in two parameters.

A locked state of ``x_i'' + omega_i**2 x_i = mu F_i(x, x')`` (``coupled-vdp``) is a cycle;
the edges of the locking region are its folds (saddle-nodes of cycles on the torus,
:mod:`numerics.locking.fold`).  In two parameters (the detuning and the coupling, or the
detuning and ``mu``) they are curves, continued here by
:func:`numerics.bifurcation.curve.continue_curve` on the defining system

    ``y(T) - y0 = 0`` (``2N`` equations; ``y0`` on the section ``xdot_1 = 0``),
    ``g(z) = 0``,

with the unknowns ``z = (y0 without xdot_1, T, p1, p2)`` and ``g`` the bordered test of
the shooting matrix ``M = [Phi(T) - I without the column of xdot_1, f(y(T))]``: the last
component of the solution of ``[[M, b], [c^T, 0]] (v, g) = (0, 1)``, zero exactly where
``M`` is singular (the non-trivial multiplier through 1 joins the trivial one: a fold of
cycles; Kuznetsov, *Elements of Applied Bifurcation Theory*, 3rd ed., sec. 10.2.2 for
bordered test functions).  ``b`` and ``c`` are the singular vectors of ``M``'s smallest
singular value at the seed.  The seeds are the folds of the one-parameter branches
(:func:`numerics.locking.fold.locate_fold`) from the locked cycle, followed on each seed
line from where ``kbm lock`` starts (:func:`line_start`: 0 when the range holds it, else
the first value from the middle out with a stable locked state of the order-1 slow flow).

The averaged tongue: the folds of the slow flow's locked fixed point
(:func:`kbm.expansion.coupled.derive_coupled` at orders 1..N, both axes kept as symbols),
``f(a, gamma) = 0``, ``det df/d(a, gamma) = 0``, continued the same way and seeded from
:func:`numerics.locking.mutual.averaged_edges`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import sympy as sp

from kbm.errors import KBMError, ParameterError
from numerics.bifurcation.forced_averaged import rates_system
from numerics.bifurcation.twoway import (FD_STEP, Task, both_ways, codim2_points, dropped_seed,
                                         interruptible, joined, on_known, why_short)
from numerics.bifurcation.result import Codim2Point, Curve
from numerics.errors import NoCycleError, NumericsError

__all__ = ["LockedCycleFold", "coupled_true_folds", "coupled_averaged_folds", "line_start"]


class LockedCycleFold:
    """The fold-of-cycles defining system of an autonomous coupled system in ``(p1, p2)``.

    Parameters
    ----------
    model
        A coupled built-in's name or a :class:`kbm.model.coupled.CoupledOscillators`.
    values
        Every other parameter's value (``mu`` included).
    axes
        The two varied parameters.
    rtol
        The integrator's tolerance.
    """

    def __init__(self, model, values: Mapping[str, float], axes: tuple[str, str],
                 rtol: float = 1e-11):
        from numerics.flow.coupled_flow import coupled_flow

        self.axes = tuple(axes)
        self.values = {k: float(v) for k, v in values.items() if k not in self.axes}
        self.flow = coupled_flow(model, {**self.values, **{k: 0.0 for k in self.axes}})
        if self.flow.nu is not None:
            raise ParameterError(f"{self.flow.model.name!r} is forced: its diagram is the "
                                 "forced responses' (a one-degree-of-freedom forced model)")
        self.model = self.flow.model
        self.n = self.flow.dof
        self.free = [j for j in range(2 * self.n) if j != self.n]
        self.rtol = rtol
        self.border: tuple[np.ndarray, np.ndarray] | None = None

    def state(self, z) -> np.ndarray:
        y = np.zeros(2 * self.n)
        y[self.free] = z[:2 * self.n - 1]
        return y

    @interruptible
    def shooting(self, z) -> tuple[np.ndarray, np.ndarray]:
        """``(y(T) - y0, M)`` at ``z``."""
        k = 2 * self.n
        fl = self.flow.at(**{self.axes[0]: float(z[k]), self.axes[1]: float(z[k + 1])})
        y0 = self.state(z)
        T = float(z[k - 1])
        if not T > 0:
            raise ArithmeticError(f"the period {T:.6g} is not positive")
        yT, Phi, _ = fl.monodromy(y0, T, rtol=self.rtol, atol=self.rtol / 10)
        M = np.empty((k, k))
        M[:, :-1] = Phi[:, self.free] - np.eye(k)[:, self.free]
        M[:, -1] = fl.rhs(yT)
        return yT - y0, M

    def set_border(self, z) -> None:
        """``b``, ``c``: the left and right singular vectors of ``M``'s smallest singular
        value at ``z``."""
        _, M = self.shooting(z)
        u, _, vt = np.linalg.svd(M)
        self.border = (u[:, -1].copy(), vt[-1].copy())

    def test(self, M: np.ndarray) -> float:
        b, c = self.border
        k = len(M)
        A = np.zeros((k + 1, k + 1))
        A[:k, :k], A[:k, k], A[k, :k] = M, b, c
        rhs = np.zeros(k + 1)
        rhs[k] = 1.0
        return float(np.linalg.solve(A, rhs)[k])

    def G(self, z) -> np.ndarray:
        r, M = self.shooting(z)
        return np.append(r, self.test(M))

    def J(self, z) -> np.ndarray:
        """Central differences (step :data:`numerics.bifurcation.forced.FD_STEP`)."""
        z = np.asarray(z, dtype=float)
        cols = []
        for i in range(len(z)):
            e = np.zeros(len(z))
            e[i] = FD_STEP * (1 + abs(z[i]))
            cols.append((self.G(z + e) - self.G(z - e)) / (2 * e[i]))
        return np.column_stack(cols)


def _seed_axis(axes: tuple[str, str]) -> int:
    return axes.index("sigma") if "sigma" in axes else 0


def line_start(model, params: Mapping[str, float], s_name: str, o_name: str, o: float,
               span: tuple[float, float]) -> float:
    """Where the locked state is followed from on the seed line ``o_name = o``: ``kbm
    lock``'s start (:func:`numerics.locking.start.locked_start` at order 1), 0 when
    ``span`` holds it, else the first value from the middle out at which the order-1 slow
    flow has a stable locked state (``mu`` followed, which the slow flow does not take as
    its parameter, or a model without an order-1 slow flow: the first of those values).

    Raises
    ------
    numerics.errors.NoCycleError
        If the slow flow has no stable locked state at any value tried.
    """
    from numerics.locking.start import locked_start, start_values

    if s_name != "mu":
        try:
            return locked_start(model, {**params, o_name: float(o)}, 1, s_name, span,
                                f"{o_name} = {o:g}")
        except NoCycleError:
            raise
        except KBMError:  # no slow flow to choose by: the true cycle decides
            pass
    return start_values(*span)[0]


def coupled_true_folds(model, params: Mapping[str, float], axes: tuple[str, str],
                       ranges: Mapping[str, tuple[float, float]], others: Sequence[float], *,
                       ds: float = 0.02, max_points: int = 300, progress=None,
                       tasks_out: list | None = None, dropped: list | None = None,
                       lines: list | None = None) -> tuple[list[Curve], list[Codim2Point]]:
    """The true fold curves of the locked cycle (the tongue's edges), seeded at the values
    ``others`` of the axis that is not the detuning; ``tasks_out`` receives the
    :class:`~numerics.bifurcation.forced.Task` of each curve (its paths' full ``z``, its
    :class:`LockedCycleFold` as ``problem``), ``dropped`` a record of each seed that gave no
    curve, ``lines`` one record per seed line: ``{"at": {other: value}, "along": name,
    "from": start, "to": [lo, hi], "folds": [...], "period": T, "cycle": error}`` (the
    locked cycle at ``from`` and its period, or why there is none, and the folds met going
    both ways to the range's ends: a diagram without curves says why from these)."""
    from numerics.shooting.coupled_orbit import coupled_cycle
    from numerics.locking.fold import locate_fold
    from numerics.locking.start import start_values

    s_i = _seed_axis(axes)
    s_name, o_name = axes[s_i], axes[1 - s_i]
    lo, hi = ranges[s_name]
    curves, points, tasks = [], [], []
    n2 = None
    for o in others:
        prob = LockedCycleFold(model, params, axes)
        n2 = 2 * prob.n
        line = {"at": {o_name: float(o)}, "along": s_name, "from": start_values(lo, hi)[0],
                "to": [lo, hi], "folds": [], "period": None, "cycle": None}
        if lines is not None:
            lines.append(line)
        try:
            start = line["from"] = line_start(prob.model, prob.values, s_name, o_name, o,
                                              (lo, hi))
            vals = {**prob.values, o_name: float(o), s_name: start}
            cyc = coupled_cycle(prob.model, vals)
        except NumericsError as exc:
            line["cycle"] = str(exc)
            continue
        line["period"] = float(cyc.period)
        rest = {k: v for k, v in vals.items() if k != s_name}
        bounds = {n2: tuple(ranges[axes[0]]), n2 + 1: tuple(ranges[axes[1]])}
        scale = np.concatenate([np.ones(n2 - 1), [cyc.period],
                                [bounds[n2][1] - bounds[n2][0],
                                 bounds[n2 + 1][1] - bounds[n2 + 1][0]]])
        for side, beyond in ((-1, lo), (1, hi)):
            fold = locate_fold(prob.model, rest, s_name, cyc.state, cyc.period, start, side,
                               beyond)
            if fold is None:
                continue
            line["folds"].append(float(fold.parameter))
            z0 = np.zeros(n2 + 2)
            z0[:n2 - 1] = np.asarray(fold.state)[prob.free]
            z0[n2 - 1] = fold.period
            z0[n2 + s_i], z0[n2 + 1 - s_i] = fold.parameter, o
            if on_known(z0, tasks, "fold", scale, 5 * ds):
                continue
            prob = LockedCycleFold(model, params, axes)  # its own border
            prob.set_border(z0)
            task = Task("fold", "true", None, z0, problem=prob)
            tests = {"cusp": lambda z, t, i=n2 + 1 - s_i: float(t[i] / scale[i])}
            try:
                task.paths = both_ways(prob.G, z0, jac=prob.J, bounds=bounds, scale=scale,
                                       ds=ds, ds_max=5 * ds, max_points=max_points,
                                       tests=tests, progress=progress)
            except NumericsError as exc:
                if dropped is not None:
                    dropped.append(dropped_seed("fold", "true", None, z0[n2:], str(exc)))
                continue
            tasks.append(task)
            if tasks_out is not None:
                tasks_out.append(task)
            pts = joined(task.paths)
            if len(pts) < 2 and dropped is not None:
                dropped.append(dropped_seed("fold", "true", None, z0[n2:],
                                            why_short(task.paths)))
            if len(pts) >= 2:
                res = max(p.residual for p in (q for path in task.paths for q in path.points))
                curves.append(Curve("fold", [tuple(p[n2:]) for p in pts], "true", None,
                                    {"label": "locking edge", "residual_max": res,
                                     "period": [float(p[n2 - 1]) for p in pts],
                                     "ends": [p.end for p in task.paths]}))
            points += codim2_points(task, (n2, n2 + 1), prob.J, scale)
            if any(p.end == "interrupted" for p in task.paths):
                return curves, points
    return curves, points


def _averaged_fold_system(model, values: Mapping[str, float], axes: tuple[str, str], order: int):
    from kbm.model.coupled import amplitudes
    from kbm.expansion.coupled import derive_coupled

    fixed = {k: sp.nsimplify(v, rational=True) for k, v in values.items()
             if k not in axes and k != "mu"}
    res = derive_coupled(model, order, fixed)
    rates = res.slow_flow()
    state = [*amplitudes(model.dof), *[g for g, _ in res.gammas]]
    P = [sp.Symbol(a) for a in axes]
    subs = {} if "mu" in axes else {sp.Symbol("mu"): float(values["mu"])}
    mu_e = P[axes.index("mu")] if "mu" in axes else float(values["mu"])
    rates = [r.subs(subs) / mu_e for r in rates]
    G, J = rates_system(rates, state, P, "det")
    return G, J, len(state)


def coupled_averaged_folds(model, params: Mapping[str, float], axes: tuple[str, str],
                           ranges: Mapping[str, tuple[float, float]], orders: Sequence[int],
                           others: Sequence[float], *, ds: float = 0.02, max_points: int = 300,
                           dropped: list | None = None) -> list[Curve]:
    """The averaged tongue: the slow flow's fold curves of its locked state at ``orders``;
    ``dropped`` receives a record of each order the engine does not take, each seed line
    without a locked state and each seed that gave no curve."""
    from numerics.flow.coupled_flow import bind_coupled
    from numerics.locking.mutual import averaged_edges

    s_i = _seed_axis(axes)
    s_name, o_name = axes[s_i], axes[1 - s_i]
    bound, _ = bind_coupled(model, {**dict(params), **{k: 0 for k in axes}})
    vals = {k: float(v) for k, v in params.items() if k not in axes}
    lo, hi = ranges[s_name]
    curves = []
    for n in orders:
        try:
            G, J, m = _averaged_fold_system(bound, vals, axes, n)
        except Exception as exc:  # noqa: BLE001 - an order the engine does not take
            if isinstance(exc, (KeyboardInterrupt, SystemExit)):
                raise
            if dropped is not None:
                dropped.append({"kind": "fold", "method": "averaged", "order": n,
                                "seed": None, "reason": f"no order-{n} slow flow ("
                                + str(exc).split(": ")[0] + ")"})
            continue
        bounds = {m: tuple(ranges[axes[0]]), m + 1: tuple(ranges[axes[1]])}
        scale = np.concatenate([np.ones(m), [bounds[m][1] - bounds[m][0],
                                             bounds[m + 1][1] - bounds[m + 1][0]]])
        tasks: list[Task] = []
        for o in others:
            try:
                start = line_start(bound, vals, s_name, o_name, o, (lo, hi))  # as the true
                edges = averaged_edges(bound, {**vals, o_name: float(o)}, n, s_name,
                                       max(abs(lo - start), abs(hi - start)), at=start)
            except NumericsError as exc:
                if dropped is not None:
                    dropped.append({"kind": "fold", "method": "averaged", "order": n,
                                    "seed": None, "reason": f"at {o_name} = {o:g}: {exc}"})
                continue
            for e in edges:
                if not (lo <= e.sigma <= hi):
                    continue
                z0 = np.zeros(m + 2)
                z0[:m] = e.state
                z0[m + s_i], z0[m + 1 - s_i] = e.sigma, o
                if on_known(z0, tasks, "fold", scale, 5 * ds):
                    continue
                task = Task("fold", "averaged", n, z0)
                try:
                    task.paths = both_ways(G, z0, jac=J, bounds=bounds, scale=scale, ds=ds,
                                           ds_max=5 * ds, max_points=max_points, tol=1e-12)
                except NumericsError as exc:
                    if dropped is not None:
                        dropped.append(dropped_seed("fold", "averaged", n, z0[m:],
                                                    str(exc) + _singular(J, z0)))
                    continue
                tasks.append(task)
                pts = joined(task.paths)
                if len(pts) >= 2:
                    curves.append(Curve("fold", [tuple(p[m:]) for p in pts], "averaged", n,
                                        {"label": "locking edge"}))
                elif dropped is not None:
                    dropped.append(dropped_seed("fold", "averaged", n, z0[m:],
                                                why_short(task.paths)))
    return curves


def _singular(J, z0) -> str:
    """Why Newton fails from a seed where the fold's defining system is singular (its
    Jacobian of rank below full: not a regular curve), else ``""``."""
    try:
        sv = np.linalg.svd(np.asarray(J(z0), dtype=float), compute_uv=False)
    except (ValueError, np.linalg.LinAlgError, ArithmeticError):
        return ""
    if not (np.all(np.isfinite(sv)) and sv[-1] <= 1e-8 * sv[0]):
        return ""
    return (f"; the defining system of a fold is singular at the seed (smallest singular "
            f"value {sv[-1]:.1e} of {sv[0]:.2g}): the locked state loses its stability there "
            "without a fold (e.g. a symmetry-breaking pitchfork of identical oscillators), "
            "and the diagram continues folds only")
