"""The averaged counterparts of a forced oscillator's two-parameter curves (issue 38).

The slow flow ``a' = A(a, phi)``, ``phi' = B(a, phi)`` of
:func:`kbm.expansion.forced.derive_forced` at orders 1..3, the parameters of both axes kept as
symbols (the rates divided by ``mu``: the same zeros): its folds
``A = B = det d(A, B)/d(a, phi) = 0`` (the averaged fold curves, with their cusps and
Bogdanov–Takens points, ``tr = 0`` on a fold) and its Hopf points
``A = B = tr d(A, B)/d(a, phi) = 0`` with ``det > 0`` (the averaged Neimark–Sacker curves, ended
where ``det`` reaches 0).  The seeds are the folds and the sign changes of the trace on the
averaged response curves (:func:`kbm.slowflow.steady.response_curve`).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence

import numpy as np
import sympy as sp

from kbm.output.evaluate import numpy_array_function
from numerics.bifurcation.result import Codim2Point, Curve
from numerics.bifurcation.twoway import (FD_STEP, Task, both_ways, codim2_points,
                                         dropped_seed, joined, on_known, trimmed, why_short)
from numerics.errors import NumericsError

__all__ = ["rates_system", "averaged_fold_curves"]


def _averaged_system(forced, values: Mapping[str, float], axes: tuple[str, str], order: int):
    """``G(z)``, ``G'(z)`` of the order-``order`` slow flow's fold and Hopf curves,
    ``z = (a, phi, p1, p2)``, the rates divided by ``mu`` (the same zeros)."""
    from kbm.expansion.forced import derive_forced
    from kbm.model.forced import phi as phi_s
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
    jac2 = numpy_array_function(sp.Matrix([da, dph]).jacobian([a_s, phi_s]).tolist(),
                                (a_s, phi_s, *P), cse=True)
    return systems, lambda z: np.array(jac2(*z), dtype=float)


def rates_system(rates: Sequence[sp.Expr], state: Sequence[sp.Symbol], P: Sequence[sp.Symbol],
                 test: str) -> tuple[Callable, Callable]:
    """``G(z) = (f, det df/dy)`` (``test = "det"``: folds) or ``(f, tr df/dy)``
    (``"trace"``: Hopf points) of the slow flow ``y' = f(y; p1, p2)``, ``z = (y, p1, p2)``,
    and its Jacobian: ``df/dz`` exact (lambdified), the test's row by central differences."""
    var = (*state, *P)
    F = sp.Matrix(list(rates))
    f = numpy_array_function(list(rates), var, cse=True)  # besselj: scipy.special.jv
    jac = numpy_array_function(F.jacobian(var).tolist(), var, cse=True)
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
                         amplitudes=(1e-3, 5.0), dropped: list | None = None
                         ) -> tuple[list[Curve], list[Codim2Point]]:
    """The slow flow's fold curves (with their cusp and Bogdanov–Takens points) and Hopf
    curves (the averaged Neimark–Sacker curves, ``det > 0``) at each order, seeded from the
    averaged response curves in ``sigma`` at the values ``others`` of the other axis;
    ``dropped`` receives a record of each seed that gave no curve."""
    from kbm.expansion.forced import derive_forced
    from kbm.slowflow.steady import response_curve

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
            if on_known(z0, tasks, kind, scale, 5 * ds):
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
            except NumericsError as exc:
                if dropped is not None:
                    dropped.append(dropped_seed(kind, "averaged", n, z0[2:], str(exc)))
                continue
            tasks.append(task)
            pts = joined(task.paths) if kind != "neimark-sacker" else \
                trimmed(task.paths, lambda z: np.linalg.det(jac2(z)) > 0)
            if len(pts) >= 2:
                curves.append(Curve(kind, [tuple(p[2:]) for p in pts], "averaged", n))
            elif dropped is not None:
                dropped.append(dropped_seed(kind, "averaged", n, z0[2:], why_short(task.paths)))
            points += codim2_points(task, (2, 3), J, scale)
    return curves, points
