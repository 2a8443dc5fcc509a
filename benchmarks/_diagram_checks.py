"""kbm's side of ``bench_diagram.py``'s checks of AUTO-07p's curves: at each of AUTO's
points, kbm's defining system solved with one parameter fixed at AUTO's value (Newton on
the fold systems, the secant method on the manifolds' gap), and the distance in the other.
"""

from __future__ import annotations

import numpy as np

from numerics.bifurcation.forced import DrivenProblem
from numerics.bifurcation.twoway import joined


def fold_sigma_at(prob: DrivenProblem, z0: np.ndarray, h: float, tol: float = 1e-10):
    """kbm's fold point at ``h`` (fixed) by Newton on its defining system in ``(x0, v0,
    sigma)`` from ``z0``: ``(sigma, max |G|)``, or ``None``."""
    G, J = prob.system_for("fold"), prob.jacobian_for("fold")
    z = np.array(z0, dtype=float)
    z[3] = h
    for _ in range(12):
        g = G(z)
        if np.max(np.abs(g)) <= tol:
            return float(z[2]), float(np.max(np.abs(g)))
        z[:3] -= np.linalg.solve(J(z)[:, :3], g)
    return None


def forced_agreement(prob: DrivenProblem, kbm_z: np.ndarray, auto_pts: np.ndarray,
                     n: int = 16) -> tuple[float, int, int]:
    """The largest ``|sigma_AUTO - sigma_kbm|`` at equal ``h`` over ``n`` of AUTO's points
    (every point of the fold curve but within 0.01 of the cusp's h, where the fold curve's
    two sides meet), kbm's fold solved at each ``h`` from its nearest curve point; with the
    count compared and the count where kbm's Newton failed."""
    h_c = float(np.min(auto_pts[:, 1]))
    keep = auto_pts[auto_pts[:, 1] > h_c + 0.01]
    pick = keep[np.linspace(0, len(keep) - 1, min(n, len(keep))).round().astype(int)]
    worst, fails = 0.0, 0
    for s, h in pick:
        near = kbm_z[np.argmin(np.hypot(kbm_z[:, 2] - s, kbm_z[:, 3] - h))]
        got = fold_sigma_at(prob, near, h)
        if got is None:
            fails += 1
            continue
        worst = max(worst, abs(got[0] - s))
    return worst, len(pick), fails


def delta_at(kit, loop0, beta: float, guess: float, tol: float = 1e-10, axis: int = 0):
    """kbm's connection at ``beta`` (fixed): the secant method on the manifolds' gap in
    Delta from ``guess``, the loop's saddles followed; ``(Delta, |gap|)`` or ``None``.  With
    ``axis = 1`` the roles swap: ``beta`` at the Delta given."""
    from numerics.bifurcation import connections as C

    loop = C.Loop(loop0.x_from, loop0.x_to, loop0.leave, loop0.arrive)
    d = C.gap_function(kit, loop)

    def gap(v):
        return float(d((v, beta) if axis == 0 else (beta, v))[0])
    a0, a1 = guess, guess + 1e-6
    g0 = gap(a0)
    for _ in range(30):
        g1 = gap(a1)
        if abs(g1) <= tol:
            return a1, abs(g1)
        a0, a1, g0 = a1, a1 - g1 * (a1 - a0) / (g1 - g0), g1
    return None


def beta_gap_at_end(k: dict, auto_pts: np.ndarray) -> str:
    """AUTO's last point's ``beta`` less kbm's connection at its ``Delta``: near the fold
    line the curve is nearly level in beta, so the distance in Delta at equal beta
    magnifies the one across the curve."""
    a, b = auto_pts[-1]
    kz = k["z"][np.argsort(k["z"][:, 0])]
    got = delta_at(k["kit"], k["loop0"], a, float(np.interp(a, kz[:, 0], kz[:, 1])), axis=1)
    return "?" if got is None else f"{b - got[0]:+.1e} in beta at its last Delta {a:.4f}"


def sedf_agreement(k: dict, auto_pts: np.ndarray, n: int = 10) -> tuple[list, int]:
    """``[(beta, Delta_AUTO - Delta_kbm)]`` at ``n`` of AUTO's points inside kbm's range of
    beta (kbm's Delta solved at AUTO's beta, from its own path interpolated), and the count
    where the secant failed."""
    kz = k["z"][np.argsort(k["z"][:, 1])]
    inside = auto_pts[(auto_pts[:, 1] >= kz[0, 1]) & (auto_pts[:, 1] <= kz[-1, 1])]
    pick = inside[np.linspace(0, len(inside) - 1, min(n, len(inside))).round().astype(int)]
    out, fails = [], 0
    for a, b in pick:
        got = delta_at(k["kit"], k["loop0"], b, float(np.interp(b, kz[:, 1], kz[:, 0])))
        if got is None:
            fails += 1
            continue
        out.append((float(b), float(a - got[0])))
    return out, fails


def edge_sigma_at(prob, z0: np.ndarray, c: float, tol: float = 1e-10):
    """kbm's tongue edge at ``c`` (fixed): Newton on the fold system in every unknown but
    ``c`` from ``z0``; ``(sigma, max |G|)`` or ``None``."""
    z = np.array(z0, dtype=float)
    z[-1] = c
    for _ in range(12):
        g = prob.G(z)
        if np.max(np.abs(g)) <= tol:
            return float(z[-2]), float(np.max(np.abs(g)))
        z[:-1] -= np.linalg.solve(prob.J(z)[:, :-1], g)
    return None


def coupled_agreement(k: dict, auto_pts: np.ndarray, n: int = 12) -> tuple[float, int, int]:
    """The largest ``|sigma_AUTO - sigma_kbm|`` at equal ``c`` over ``n`` of AUTO's points,
    kbm's edge solved at each ``c`` from its nearest curve point (its own bordered test)."""
    pick = auto_pts[np.linspace(0, len(auto_pts) - 1, min(n, len(auto_pts))).round()
                    .astype(int)]
    worst, fails = 0.0, 0
    for s, c in pick:
        best = None
        for task in k["tasks"]:
            z = joined(task.paths)
            i = int(np.argmin(np.hypot(z[:, -2] - s, z[:, -1] - c)))
            d = float(np.hypot(z[i, -2] - s, z[i, -1] - c))
            if best is None or d < best[0]:
                best = (d, task.problem, z[i])
        got = edge_sigma_at(best[1], best[2], c)
        if got is None:
            fails += 1
            continue
        worst = max(worst, abs(got[0] - s))
    return worst, len(pick), fails
